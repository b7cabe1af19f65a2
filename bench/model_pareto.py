"""Error against cost of drift models: polynomial orders 1-8 and
piecewise-linear tables, side by side, on a real drift curve and on the
project's simulated chamber.

    python bench/model_pareto.py --json pareto.json --plot figs/

For each dataset, axis, family and size: cv_rms (blocked cross-validation
over temperature), fit_rms (the deployed fixed-point model as the C computes
it), data_bytes, and on the MSP430F5510 simulator text_bytes, cycles and
energy_uj; the columns are defined in lab.studies.pareto (rows) and
lab.mcu.model_cost (MSP430 figures).  Every MCU result is read back from
the simulator and compared with the host C bit for bit; a mismatch stops the
bench.

Family "pwl2" (with --port-tables): tables whose knots are a power of two
temperature units apart (the grid starts at the data's first temperature and
ends at or before its last one; beyond the last knot the table is flat), the
layout the MSP430 assembly lookup of csrc/port/msp430/sig_pwl_msp430.S
indexes with one product: cycles of sig_pwl_eval_axes_msp430 (the three axes
of one image per call) divided by 3, checked bit for bit against the host C
sig_pwl_eval_q16.  Its entries are stored with at most 4 fraction bits (1/16
LSB: value_frac 4 needs no output shift; the extra rounding is below 1/32
LSB).  Its size is the grid's own knot count (the requested count rounded up
to the next power-of-two spacing).

Datasets: the MPU-6000 gyro offset curve of ../shared/data (MatrixPilot,
GPL: read from there, never bundled) and pysig.sim._chamber's default run
(the magnetometer paper's 0/25/50/70 °C steps) averaged into 0.25 °C bins."""
from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

from pysig.errors import PysigError
from pysig.io import atomic_output
from lab.mcu import model_cost
from lab.mcu import runner
from lab.mcu.runner import McuError
from pysig.tcomp._cross_validation import DEFAULT_BLOCKS, PAPER_ORDER
from lab.studies.pareto import (POLY_ORDERS, PWL_KNOTS, cheapest_within, datasets, model_name,
                                pareto_front, run_dataset, summarise)

ROOT = Path(__file__).resolve().parent.parent
SHARED_DATA = Path(os.environ.get("PYSIG_SHARED_DATA", ROOT.parent / "shared" / "data"))  # a worktree elsewhere
MPU_CSV = SHARED_DATA / "mpu6000_gyro_offset_vs_temp" / "mpu6000_sn102_gyro_offset.csv"
PAPER_CLAIM = ("Magnetometer paper (4 chamber temperatures, its Tables 2-3):\n"
               "order 2 is the best error/cost trade-off")


def print_table(rows):
    hdr = (f"{'dataset':8} {'axis':7} {'family':6} {'size':>4} {'cv_rms':>9} {'fit_rms':>9} "
           f"{'data_B':>6} {'text_B':>6} {'cycles':>8} {'energy_uJ':>9} {'avr_cyc':>8} {'avr_B':>6}")
    print(hdr)
    print("-" * len(hdr))
    for r in rows:
        cyc = "-" if r["cycles"] is None else f"{r['cycles']:8.1f}"
        en = "-" if r["energy_uj"] is None else f"{r['energy_uj']:9.3f}"
        tb = "-" if r["text_bytes"] is None else str(r["text_bytes"])
        acyc = "-" if r.get("avr_cycles") is None else f"{r['avr_cycles']:8.1f}"
        ab = "-" if r.get("avr_text_bytes") is None else str(r["avr_text_bytes"])
        print(f"{r['dataset']:8} {r['axis']:7} {r['family']:6} {r['size']:4d} {r['cv_rms']:9.3f} "
              f"{r['fit_rms']:9.3f} {r['data_bytes']:6d} {tb:>6} {cyc:>8} {en:>9} {acyc:>8} {ab:>6}")


