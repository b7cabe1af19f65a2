"""Per-order table of the temperature compensation (the
magnetometer paper's Table 3): for polynomial orders 1-6, the error after
correction on held-out temperatures (leave-one-temperature-out, pysig.tcomp.fit)
as RMS, max |error| and variance, on

* simulated chamber data (pysig.sim.chamber, the magnetometer paper's 0/25/50/70 °C steps,
  several seeds; and a ramp profile), with the conditioning of the magnetometer paper's
  normal equations next to the scaled fit and the measured fixed-point error;
* every recording in ../shared/data that has a temperature column.

    python bench/tcomp_orders.py [--json FILE] [--seeds N]
"""
import argparse
import json
import time
from pathlib import Path

import numpy as np

from pysig.tcomp import _tcomp, fit
from pysig import lsq
from pysig.sim import chamber as sim_chamber
from pysig.errors import PysigError
from pysig.io import read_csv

ROOT = Path(__file__).resolve().parent.parent

DATA = ROOT.parent / "shared" / "data"
ORDERS = range(1, 7)
# recordings with a temperature: files, temperature column, reading columns, unit
RECORDINGS = {
    "mpu6000_gyro_offset_vs_temp": (["mpu6000_sn102_gyro_offset.csv"], "temp_c",
                                    ["gyro_x", "gyro_y", "gyro_z"], "table unit, ~1/2099 dps"),
    "bmi270_two_temps": (["bmi270_cold.csv", "bmi270_hot.csv"], "temp_c",
                         ["gyro_x_dps", "gyro_y_dps", "gyro_z_dps"], "dps"),
}


def fixed_point_error(temp, columns, order):
    """Max |delta_fixed - delta_float64| (LSB) over every 0.01 °C step of the
    calibrated range, through the C code."""
    m = fit.fit_tcomp(temp, columns, order=order)
    c = _tcomp.TcompQ.from_fields(**m.fixed_fields())
    t = np.arange(m.scaling.t_lo, m.scaling.t_hi + 1)
    worst = 0.0
    for a in range(len(m.axes)):
        d, _ = c.delta(a, t)
        worst = max(worst, float(np.max(np.abs(d / 2.0 ** m.q[a] - m.delta(t / 100.0, a)))))
    return worst


def cv_rows(dataset, temp, columns, unit, extra=None):
    groups = fit.temperature_groups(temp)
    rows = []
    for r in fit.cross_validate(temp, columns, orders=ORDERS, groups=groups):
        row = {"dataset": dataset, "order": r["order"], "label": r["label"], "unit": unit,
               "temperatures": groups.count}
        if "refused" in r:
            row["refused"] = r["refused"]
        else:
            row.update(rms=r["rms"], max=r["max"], var=r["var"],
                       per_axis=r["per_axis"])
        if extra and r["order"] in extra:
            row.update(extra[r["order"]])
        rows.append(row)
    return rows


def simulated(seeds):
    out = []
    for profile in ("steps", "ramp"):
        per_seed = []
        for seed in range(seeds):
            p = sim_chamber.ChamberParams(seed=seed, profile=profile)
            d = sim_chamber.simulate(p)
            cols = {k: d[k] for k in "xyz"}
            extra = None
            if seed == 0:
                extra = {}
                for order in ORDERS:
                    _, c_normal = lsq.fit_normal_equations(d["temp"], d["x"], order)
                    extra[order] = {"cond_normal_equations": c_normal,
                                    "cond_scaled": lsq.fit_poly(d["temp"], d["x"], order).cond,
                                    "fixed_point_max_err_lsb": fixed_point_error(d["temp"], cols, order)}
            rows = cv_rows(f"sim_{profile}_seed{seed}", d["temp"], cols, "LSB", extra)
            per_seed.append(rows)
            out.extend(rows)
        best = [min((r for r in rows if r["order"] >= 1 and "var" in r), key=lambda r: r["var"])["order"]
                for rows in per_seed]
        chosen = [fit.select_order([{"order": r["order"], "var": r.get("var", 0), **({"refused": 1} if "refused" in r else {})}
                                    for r in rows]) for rows in per_seed]
        mean_var = {o: float(np.mean([r["var"] for rows in per_seed for r in rows if r["order"] == o]))
                    for o in [0, *ORDERS]}
        out.append({"dataset": f"sim_{profile}_summary", "seeds": seeds, "lowest_cv_variance_order": best,
                    "selected_order": chosen, "mean_var": mean_var})
    return out


