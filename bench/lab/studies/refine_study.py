"""How well refine finds what it was not told: the cases of the refine table
(bench/refine_table.py prints them): data with an undeclared effect, from
the simulators where they can show it and from the rotating-field synthetic
run otherwise; clean data from three generators; every real recording
refine can be run on.  `row` turns a Result into one table row.
"""
import os

import numpy as np

from pysig.io import read_csv
from pysig.sim._chamber import ChamberParams, simulate as sim_chamber
from pysig.sim._loadcell import simulate as sim_loadcell
from lab.studies.refine_cases import chamber_run, fit_data, loadcell_creep_run
from pysig.refine import _effect_models as fx
from pysig.refine._loop import plateau_reference

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


def real_cases(data_dir):
    hx = os.path.join(data_dir, "hx711_steps_10hz", "hx711_steps_10hz.csv")
    if os.path.exists(hx):
        d = read_csv(hx, ["t_s", "lc1_counts", "lc2_counts"])
        for col in ("lc1_counts", "lc2_counts"):
            r, mask, n_p = plateau_reference(d[col], d["t_s"])
            yield f"hx711 {col} (plateau reference, {n_p} levels)", fx.FitData(
                y=d[col], t=d["t_s"], r=r, mask=mask, ref_from_y=True)
    mpu = os.path.join(data_dir, "mpu6000_gyro_offset_vs_temp", "mpu6000_sn102_gyro_offset.csv")
    if os.path.exists(mpu):
        d = read_csv(mpu, ["temp_c", "gyro_x", "gyro_y", "gyro_z"])
        for col in ("gyro_x", "gyro_y", "gyro_z"):
            yield f"mpu6000 {col} (constant field, rows = temperature bins)", fx.FitData(
                y=d[col], t=np.arange(d[col].size, dtype=float), T=d["temp_c"])
    cold = os.path.join(data_dir, "bmi270_two_temps", "bmi270_cold.csv")
    hot = os.path.join(data_dir, "bmi270_two_temps", "bmi270_hot.csv")
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
