"""Per-order study of the temperature compensation (the magnetometer paper's
Table 3): for polynomial orders 1-6, the error after correction on held-out
temperatures (leave-one-temperature-out, pysig.tcomp._poly_fit) as RMS, max
|error| and variance, on the chamber simulator (with the conditioning of the
magnetometer paper's normal equations next to the scaled fit, and the
measured fixed-point error) and on recordings with a temperature column.
bench/tcomp_orders.py prints the rows and writes them as JSON.
"""
from pathlib import Path

import numpy as np

from pysig import lsq
from pysig.errors import PysigError
from pysig.io import read_csv
from pysig.sim import _chamber as sim_chamber
from pysig.tcomp import _tcomp
from pysig.tcomp import _poly_fit as fit

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
    """One row per order of the leave-one-temperature-out CV of a dataset."""
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
    """CV rows of the chamber simulator, steps and ramp profiles, `seeds`
    seeds each (seed 0 with conditioning and fixed-point error), and a
    summary row per profile: the order each seed's CV prefers and selects."""
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


def recordings(data_dir):
    """CV rows (and what the fit says per order) of every recording folder in
    `data_dir` that has a temperature column; a folder without one, or
    without a configuration in RECORDINGS, gets a "skipped" row."""
    data_dir = Path(data_dir)
    out = []
    for folder in sorted(p for p in data_dir.iterdir() if p.is_dir()) if data_dir.is_dir() else []:
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
