"""How well refine finds what it was not told: refine on data with an
undeclared effect (does it name the effect, by how much does the RMS fall),
on clean data (how many seeds get something added), and on every real
recording in ../shared/data (what it found, RMS before and after).  The
cases are lab.studies.refine_study; this script runs, prints and writes them.

    python bench/refine_table.py --json bench/results/refine_table.json

Clean data is measured on three generators (the rotating-field synthetic
run of bench/lab/studies/refine_cases.py, the chamber simulator, the load-cell
simulator), --clean-seeds seeds each; CI runs 20 seeds of the first only.
"""
import argparse
import json
import os
import sys
import time

from pysig.io import atomic_output
from pysig.refine._loop import refine
from lab.studies.refine_study import clean_cases, injected_cases, real_cases, row

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "shared", "data")


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
        with atomic_output(args.json) as fh:
            json.dump(out, fh, indent=2, default=float)
            fh.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
