"""The refinement loop's numbers: refine on data with an undeclared effect (does it name
the effect, by how much does the RMS fall), on clean data (how many seeds
get something added), and on every real recording in ../shared/data (what
it found, RMS before and after).

    python bench/refine_table.py --json bench/results/refine_table.json

Clean data is measured on three generators (the rotating-field synthetic
run of pysig/sim/refine_cases.py, the chamber simulator, the load-cell
simulator), --clean-seeds seeds each; CI runs 20 seeds of the first only.
"""
import argparse
import json
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

from pysig.refine import effects as fx  # noqa: E402
from pysig.io import read_csv  # noqa: E402
from pysig.refine.loop import plateau_reference, refine  # noqa: E402
from pysig.sim.chamber import ChamberParams, simulate as sim_chamber  # noqa: E402
from pysig.sim.loadcell import simulate as sim_loadcell  # noqa: E402
from pysig.sim.refine_cases import chamber_run, fit_data, loadcell_creep_run  # noqa: E402

DATA = os.path.join(HERE, "..", "..", "shared", "data")
LOADS = ((0.0, 0.0), (20.0, 5.0), (80.0, 10.0), (150.0, 20.0), (220.0, 10.0),
         (300.0, 0.0), (360.0, 15.0), (420.0, 2.0))
CH = dict(sample_rate_hz=0.2, noise_lsb=2.0, profile="ramp", ramp_cycles=2)


def injected_cases():
    """(label, injected, FitData) for each effect, on the simulators where they
    can show it and on the rotating-field synthetic run otherwise."""
    def ch(**kw):
        r = sim_chamber(ChamberParams(**{**CH, **kw}))
        return fx.FitData(y=r["x"], t=r["t"], T=r["temp"], r=r["ref_x"])

    def lc(**kw):
        r = sim_loadcell(seed=kw.pop("seed", 0), duration_s=480.0, load_steps=LOADS,
                         noise_uv_rms=0.05, **kw)
        return fx.FitData(y=r["counts"], t=r["t"], r=r["ref_kg"])
    yield "sim_chamber thermal_lag_s=400", "thermal_lag", ch(seed=0, thermal_lag_s=400.0)
    yield "sim_chamber hysteresis 24 LSB", "hysteresis", ch(seed=0, hysteresis_lsb=(24.0,) * 3)
    yield "sim_loadcell creep 0.3 %, 30 s", "creep", lc(creep_frac=0.003, creep_tau_s=30.0)
    yield "sim_loadcell nonlinearity 0.05 % FS", "nonlinearity", lc(nonlinearity_frac_fs=0.0005)
    for eff in ("gain_drift", "cross_axis", "nonlinearity", "thermal_lag", "hysteresis"):
        yield f"synthetic rotating field: {eff}", eff, fit_data(chamber_run(eff, seed=0))
    yield "synthetic: warm-up 8 LSB, tau 300 s after power-on", "warm_up", fit_data(chamber_run("warm_up", seed=0))
    yield "synthetic: thermal_lag + hysteresis", "thermal_lag+hysteresis", \
        fit_data(chamber_run(("thermal_lag", "hysteresis"), seed=0))
    # a lag and a hysteresis on the simulator's constant-rate ramp imitate each
    # other; the simulator's branch follows the chamber, not the lagged die
    yield "sim_chamber thermal_lag_s=400 + hysteresis 24 LSB", "thermal_lag+hysteresis", \
        ch(seed=0, thermal_lag_s=400.0, hysteresis_lsb=(24.0,) * 3)
    for seed, loads in ((0, (0.0, 50.0, 0.0, 50.0)), (1, (0.0, 30.0, 0.0, 45.0))):
        r = loadcell_creep_run(seed=seed, loads=loads, hold_s=1200.0 if seed == 0 else 900.0)
        yield (f"HX711-like creep 0.04 %, 300 s, noise 25, 0.2 % impulses 2k-20k, loads {loads}",
               "creep", fx.FitData(y=r["counts"], t=r["t"], r=r["ref_kg"]))
    r = sim_chamber(ChamberParams(seed=0, sample_rate_hz=0.5, temp_noise_c=0.15, noise_lsb=1.0,
                                  profile="ramp", thermal_lag_s=300.0))
    yield "sim_chamber thermal_lag_s=300, temperature noise 0.15 °C every 2 s", "thermal_lag", \
        fx.FitData(y=r["x"], t=r["t"], T=r["temp"], r=r["ref_x"])
    yield "synthetic: step in time (outside library)", "(none: step)", fit_data(chamber_run("step", seed=0))
    yield "sim_loadcell zero random walk (outside library)", "(none: drift)", lc(seed=3, drift_rw_uv=0.05)