def print_summary(summary):
    for s in summary:
        print(f"\n{s['dataset']}: {s['n_temperatures']} temperatures, "
              f"{s['temp_range_c'][0]:.2f}..{s['temp_range_c'][1]:.2f} °C; " + "; ".join(s["notes"]))
        for axis, a in s["axes"].items():
            fp = a["four_point"]
            o = {r["order"]: r for r in fp["orders"]}
            print(f"  {axis}: blocked CV picks poly order {a['cv_choice_poly']}, table of "
                  f"{a['cv_choice_pwl']} knots; paper's order 2 cv_rms {a['paper_order_cv_rms']:.2f}; "
                  f"four points ({fp['mode']}) at " + ", ".join(f"{t:.2f}" for t in fp["temps_c"])
                  + f" °C choose order {fp['loo_choice']} (leave-one-out); dense-curve RMS "
                  + ", ".join(f"order {k} {o[k]['dense_rms']:.2f}" for k in o))
            if "cheapest_within_5pct" in a:
                c = a["cheapest_within_5pct"]
                print(f"    cheapest model within 5 % of the best CV: {c['family']} {c['size']} "
                      f"(cv_rms {c['cv_rms']:.2f}, {c['cycles']:.0f} cycles)")
            if "pareto_front" in a:
                print("    Pareto front (cycles, cv_rms): "
                      + ", ".join(f"{f} {n}" for f, n in a["pareto_front"]))
            print("    Pareto front (data bytes, cv_rms): "
                  + ", ".join(f"{f} {n}" for f, n in a["pareto_front_bytes"]))


# -------------------------------------------------------------------- plot --
def plot(rows, summary, directory):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    written = []
    for s in summary:
        name = s["dataset"]
        mine = [r for r in rows if r["dataset"] == name]
        axes = list(s["axes"])
        fig, subs = plt.subplots(2, len(axes), figsize=(5.2 * len(axes), 8.4), squeeze=False)
        for col, axis in enumerate(axes):
            rs = [r for r in mine if r["axis"] == axis]
            fp = {o["order"]: o for o in s["axes"][axis]["four_point"]["orders"]}
            for row, cost, label in ((0, "cycles", "MSP430F5510 cycles per call (mspdebug sim)"),
                                     (1, "data_bytes", "model bytes per axis (coefficients / table)")):
                ax = subs[row][col]
                for fam, mk, colr, lab in (
                        ("poly", "o", "tab:blue", "polynomial (order), portable C"),
                        ("pwl", "s", "tab:orange", "table (knots), portable C"),
                        ("pwl2", "^", "tab:green", "table, power-of-two knots (knots), "
                                                   "port assembly, 3 axes per call")):
                    fr = [r for r in rs if r["family"] == fam]
                    if not fr:
                        continue
                    ax.scatter([r[cost] for r in fr], [r["cv_rms"] for r in fr], marker=mk, c=colr,
                               label=lab, zorder=3)
                    for r in fr:
                        ax.annotate(str(r["size"]), (r[cost], r["cv_rms"]), fontsize=7,
                                    xytext=(3, 3), textcoords="offset points")
                front = pareto_front(rs, cost)
                ax.step([r[cost] for r in front], [r["cv_rms"] for r in front], "k--", lw=1,
                        where="post", label="Pareto front", zorder=2)
                paper = next(r for r in rs if r["family"] == "poly" and r["size"] == PAPER_ORDER)
                ax.scatter([paper[cost]], [paper["cv_rms"]], s=180, facecolors="none",
                           edgecolors="red", lw=1.5, label="paper's pick: order 2", zorder=4)
                ax.axhline(fp[PAPER_ORDER]["dense_rms"], color="red", lw=0.8, ls=":",
                           label="order 2 fitted on the 4 paper points: RMS on the dense curve")
                loo = s["axes"][axis]["four_point"]["loo_choice"]
                if loo != PAPER_ORDER:
                    ax.axhline(fp[loo]["dense_rms"], color="purple", lw=0.8, ls="-.",
                               label=f"order {loo}, chosen by the 4 points' own leave-one-out: "
                                     f"dense RMS")
                ax.set_xscale("log")
                ax.set_yscale("log")
                ax.xaxis.set_minor_formatter(NullFormatter())
                ax.set_xlabel(label)
                ax.set_ylabel(f"blocked-CV RMS [{rs[0]['unit']}]")
                ax.set_title(f"{name}: {axis}")
                ax.grid(True, which="both", alpha=0.3)
        subs[0][0].legend(fontsize=7, loc="best")
        fig.text(0.99, 0.01, PAPER_CLAIM, ha="right", va="bottom", fontsize=8,
                 bbox=dict(boxstyle="round", fc="lightyellow", ec="grey"))
        here = []
        for axis in axes:
            rs = [r for r in mine if r["axis"] == axis]
            p2 = next(r for r in rs if r["family"] == "poly" and r["size"] == PAPER_ORDER)
            best = min(rs, key=lambda r: r["cv_rms"])
            cheap = cheapest_within(rs)
            here.append(f"{axis}: order 2 {p2['cv_rms']:.3g} at {p2['cycles']:.0f} cycles; best "
                        f"{model_name(best)} {best['cv_rms']:.3g} at {best['cycles']:.0f}; "
                        f"cheapest within 5 %: {model_name(cheap)} {cheap['cv_rms']:.3g} at "
                        f"{cheap['cycles']:.0f}")
        fig.text(0.01, 0.01, "Measured here (blocked-CV RMS):\n" + "\n".join(here), ha="left",
                 va="bottom", fontsize=8, bbox=dict(boxstyle="round", fc="white", ec="grey"))
        fig.tight_layout(rect=(0, 0.08, 1, 1))
        path = directory / f"pareto_{name}.png"
        with atomic_output(path, "wb") as fh:
            fig.savefig(fh, format="png", dpi=110)
        plt.close(fig)
        written.append(str(path))
    return written


