"""Model choice on every real temperature curve and the simulated chamber:
`pysig fit --model auto` (pysig.tcomp._calibration.fit_model) per curve, with the
chosen family and size, its blocked-CV RMS, the best CV RMS of any family
and size, the per-axis MCU cost (pysig.tcomp._cost: MSP430F5510 cycles and
data bytes from bench/model_pareto.py), the fixed-point error, and whether
the image -> C loader -> sig_tmodel_apply path equals `apply --fixed`.

    python bench/tcomp_auto.py [--json FILE] [--data DIR]

Curves: each MPU-6000 gyro axis in °C and in raw TEMP_OUT codes, the three
axes together, the BMI270 two-temperature gyro (readings x 100: centi-dps
codes), the chamber simulator's default run (3 axes), and generated curves
far from those (uint16 codes 63000..65000, negative int16 codes, a unit
of 1000 LSB per step)."""
import argparse
import json
import os
from pathlib import Path

import numpy as np

from pysig.io import read_csv
from pysig.tcomp import _cost as cost, _calibration as tmodel
from pysig.tcomp._tempcode import CELSIUS, raw_code


def curves(data):
    mpu = read_csv(data / "mpu6000_gyro_offset_vs_temp" / "mpu6000_sn102_gyro_offset.csv")
    for axis in ("gyro_x", "gyro_y", "gyro_z"):
        yield f"MPU-6000 {axis}, °C", mpu["temp_c"], {axis: mpu[axis]}, CELSIUS, 1.0
        yield f"MPU-6000 {axis}, raw code", mpu["temp_raw"], {axis: mpu[axis]}, \
            raw_code(mpu["temp_raw"], 1 / 340, 36.53), 1.0
    yield "MPU-6000 3 axes, °C", mpu["temp_c"], {a: mpu[a] for a in ("gyro_x", "gyro_y", "gyro_z")}, CELSIUS, 1.0
    folder = data / "bmi270_two_temps"
    parts = [read_csv(folder / f) for f in ("bmi270_cold.csv", "bmi270_hot.csv")]
    bmi = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    yield "BMI270 gyro x,y,z (2 temps)", bmi["temp_c"], \
        {a: bmi[a] for a in ("gyro_x_dps", "gyro_y_dps", "gyro_z_dps")}, CELSIUS, 100.0
    yield from chamber_curve()
    rng = np.random.default_rng(7)
    codes = np.repeat(np.arange(63000, 65001, 5), 2).astype(float)
    y = np.rint(700 * np.sin((codes - 63000) / 2000 * 4) + rng.normal(0, 3, codes.size))
    yield "generated, uint16 codes 63000..65000", codes, {"x": y}, raw_code(codes), 1.0
    codes = np.arange(-30000, -26000, 7).astype(float)
    y = np.rint(-0.004 * (codes + 28000) ** 2 / 100 + rng.normal(0, 1, codes.size))
    yield "generated, int16 codes -30000..-26001", codes, {"x": y}, raw_code(codes), 1.0
    t = np.linspace(-40, 125, 3000)
    y = np.rint(1000 * np.round(3 * np.tanh((t - 40) / 30)) + rng.normal(0, 50, t.size))
    yield "generated, steps of 1000 LSB, -40..125 °C", t, {"x": y}, CELSIUS, 1.0


def chamber_curve():
    import tempfile
    from pysig.cli import main
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "run.csv"
        main(["chamber", "-o", str(path)])
        d = read_csv(path)
    yield "chamber simulator x,y,z (default run)", d["temp"], {a: d[a] for a in "xyz"}, CELSIUS, 1.0


def run_one(name, temp, cols, temp_code, scale):
    r = tmodel.fit_model(temp, cols, temp_code=temp_code, value_scale=scale)
    m, sel = r.model, r.model.report["selection"]
    fixed, _ = tmodel.apply_fixed(m, temp, list(cols.values()))
    flt, _ = tmodel.apply_float(m, temp, list(cols.values()))
    fam, size = sel["chosen"].split(":")
    c = cost.cost(fam, int(size))
    errs = m.error_bound_lsb if m.family == "poly" else m.error_lsb
    return {"curve": name, "axes": list(cols), "chosen": sel["chosen"], "cv_rms": sel["cv_rms"],
            "best": sel["best"], "best_cv_rms": sel["best_cv_rms"],
            "ratio": (sel["cv_rms"] / sel["best_cv_rms"]) if sel["cv_rms"] else None,
            "cycles_per_axis": c.cycles, "bytes_per_axis": c.data_bytes,
            "fixed_error_lsb": max(errs), "warnings": r.warnings,
            "fixed_minus_float_max": float(max(np.max(np.abs(a - b)) for a, b in zip(fixed, flt))),
            "unit": f"reading x {scale:g}" if scale != 1 else "reading LSB"}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json")
    ap.add_argument("--data", default=os.environ.get("PYSIG_SHARED_DATA",
                                                     str(Path(__file__).resolve().parents[2] / "shared" / "data")))
    args = ap.parse_args()
    rows = [run_one(*c) for c in curves(Path(args.data))]
    print(f"{'curve':44} {'chosen':>10} {'CV RMS':>9} {'best':>10} {'best CV':>9} {'ratio':>6} "
          f"{'cyc/ax':>7} {'B/ax':>5} {'fx err':>7}")
    for r in rows:
        cv = f"{r['cv_rms']:9.4g}" if r["cv_rms"] else f"{'no CV':>9}"
        bc = f"{r['best_cv_rms']:9.4g}" if r["best_cv_rms"] else f"{'-':>9}"
        ratio = f"{r['ratio']:6.3f}" if r["ratio"] else f"{'-':>6}"
        print(f"{r['curve']:44} {r['chosen']:>10} {cv} {str(r['best']):>10} {bc} {ratio} "
              f"{r['cycles_per_axis']:7d} {r['bytes_per_axis']:5d} {r['fixed_error_lsb']:7.3g}")
    if args.json:
        Path(args.json).write_text(json.dumps({"description": __doc__, "rows": rows}, indent=2) + "\n")
        print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
