"""Pour lag over many noise seeds: how often the default chain's lag on a
pour exceeds one sample at the 95th percentile, per slope.

    python bench/pour_lag_seeds.py --json FILE [--seeds 200]

bench/weighing_dynamic.py takes the worst of 2 (or --seeds) seeds per cell;
this runs its generated run (kg, 10 samples/s: the same placement, bump,
pours of S over 1, 3 and 8 s and removal) over many seeds at noise levels
that put the pours at 4-100 sigma per sample, with 0 and 1 % glitches, and
counts per slope the pours whose lag p95 (weighing_dynamic's definition:
(truth - output) / slope over the pour's samples) is above 1 sample.
"""
import argparse

import numpy as np

from pysig.io import atomic_output
from pysig.weigh import Chain

import weighing_defaults as wd
import weighing_dynamic as wdyn

SIGMA_REL = (0.001, 0.005, 0.016, 0.02, 0.025, 0.03)   # pours of 4 .. 100 sigma per sample
MIN_SLOPE_SIGMA = 4.0
FIRST_SEED = 1000                                       # apart from weighing_dynamic's seeds 0..7


def pour_p95(out, truth, t, events, rate):
    """{slope in sigma per sample (unrounded slope, sigma): lag p95} of one run."""
    res = []
    for t0, dur, dunit in events["pours"]:
        idx = np.flatnonzero((t > t0) & (t <= t0 + dur))
        slope = dunit / (dur * rate)
        res.append((slope, float(np.percentile((truth[idx] - out[idx]) / slope, 95))))
    return res


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", help="write the rows here")
    ap.add_argument("--seeds", type=int, default=200)
    a = ap.parse_args(argv)
    per = {}
    for sigma_rel in SIGMA_REL:
        for glitch_rate in wdyn.GLITCH_RATES:
            for seed in range(FIRST_SEED, FIRST_SEED + a.seeds):
                x, _, truth, sigma, t, events = wdyn.make_run("kg", sigma_rel, glitch_rate, seed)
                out = Chain().process(x)[0]
                for slope, p95 in pour_p95(out, truth, t, events, 10.0):
                    if slope / sigma >= MIN_SLOPE_SIGMA:
                        per.setdefault((round(slope / sigma, 2), glitch_rate), []).append(p95)
    rows = [{"slope_sigma": k[0], "glitch_rate": k[1], "pours": len(v),
             "share_p95_above_1": float(np.mean(np.array(v) > 1.0)),
             "p95_median": float(np.median(v)), "p95_worst": float(np.max(v))} for k, v in sorted(per.items())]
    print("slope (sigma/sample) | glitches | pours | lag p95 > 1 sample | median p95 | worst p95")
    print("---|---|---|---|---|---")
    for r in rows:
        print(f"{r['slope_sigma']:.2f} | {100 * r['glitch_rate']:.0f} % | {r['pours']} | "
              f"{100 * r['share_p95_above_1']:.1f} % | {r['p95_median']:.2f} | {r['p95_worst']:.2f}")
    if a.json:
        with atomic_output(a.json) as fh:
            wd.write_json({"rows": rows, "seeds": a.seeds, "first_seed": FIRST_SEED, "definitions": __doc__}, fh)
        print(f"\nwrote {a.json}")


if __name__ == "__main__":
    main()