def int_list(text):
    return tuple(int(v) for v in text.split(",") if v)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", help="write rows and summary as JSON here")
    ap.add_argument("--plot", help="write pareto_<dataset>.png into this directory")
    ap.add_argument("--datasets", default="mpu6000,chamber",
                    help="comma-separated: mpu6000 (real curve), chamber (simulated)")
    ap.add_argument("--mpu-csv", default=str(MPU_CSV),
                    help="the MPU-6000 gyro offset recording (default: ../shared/data's)")
    ap.add_argument("--blocks", type=int, default=DEFAULT_BLOCKS,
                    help=f"temperature blocks of the cross-validation (default {DEFAULT_BLOCKS}; "
                         f"the two end blocks are never held out)")
    ap.add_argument("--orders", type=int_list, default=POLY_ORDERS,
                    help="polynomial orders, comma-separated (default 1-8)")
    ap.add_argument("--knots", type=int_list, default=PWL_KNOTS,
                    help="table sizes, comma-separated (default " + ",".join(map(str, PWL_KNOTS)) + ")")
    ap.add_argument("--port-tables", action="store_true",
                    help="add the power-of-two tables on the MSP430 assembly lookup (family pwl2)")
    ap.add_argument("--no-mcu", action="store_true",
                    help="skip the MSP430 builds (cycles, text bytes, energy left empty)")
    ap.add_argument("--no-avr", action="store_true",
                    help="skip the ATmega328P builds (avr_* columns left empty)")
    args = ap.parse_args(argv)
    if args.plot and args.no_mcu:
        ap.error("--plot needs the MCU cycles (drop --no-mcu)")
    rows, summary = [], []
    try:
        for name, (curve, unit) in datasets(args.datasets.split(","), args.mpu_csv).items():
            print(f"{name}: fitting, cross-validating and measuring ...", file=sys.stderr)
            r = run_dataset(name, curve, unit, mcu=not args.no_mcu, n_blocks=args.blocks,
                            poly_orders=args.orders, pwl_knots=args.knots,
                            port_tables=args.port_tables, avr=not args.no_avr,
                            log=lambda m: print(m, file=sys.stderr))
            rows += r
            summary.append(summarise(name, curve, r))
    except (PysigError, McuError) as exc:
        raise SystemExit(str(exc)) from None
    print_table(rows)
    print_summary(summary)
    if args.plot:
        for p in plot(rows, summary, args.plot):
            print(f"wrote {p}")
    if args.json:
        doc = {"description": __doc__, "mcu": {"target": "MSP430F5510", "mclk_hz": model_cost.MCLK_HZ,
                                                "supply_a": model_cost.SUPPLY_A,
                                                "supply_v": model_cost.SUPPLY_V,
                                                "timing": "mspdebug 0.22 sim, classic MSP430 table",
                                                "multiplier": "16x16 MPY helpers (-mhwmult=f5series)",
                                                "temps_per_call_mean": model_cost.N_TEMPS},
               "avr": None if args.no_avr else {
                   "target": "ATmega328P", "f_cpu_hz": runner.AVR_F_CPU,
                   "timing": "simavr 1.6; the harness's Timer 1 at clk/1 (bench/mcu/avr/bench_avr.h)",
                   "compiler": "gcc-avr 5.4 -Os, avr-libc 2.0"},
               "cv": {"blocks": args.blocks, "held_out": "interior blocks"},
               "rows": rows, "summary": summary}
        with atomic_output(args.json) as fh:
            json.dump(doc, fh, indent=1)
        print(f"wrote {args.json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