def clean_cases():
    """(label, seed -> FitData) for clean runs: no effect the base model lacks."""
    def ch(seed):
        r = sim_chamber(ChamberParams(**{**CH, "seed": seed}))
        return fx.FitData(y=r["x"], t=r["t"], T=r["temp"], r=r["ref_x"])

    def lc(seed):
        r = sim_loadcell(seed=seed, duration_s=480.0, load_steps=LOADS, noise_uv_rms=0.05)
        return fx.FitData(y=r["counts"], t=r["t"], r=r["ref_kg"])
    yield "synthetic rotating field (seeds 100..)", lambda s: fit_data(chamber_run(None, seed=100 + s))
    yield "sim_chamber ramp, constant field", ch
    yield "sim_loadcell steps", lc

    def noisy_t(seed):
        r = sim_chamber(ChamberParams(seed=seed, sample_rate_hz=0.5, temp_noise_c=0.15, noise_lsb=1.0,
                                      profile="ramp"))
        return fx.FitData(y=r["x"], t=r["t"], T=r["temp"], r=r["ref_x"])
    yield "sim_chamber ramp, temperature noise 0.15 °C every 2 s, noise 1 LSB", noisy_t


def real_cases(DATA=DATA):
    hx = os.path.join(DATA, "hx711_steps_10hz", "hx711_steps_10hz.csv")
    if os.path.exists(hx):
        d = read_csv(hx, ["t_s", "lc1_counts", "lc2_counts"])
        for col in ("lc1_counts", "lc2_counts"):
            r, mask, n_p = plateau_reference(d[col], d["t_s"])
            yield f"hx711 {col} (plateau reference, {n_p} levels)", fx.FitData(
                y=d[col], t=d["t_s"], r=r, mask=mask, ref_from_y=True)
    mpu = os.path.join(DATA, "mpu6000_gyro_offset_vs_temp", "mpu6000_sn102_gyro_offset.csv")
    if os.path.exists(mpu):
        d = read_csv(mpu, ["temp_c", "gyro_x", "gyro_y", "gyro_z"])
        for col in ("gyro_x", "gyro_y", "gyro_z"):
            yield f"mpu6000 {col} (constant field, rows = temperature bins)", fx.FitData(
                y=d[col], t=np.arange(d[col].size, dtype=float), T=d["temp_c"])
    cold = os.path.join(DATA, "bmi270_two_temps", "bmi270_cold.csv")
    hot = os.path.join(DATA, "bmi270_two_temps", "bmi270_hot.csv")
    if os.path.exists(cold) and os.path.exists(hot):
        cols = ["temp_c", "gyro_x_dps", "gyro_y_dps", "gyro_z_dps"]
        a, b = read_csv(cold, cols), read_csv(hot, cols)
        for col in cols[1:]:
            y = np.concatenate([a[col], b[col]])
            yield f"bmi270 {col} (cold + hot files joined)", fx.FitData(
                y=y, t=np.arange(y.size, dtype=float), T=np.concatenate([a["temp_c"], b["temp_c"]]),
                segments=(0, a[col].size))


