"""Can a record resolve an effect at all?  The oracle verdict for a
generated overlapping-effect case (lab.studies.overlap_cases): the
stopping rule on the blocked-CV residual of the model with every effect at
its TRUE parameter (fixed in every fold, not searched) against the same
model without the effect judged, a drift of `knots` knots under both when
the record has one.  An effect the oracle cannot pass is a limit of the
record; one it passes and refine misses is a limit of refine's search or
of its judging.

    PYTHONPATH=.:bench python3 bench/lab/studies/overlap_oracle.py hysteresis+drift 3 --knots 3 4 5
"""
import argparse

from pysig.refine import Options
from pysig.refine import _effect_models as fx
from pysig.refine import _robust as robust
from pysig.refine._base_model import choose_base_order
from pysig.refine._cross_validation import cv_residual, rms
from pysig.refine._stopping import judge

from lab.studies.overlap_cases import HELD_OUT, UNITS, overlap_case

GENERATED_START_BRANCH = 0     # overlap_case's play operator starts on neither branch


def true_effects(truth, knots):
    effects = [fx.Effect(name, GENERATED_START_BRANCH if name == "hysteresis" else 0, next(iter(p.values())))
               for name, p in truth["effects"].items()]
    if truth["drift"]:
        effects.append(fx.Effect("drift", knots))
    return effects


def oracle_verdicts(truth, data, knots=3, opts=None, n_tried=4):
    """{effect: verdict} of each physical effect at its true parameter on
    top of the others at theirs (a `judge` verdict with "accepted"), the
    offset order chosen by blocked CV with all of them in."""
    opts = opts or Options()
    per_report = robust.samples_per_report(data.dt, opts.report_s)
    effects = true_effects(truth, knots)
    order, _ = choose_base_order(data, opts, effects)
    out = {}
    for name in truth["effects"]:
        rest = tuple(e for e in effects if e.name != name)
        e_without = cv_residual(data, fx.ModelSpec(order, rest), opts)
        e_with = cv_residual(data, fx.ModelSpec(order, tuple(effects)), opts)
        ok, verdict = judge(e_without, e_with, opts, per_report, n_tried)
        out[name] = {"accepted": bool(ok), "order": order, "cv_rms_without": rms(e_without),
                     "cv_rms_with": rms(e_with), **verdict}
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("kind")
    ap.add_argument("seeds", type=int, nargs="+")
    ap.add_argument("--knots", type=int, nargs="+", default=[3])
    ap.add_argument("--noise", type=float, default=HELD_OUT["noise"])
    ap.add_argument("--dt", type=float, default=HELD_OUT["dt"])
    ap.add_argument("--length-s", type=float, default=HELD_OUT["length_s"])
    ap.add_argument("--unit", type=int, default=0, choices=range(len(UNITS)))
    args = ap.parse_args(argv)
    print("| case | drift knots | effect | accepted | p (needs) | systematic removed (margin) | CV RMS without -> with |")
    print("|---|---|---|---|---|---|---|")
    for seed in args.seeds:
        label, truth, data = overlap_case(args.kind, seed=seed, noise=args.noise, dt=args.dt,
                                          length_s=args.length_s, unit=UNITS[args.unit])
        for knots in args.knots if truth["drift"] else [None]:
            for name, v in oracle_verdicts(truth, data, knots or 3).items():
                print(f"| {label} | {knots or '-'} | {name} | {'yes' if v['accepted'] else 'no'} | "
                      f"{v['p_value']:.2g} ({v['p_threshold']:.3g}) | {v['systematic_removed']:.3g} "
                      f"({Options().material * v['reading_noise']:.3g}) | {v['cv_rms_without']:.4g} -> {v['cv_rms_with']:.4g} |",
                      flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
