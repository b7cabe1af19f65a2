"""Per-order table of the temperature compensation (the magnetometer
paper's Table 3, computed by lab.studies.orders_study): for polynomial
orders 1-6, the error after correction on held-out temperatures
(leave-one-temperature-out, pysig.tcomp._poly_fit) as RMS, max |error| and
variance, on

* simulated chamber data (pysig.sim._chamber, the magnetometer paper's 0/25/50/70 °C steps,
  several seeds; and a ramp profile), with the conditioning of the magnetometer paper's
  normal equations next to the scaled fit and the measured fixed-point error;
* every recording in ../shared/data that has a temperature column.

    python bench/tcomp_orders.py [--json FILE] [--seeds N] [--data DIR]
"""
import argparse
import json
import time
from pathlib import Path

from lab.studies.orders_study import recordings, simulated

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT.parent / "shared" / "data"


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
    ap.add_argument("--data", default=str(DATA), help="folder of recordings (default ../shared/data)")
    args = ap.parse_args(argv)
    start = time.perf_counter()
    rows = simulated(args.seeds) + recordings(args.data)
    print_table(rows)
    print(f"\n({time.perf_counter() - start:.1f} s)")
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1) + "\n")
        print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
