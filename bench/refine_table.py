"""How well refine finds what it was not told: refine on data with an
undeclared effect (does it name the effect, by how much does the RMS fall),
on clean data (how many seeds get something added), and on every real
recording in ../shared/data (what it found, RMS before and after).  The
cases are lab.studies.refine_study; this script runs, prints and writes them.

    python bench/refine_table.py --json bench/results/refine_table.json

Clean data is measured on three generators (the rotating-field synthetic
run of bench/lab/studies/refine_cases.py, the chamber simulator, the load-cell
simulator), --clean-seeds seeds each; CI runs 20 seeds of the first only.

Overlapping effects (bench/lab/studies/overlap_cases.py): lag + drift,
hysteresis + drift, warm-up + lag, a drift alone and clean records at two
noise levels, two sample rates, two record lengths and two units, and
records built like two real bench logs (a resistor on a stepped plate, an
instrument carried between cold and warm places); each judged by the
physical effects named, each parameter within +-50 %, and the blocked-CV
error cut; the same kinds once more off the grid (held out: noise 1 LSB,
every 5 s, 8 h, seeds 3 and 11, both units); imperfect versions of the
two real-like records (coloured noise, a room cycle, quantised readings and
temperatures, a two-pole lag, a spread of hysteresis widths, an irregular
drift, structure no candidate explains) with controls that lack the
physical effect (nothing physical may be claimed there).

Imperfect records (bench/lab/studies/imperfect_cases.py): no physical
effect, only the static offset (and a random-walk or 1/f zero in some), but
AR(1) noise, a quantised reading and temperature, a room cycle, gaps between
sessions and jittered times, on three temperature profiles and two units;
counted by the records on which any effect is named (a false claim).  The
same imperfections with a real thermal lag or hysteresis check that power
is kept.  Run with OPENBLAS_NUM_THREADS=1 on a shared machine (many small
least-squares fits: threads only contend).
"""
import argparse
import json
import os
import sys
import time

from pysig.io import atomic_output
from pysig.refine import refine
from lab.studies.refine_study import clean_cases, injected_cases, real_cases, row
from lab.studies.overlap_cases import (HELD_OUT, KINDS, grid_cases, held_out_cases, real_like_imperfect_cases, judge_case,
                                      options_for, real_like_cases)
from lab.studies.imperfect_cases import imperfect_clean_cases, imperfect_effect_cases

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "shared", "data")


def fmt(r):
    found = ", ".join(r["found"]) or "nothing"
    rb, pb, ab = r["robust_rms"], r["plain_rms"], r["averaged_rms"]
    return (f"| {r['case']} | {r['injected'] or '-'} | {found} | {r['impulses']} | "
            f"{rb[0]:.4g} -> {rb[1]:.4g} | {pb[0]:.4g} -> {pb[1]:.4g} | {ab[0]:.4g} -> {ab[1]:.4g} | "
            f"{rb[0] / rb[1]:.2f}x | {'yes' if r['unexplained'] else 'no'} |")


def overlap_row(label, truth, res, seconds):
    j = judge_case(truth, res)
    return {"case": label, **j, "seconds": seconds}


def fmt_overlap(r):
    params = ", ".join(f"{k} {r['params'][k]:.4g} (true {v:.4g})" for k, v in r["truth"].items()
                       if k in r["params"]) or "-"
    shares = ", ".join(f"{k} {100 * v:.0f} %" for k, v in r["shares"].items()) or "-"
    ok = all(r["params_within_50pct"].values())
    return (f"| {r['case']} | {', '.join(r['expected']) or '-'} | {', '.join(r['found']) or 'nothing'} | "
            f"{'yes' if r['named_right'] else 'NO'} | {params} | {'yes' if ok else 'NO'} | "
            f"{'yes' if r['drift_reported'] else 'no'} | {r['cv_cut']:.2f}x | {shares} |")