def row(label, res, injected=None, seconds=0.0):
    rep = res.report()
    u = rep["unexplained"]
    b, a = rep["before"], rep["after"]
    return {"case": label, "injected": injected,
            "found": [s["effect"] if s["effect"] != "offset_shape" else f"offset_shape: {rep['final_offset']}"
                      for s in rep["steps"]],
            "impulses": rep["impulses"]["count"],
            "robust_rms": [b["rms"], a["rms"]], "plain_rms": [b["plain_rms"], a["plain_rms"]],
            "averaged_rms": [b["averaged_rms"], a["averaged_rms"]],
            "systematic_rms": [b["systematic_rms"], a["systematic_rms"]],
            "report_s": rep["report_s"],
            "not_claimed": sorted({r["effect"] for r in rep["not_claimed"]}),
            "params": [{k: v for k, v in s["params"].items() if k != "coefficients"} for s in rep["steps"]],
            "base_rms": rep["base_rms"], "final_rms": rep["final_rms"],
            "ratio": rep["base_rms"] / rep["final_rms"],
            "base_cv_rms": rep["base_cv_rms"], "final_cv_rms": rep["final_cv_rms"],
            "unexplained": u["unexplained"], "ljung_box_p": u["ljung_box_p"],
            "acf_lag1": u["acf_lag1"], "time_blocks_r2": u["time_blocks_r2"],
            "seen": u.get("seen", ""), "seconds": seconds}


def fmt(r):
    found = ", ".join(r["found"]) or "nothing"
    rb, pb, ab = r["robust_rms"], r["plain_rms"], r["averaged_rms"]
    return (f"| {r['case']} | {r['injected'] or '-'} | {found} | {r['impulses']} | "
            f"{rb[0]:.4g} -> {rb[1]:.4g} | {pb[0]:.4g} -> {pb[1]:.4g} | {ab[0]:.4g} -> {ab[1]:.4g} | "
            f"{rb[0] / rb[1]:.2f}x | {'yes' if r['unexplained'] else 'no'} |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", help="write the rows as JSON")
    ap.add_argument("--clean-seeds", type=int, default=20)
    ap.add_argument("--skip-injected", action="store_true")
    ap.add_argument("--data", default=DATA, help="the shared recordings (default ../shared/data)")
    args = ap.parse_args(argv)
    out = {"injected": [], "clean": {}, "real": []}
    head = ("| case | injected | refine added | impulses | robust RMS | plain RMS | RMS of 10-s reading | "
            "ratio (robust) | unexplained |\n|---|---|---|---|---|---|---|---|---|")
    if not args.skip_injected:
        print(head)
        for label, inj, data in injected_cases():
            t0 = time.perf_counter()
            res = refine(data)
            r = row(label, res, inj, time.perf_counter() - t0)
            out["injected"].append(r)
            print(fmt(r), flush=True)
        print()
        for label, make in clean_cases():
            added = []
            t0 = time.perf_counter()
            for seed in range(args.clean_seeds):
                added.append([s.effect for s in refine(make(seed)).steps])
            n_clean = sum(1 for a in added if not a)
            out["clean"][label] = {"seeds": args.clean_seeds, "nothing_added": n_clean, "added": added,
                                   "seconds": time.perf_counter() - t0}
            print(f"clean, {label}: nothing added in {n_clean} of {args.clean_seeds} seeds", flush=True)
        print()
    print(head)
    for label, data in real_cases(args.data):
        t0 = time.perf_counter()
        res = refine(data)
        r = row(label, res, None, time.perf_counter() - t0)
        out["real"].append(r)
        print(fmt(r), flush=True)
        if r["seen"]:
            print(f"|   | | unexplained: {r['seen']} | | | | |")
    if args.json:
        os.makedirs(os.path.dirname(os.path.abspath(args.json)), exist_ok=True)
        from pysig.io import atomic_output
        with atomic_output(args.json) as fh:
            json.dump(out, fh, indent=2, default=float)
            fh.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