def recordings():
    out = []
    for folder in sorted(p for p in DATA.iterdir() if p.is_dir()) if DATA.is_dir() else []:
        csvs = sorted(folder.glob("*.csv"))
        header = set()
        for f in csvs:
            header |= set(f.read_text().split("\n", 1)[0].split(","))
        if not any("temp" in h for h in header):
            out.append({"dataset": folder.name, "skipped": "no temperature column"})
            continue
        if folder.name not in RECORDINGS:
            out.append({"dataset": folder.name, "skipped": "has a temperature column but no configuration here"})
            continue
        files, tcol, cols, unit = RECORDINGS[folder.name]
        parts = [read_csv(folder / f, [tcol] + cols) for f in files]
        d = {k: np.concatenate([p[k] for p in parts]) for k in [tcol] + cols}
        rows = cv_rows(folder.name, d[tcol], {k: d[k] for k in cols}, unit)
        # what the fit itself says per order (the refusal names the counts)
        for r in rows:
            if r["order"] == 0:
                continue
            try:
                m = fit.fit_tcomp(d[tcol], {k: d[k] for k in cols}, order=r["order"])
                r["fit"] = "ok"
                r["in_sample_rms"] = {k: m.report["per_axis"][k]["rms"] for k in cols}
                if folder.name == "bmi270_two_temps":
                    r["plateau_bias"] = fit.group_bias_report(m, d[tcol], {k: d[k] for k in cols})
            except PysigError as exc:
                r["fit"] = f"refused: {exc}"
        out.extend(rows)
    return out


def print_table(rows):
    current = None
    for r in rows:
        if "skipped" in r:
            print(f"\n{r['dataset']}: skipped ({r['skipped']})")
            continue
        if "mean_var" in r:
            print(f"  {r['dataset']}: over {r['seeds']} seeds, order with the lowest CV variance: "
                  f"{r['lowest_cv_variance_order']}; selected (smallest within 5 %): {r['selected_order']}")
            print("  mean variance per order: " + ", ".join(f"{o}: {v:.4g}" for o, v in r["mean_var"].items()))
            continue
        if r["dataset"] != current:
            current = r["dataset"]
            print(f"\n{current} ({r['temperatures']} temperature groups, unit {r['unit']})")
            print(f"{'order':>7} {'RMS':>10} {'max':>10} {'variance':>11} {'cond(CᵀC)':>10} {'cond(scaled)':>12} "
                  f"{'fixed err':>9}  fit")
        if "refused" in r:
            line = f"{r['label']:>7}   CV refused: {r['refused']}"
        else:
            line = f"{r['label']:>7} {r['rms']:10.4g} {r['max']:10.4g} {r['var']:11.4g}"
            if "cond_normal_equations" in r:
                line += (f" {r['cond_normal_equations']:10.2g} {r['cond_scaled']:12.3g} "
                         f"{r['fixed_point_max_err_lsb']:9.2g}")
        if "fit" in r:
            line += f"  fit: {r['fit']}"
        print(line)
        for b in r.get("plateau_bias", []):
            print(f"          plateau {b['temp_c']:.2f} °C ({b['samples']} samples): bias before "
                  + ", ".join(f"{v:+.3f}" for v in b["before"].values()) + " -> after "
                  + ", ".join(f"{v:+.3f}" for v in b["after"].values()))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", metavar="FILE")
    ap.add_argument("--seeds", type=int, default=5)
    args = ap.parse_args(argv)
    start = time.perf_counter()
    rows = simulated(args.seeds) + recordings()
    print_table(rows)
    print(f"\n({time.perf_counter() - start:.1f} s)")
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1) + "\n")
        print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