def overlap_summary(rows, kind_end=","):
    """Counts by kind of case (the part of the label before the first
    `kind_end`)."""
    out = {}
    for r in rows:
        kind = r["case"].split(kind_end)[0]
        k = out.setdefault(kind, {"cases": 0, "named_right": 0, "params_within_50pct": 0, "drift_reported": 0,
                                  "cv_cut_min": float("inf"), "cv_cut_median": None, "_cuts": []})
        k["cases"] += 1
        k["named_right"] += r["named_right"]
        k["params_within_50pct"] += all(r["params_within_50pct"].values())
        k["drift_reported"] += r["drift_reported"]
        k["_cuts"].append(r["cv_cut"])
    for k in out.values():
        cuts = sorted(k.pop("_cuts"))
        k["cv_cut_min"], k["cv_cut_median"] = cuts[0], cuts[len(cuts) // 2]
    return out


def imperfect_summary(rows):
    """Per imperfection (the label's part after "imperfect: "): cases, and
    those where a physical effect was named, the drift, an offset shape."""
    out = {}
    for r in rows:
        kind = r["case"].split("imperfect: ")[1].split(",")[0]
        k = out.setdefault(kind, {"cases": 0, "effect_named": 0, "drift": 0})
        k["cases"] += 1
        k["effect_named"] += bool(r["found"])
        k["drift"] += r["drift_reported"]
    return out


def run_imperfect(out, clean_seeds, effect_seeds):
    """The imperfect records: no effect (false claims counted), then with one."""
    for key, cases in (("imperfect_clean", imperfect_clean_cases(range(clean_seeds))),
                       ("imperfect_effect", imperfect_effect_cases(range(effect_seeds)))):
        print("| case | in the record | refine named | right | parameter (true) | within 50 % | drift line | "
              "CV cut | share of systematic removed |\n|---|---|---|---|---|---|---|---|---|")
        for label, truth, data in cases:
            t0 = time.perf_counter()
            r = overlap_row(label, truth, refine(data), time.perf_counter() - t0)
            out[key].append(r)
            print(fmt_overlap(r), flush=True)
        print()
    out["imperfect_clean_summary"] = imperfect_summary(out["imperfect_clean"])
    for kind, k in out["imperfect_clean_summary"].items():
        print(f"  no effect, {kind}: an effect named on {k['effect_named']} of {k['cases']} "
              f"(drift line on {k['drift']})")
    found = sum(r["named_right"] for r in out["imperfect_effect"])
    print(f"  with a lag or a hysteresis: named right on {found} of {len(out['imperfect_effect'])}")
    print()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", help="write the rows as JSON")
    ap.add_argument("--clean-seeds", type=int, default=20)
    ap.add_argument("--skip-injected", action="store_true")
    ap.add_argument("--data", default=DATA, help="the shared recordings (default ../shared/data)")
    ap.add_argument("--skip-overlap", action="store_true")
    ap.add_argument("--overlap-seeds", type=int, default=1, help="seeds of each overlapping-effect grid case")
    ap.add_argument("--real-like-seeds", type=int, default=3)
    ap.add_argument("--real-like-imperfect-seeds", type=int, default=8,
                    help="seeds of the imperfect real-like records and of their controls (0: skip)")
    ap.add_argument("--skip-held-out", action="store_true",
                    help="skip the overlapping-effect cases at a noise, rate, length and seeds off the grid")
    ap.add_argument("--held-out-seeds", type=int, nargs="+", default=list(HELD_OUT["seeds"]),
                    help="seeds of the held-out cases (the bench's are %(default)s)")
    ap.add_argument("--held-out-kinds", nargs="+", default=list(KINDS), choices=KINDS,
                    help="kinds of held-out case to run (all by default)")
    ap.add_argument("--imperfect-seeds", type=int, default=10,
                    help="seeds of each imperfection of the no-effect imperfect records (0: skip)")
    ap.add_argument("--imperfect-effect-seeds", type=int, default=3,
                    help="seeds of each effect under all imperfections")
    args = ap.parse_args(argv)
    out = {"injected": [], "clean": {}, "real": [], "overlap": [], "real_like": [], "held_out": [],
           "imperfect_clean": [], "imperfect_effect": [], "real_like_imperfect": []}
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
    if not args.skip_overlap:
        ohead = ("| case | in the record | refine named | right | parameter (true) | within 50 % | drift line | "
                 "CV cut | share of systematic removed |\n|---|---|---|---|---|---|---|---|---|")
        sets = [("real_like", real_like_cases(tuple(range(args.real_like_seeds)))),
                ("real_like_imperfect", real_like_imperfect_cases(tuple(range(args.real_like_imperfect_seeds)))),
                ("overlap", grid_cases(tuple(range(args.overlap_seeds))))]
        if not args.skip_held_out:
            sets.append(("held_out", held_out_cases(tuple(args.held_out_seeds), tuple(args.held_out_kinds))))
        for key, cases in sets:
            print(ohead)
            for label, truth, data in cases:
                t0 = time.perf_counter()
                res = refine(data, options_for(truth))
                r = overlap_row(label, truth, res, time.perf_counter() - t0)
                out[key].append(r)
                print(fmt_overlap(r), flush=True)
            print()
        out["overlap_summary"] = overlap_summary(out["overlap"] + out["real_like"])
        out["held_out_summary"] = overlap_summary(out["held_out"])
        out["real_like_imperfect_summary"] = overlap_summary(out["real_like_imperfect"], kind_end=":")
        for title, summary in (("grid and real-like", out["overlap_summary"]),
                               ("held out", out["held_out_summary"]),
                               ("real-like, imperfect (controls: no physical effect)",
                                out["real_like_imperfect_summary"])):
            print(title)
            for kind, k in summary.items():
                print(f"  {kind}: named right {k['named_right']}/{k['cases']}, parameters within 50 % "
                      f"{k['params_within_50pct']}/{k['cases']}, drift line {k['drift_reported']}/{k['cases']}, "
                      f"CV cut min {k['cv_cut_min']:.2f}x median {k['cv_cut_median']:.2f}x")
        print()
    if args.imperfect_seeds > 0:
        run_imperfect(out, args.imperfect_seeds, args.imperfect_effect_seeds)
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
        with atomic_output(args.json) as fh:
            json.dump(out, fh, indent=2, default=float)
            fh.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
