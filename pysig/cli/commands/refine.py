"""`pysig refine IN.csv --time t [--time-unit s|ms|us] --temp temp --columns x --ref ref [--model model.json] --json R.json --plot DIR`

Close the loop on measured data: fit the base model, find the effect the
residual points at, add it while it significantly lowers the out-of-sample
(time-blocked CV) error, and say what structure is left unexplained.
`--model model.json` starts from the model `pysig fit` chose (its family
and size, its temperature and reading columns unless --temp/--columns say
otherwise) instead of an offset order chosen here.  Times are in seconds
unless --time-unit says ms or us; without it, a sample interval or a column
name that suggests milliseconds or microseconds gives a warning.  A time
column of ISO 8601 date-times (a logger's time stamps) is read as such."""
import json
import os
import re
import sys
from dataclasses import replace

import numpy as np

from ... import refine as rf
from ...refine import FitData
from ...errors import InputFileError, InsufficientDataError, RangeError
from ...io import TIME_UNITS, atomic_output, check_time_column, read_csv, read_time_column


def _names(values):
    out = []
    for v in values or []:
        out.extend(x.strip() for x in v.split(",") if x.strip())
    return out


def register(sub):
    p = sub.add_parser("refine", help="find the effect the model lacks, add it, report before/after",
                       description=__doc__)
    p.add_argument("inputs", nargs="+", metavar="IN.csv",
                   help="CSV file(s); several files are joined end to end in time")
    p.add_argument("--time", help="time column: numbers (see --time-unit) or ISO 8601 date-times "
                                     "(2026-03-01T12:00:00, optional fraction and zone); default: the sample index")
    p.add_argument("--time-unit", choices=sorted(TIME_UNITS), default=None,
                   help="the time column's unit (default s; a warning when it looks like ms or us)")
    p.add_argument("--model", metavar="model.json",
                   help="start from this fitted model (pysig fit): its family and size, its columns")
    p.add_argument("--temp", help="temperature column (omit for weighing)")
    p.add_argument("--columns", nargs="+",
                   help="measured column(s), e.g. x or x,y,z (default: the --model's axes)")
    p.add_argument("--ref", nargs="+",
                   help="true value column(s), one per measured column (or one for all); "
                        "without it: the reading at T0 (constant field), or for weighing "
                        "without --temp the held load levels")
    p.add_argument("--folds", type=int, default=rf.DEFAULT_FOLDS, help="time blocks for CV")
    p.add_argument("--alpha", type=float, default=rf.DEFAULT_ALPHA,
                   help="family-wise level of the stopping test")
    p.add_argument("--min-gain", type=float, default=rf.DEFAULT_MIN_GAIN,
                   help="smallest relative CV RMS drop that counts")
    p.add_argument("--report-s", type=float, default=rf.DEFAULT_REPORT_S,
                   help="seconds a reported reading averages over: effects are judged by the "
                        "systematic error they remove from such a reading")
    p.add_argument("--json", metavar="REPORT.json", help="write the report as JSON")
    p.add_argument("--plot", metavar="DIR", help="write residual PNGs into DIR")
    p.set_defaults(func=run)


DAY_S = 86400.0
# (median interval at least, span over), both read as seconds: a log more
# likely in ms or us.  A bench or chamber log at a minute or so runs for a
# day or two (no warning); the same numbers in ms span months.
UNLIKELY_SECONDS = ((1000.0, DAY_S), (100.0, 7 * DAY_S), (0.0, 30 * DAY_S))


def time_unit_warning(name, t):
    """A warning when seconds are unlikely: a name ending in ms/us, or a
    sample interval and span that would make an unlikely log in seconds
    (UNLIKELY_SECONDS; no time unit given)."""
    named = re.search(r"(^|[_\s\[(])(ms|us|µs)[\])]?$", name.lower())
    if named:
        unit = "ms" if named.group(2) == "ms" else "us"
        return (f"time column '{name}' is named like {unit}, read as seconds: give --time-unit {unit} "
                    f"(or --time-unit s to keep seconds)")
    if t.size > 1:
        dt, span = float(np.median(np.diff(t))), float(t[-1] - t[0])
        if any(dt >= interval and span > longest for interval, longest in UNLIKELY_SECONDS):
            unit = "us" if dt >= 1e4 else "ms"
            return (f"time column '{name}': the median sample interval is {dt:g} s and the log spans "
                    f"{span / DAY_S:.3g} days if it is in seconds; if it is in {unit}, give --time-unit {unit} "
                    f"(or --time-unit s to keep seconds)")
    return None


def starting_model(args):
    """(family, size) of --model, its columns filling --temp/--columns."""
    from ...tcomp import load as load_model
    model = load_model(args.model)
    if args.columns is None:
        args.columns = [",".join(model.axes)]
    if args.temp is None:
        args.temp = model.temp_column
    return model.family, model.size


def load(args):
    """Read and join the inputs: dict column -> array, plus the time axis."""
    measured = _names(args.columns)
    refs = _names(args.ref)
    if refs and len(refs) not in (1, len(measured)):
        raise InputFileError(f"refine: {len(refs)} --ref columns for {len(measured)} measured columns")
    wanted = list(dict.fromkeys(measured + refs + [c for c in (args.temp,) if c]))
    parts, t_all, t_end, starts = [], [], None, []
    for path in args.inputs:
        cols = read_csv(path, wanted)
        n = next(iter(cols.values())).size
        if args.time:
            # numbers in --time-unit, or ISO 8601 date-times (their own unit)
            t, kind = read_time_column(path, args.time, args.time_unit)
            check_time_column(path, args.time, t)
            if args.time_unit is None and kind == "number":
                warning = time_unit_warning(args.time, t)
                if warning:
                    print(f"warning: {path}: {warning}", file=sys.stderr)
        else:
            t = np.arange(n, dtype=float)
        if t_end is not None:          # join end to end, one median interval apart
            dt = float(np.median(np.diff(t))) if n > 1 else 1.0
            t = t - t[0] + t_end + dt
        t_end = float(t[-1])
        starts.append(sum(c.size for c in t_all))       # each file is a power-on
        parts.append(cols)
        t_all.append(t)
    joined = {k: np.concatenate([c[k] for c in parts]) for k in wanted}
    return joined, np.concatenate(t_all), measured, refs, tuple(starts)


def build_data(joined, t, measured, refs, i, temp, inputs, segments=(0,)):
    name = measured[i]
    ref_name = (refs[i] if len(refs) == len(measured) else refs[0]) if refs else None
    labels = {"column": name, "inputs": inputs}
    r, mask, ref_from_y = None, None, False
    if ref_name:
        r = joined[ref_name]
        labels["reference"] = f"column {ref_name}"
    elif temp is None:
        r, mask, n_plateaus = rf.plateau_reference(joined[name], t)
        ref_from_y = True
        labels["reference"] = f"held load levels ({n_plateaus} plateaus found in {name})"
    else:
        labels["reference"] = "constant field (the reading at T0)"
    others = {}
    if refs and len(refs) == len(measured):
        others = {refs[j]: joined[refs[j]] for j in range(len(refs)) if j != i}
    return FitData(y=joined[name], t=t, T=joined[temp] if temp else None, r=r, others=others,
                   mask=mask, labels=labels, ref_from_y=ref_from_y, segments=segments)


def _fmt_params(params):
    items = []
    for k, v in params.items():
        if k == "coefficients" or k.endswith("_when_added"):    # the table shows the final model's value
            continue
        items.append(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}")
    return " ".join(items) or "-"


def _fmt_variant(r):
    if r["effect"] == "offset_shape":
        v = r["variant"]
        size = f"{v['knots']} knots" if v["family"] == "table" else f"order {v['order']}"
        return f"offset shape ({v['family']}, {size})"
    return r["effect"]


def _fmt_step_params(s):
    if s["effect"] == "offset_shape":
        p = s["params"]
        return f"table {p['knots']} knots" if p["family"] == "table" else f"poly order {p['order']}"
    return _fmt_params(s["params"])


def drift_and_share_lines(rep):
    """The nuisance drift on its own line, effects judged as a pair, and each
    term's share of the out-of-sample systematic error removed."""
    lines = []
    d = rep["drift"]
    if d:
        lines.append(f"  drift in time (nuisance, not in the device correction): {d['over_record']:.4g} "
                     f"{d['unit']} over the record ({d['start_to_end']:+.4g} start to end, {d['knots']} knots"
                     + (f", a step at each of {d['session_steps']} breaks between sessions"
                        if d.get("session_steps") else "") + ")")
    pairs = {tuple(sorted([s["effect"], *s["judged_with"]])) for s in rep["steps"] if s["judged_with"]}
    for pair in sorted(pairs):
        lines.append(f"  judged together: {' + '.join(pair)} (neither passed alone)")
    if rep["shares"]:
        c = rep["cv_systematic"]
        lines.append(f"  systematic error of a reading, out of sample: {c['before']:.4g} -> {c['after']:.4g}; "
                     "share removed: " + ", ".join(f"{r['effect']} {100 * r['share']:.0f} %" for r in rep["shares"]))
    return lines


def _p_text(p):
    """A p-value as printed: below double precision's resolution near 1 the
    tail probability is not trustworthy digit by digit (it may underflow to
    0), so it reads as a bound, never as 0."""
    return "< 1e-16" if p < 1e-16 else f"{p:.2g}"


def _p_is(p):
    """"p = 0.02", or "p < 1e-16" for a bound."""
    text = _p_text(p)
    return f"p {text}" if text.startswith("<") else f"p = {text}"


def format_table(name, result, start=None):
    rep = result.report()
    base = (f"base model {start}" if start else f"offset order {rep['base_model']['offset_order']}")
    lines = [f"column {name}: {rep['n_samples']} samples, reference: {rep['base_model']['reference']}, "
             f"{base}",
             f"  {'step':<5}{'effect':<14}{'params':<24}{'rms before':>11}{'rms after':>11}"
             f"{'cv before':>11}{'cv after':>11}{'p':>10}"]
    lines.append(f"  {'base':<5}{'-':<14}{'-':<24}{'':>11}{rep['base_rms']:>11.4g}"
                 f"{'':>11}{rep['base_cv_rms']:>11.4g}{'':>10}")
    for k, s in enumerate(rep["steps"], 1):
        lines.append(f"  {k:<5}{s['effect']:<14}{_fmt_step_params(s):<24}{s['rms_before']:>11.4g}"
                     f"{s['rms_after']:>11.4g}{s['cv_rms_before']:>11.4g}{s['cv_rms_after']:>11.4g}"
                     f"{_p_text(s['p_value']):>10}")
    ratio = rep["base_rms"] / rep["final_rms"] if rep["final_rms"] > 0 else float("inf")
    lines.append(f"  RMS {rep['base_rms']:.4g} -> {rep['final_rms']:.4g} ({ratio:.2f}x); "
                 f"CV RMS {rep['base_cv_rms']:.4g} -> {rep['final_cv_rms']:.4g}")
    b, a = rep["before"], rep["after"]
    imp = rep["impulses"]["count"]
    lines.append(f"  impulses: {imp} sample(s) left out; per sample: robust RMS {b['rms']:.4g} -> "
                 f"{a['rms']:.4g}, plain RMS (impulses in) {b['plain_rms']:.4g} -> {a['plain_rms']:.4g}")
    lines.append(f"  reading averaged over {rep['report_s']:g} s: RMS {b['averaged_rms']:.4g} -> "
                 f"{a['averaged_rms']:.4g}, systematic part {b['systematic_rms']:.4g} -> "
                 f"{a['systematic_rms']:.4g}")
    if rep["final_offset"] and any(s["effect"] == "offset_shape" for s in rep["steps"]):
        lines.append(f"  offset shape: {rep['final_offset']}")
    lines += drift_and_share_lines(rep)
    for s in rep["steps"]:
        if s.get("random_walk"):
            w = s["random_walk"]
            lines.append(f"  {s['effect']} under a random-walk drift: {_p_is(w['p_value'])} (needs < "
                         f"{w['p_threshold']:.2g}; the walk's step per {w['block_s']:.3g} s "
                         f"{w['level_sd']:.3g})")
    for r in rep["not_added"]:
        if "random_walk" in r:
            w = r["random_walk"]
            lines.append(f"  not added: {w['effect']} (under a random-walk drift {_p_is(w['p_value'])}, "
                         f"needs < {w['p_threshold']:.2g}; blocked CV {_p_is(r['p_value'])}, systematic "
                         f"gain {100 * r['systematic_gain']:.1f} %: a zero that wanders with the "
                         f"temperature's slow swings explains it as well)")
            continue
        lines.append(f"  not added: {_fmt_variant(r)} (systematic gain "
                     f"{100 * r['systematic_gain']:.1f} %, removed {r['systematic_removed']:.3g} vs "
                     f"reading noise {r['reading_noise']:.3g}, p = {_p_text(r['p_value'])}, needs < "
                     f"{r['p_threshold']:.2g})"
                     + ("; its model as kept scores worse out of sample" if r.get("kept_model_cv_worse") else ""))
    for r in rep.get("dropped", []):
        lines.append(f"  dropped: {r['effect']} (with {' + '.join(r['with']) or 'the offset'} in, it removed "
                     f"{r['systematic_removed']:.3g} of a reading's systematic error vs reading noise "
                     f"{r['reading_noise']:.3g}: not material)")
    for r in {r["effect"]: r for r in rep["not_claimed"]}.values():
        lines.append(f"  not claimed: {r['effect']} ({r['reason']})")
    for r in {r["effect"]: r for r in rep["at_search_edge"]}.values():     # one line per effect
        (pname, value), = [(k, v) for k, v in r.items() if k not in ("effect", "variant", "search_top")]
        lines.append(f"  not tried: {r['effect']} ({pname} = {value:.4g} at the top of its search "
                     f"range: not resolved by this record)")
    u = rep["unexplained"]
    if u["unexplained"]:
        lines.append(f"  unexplained: {u['seen']}")
    else:
        lines.append(f"  unexplained: no (Ljung-Box p = {u['ljung_box_p']:.2g}, lag-1 r = "
                     f"{u['acf_lag1']:.2f}, time blocks {100 * u['time_blocks_r2']:.1f} % of variance)")
    return "\n".join(lines)


def run(args):
    if args.folds < 2:
        raise InsufficientDataError(f"refine: --folds must be at least 2, got {args.folds}")
    if not 0 < args.alpha < 1:                  # also refuses NaN
        raise RangeError(f"refine: --alpha must be in (0, 1), got {args.alpha}")
    base, start = None, None
    if args.model:
        base = starting_model(args)
        start = f"{base[0]}:{base[1]} from {args.model}"
    if not args.columns:
        raise InputFileError("refine: give --columns (or --model, whose axes are the columns)")
    joined, t, measured, refs, starts = load(args)
    if not args.report_s > 0:                   # also refuses NaN
        raise RangeError(f"refine: --report-s must be > 0, got {args.report_s}")
    if base is not None and not args.temp:
        raise InputFileError("refine: --model needs the temperature column (--temp)")
    # progress on a terminal only (a long log takes minutes; logs and pipes stay clean)
    opts = rf.Options(folds=args.folds, alpha=args.alpha, min_gain=args.min_gain,
                      report_s=args.report_s, base=base, progress=None)
    reports, results = {}, {}
    for i, name in enumerate(measured):
        data = build_data(joined, t, measured, refs, i, args.temp, args.inputs, starts)
        res = rf.refine(data, replace(opts, label=f"refine {name}"))
        results[name] = res
        reports[name] = res.report()
        print(format_table(name, res, start))
    if args.plot:
        for name, res in results.items():
            from ...refine import write_plots
            prefix = f"{name}_" if len(measured) > 1 else ""
            for path in write_plots(res, args.plot, prefix):
                print(f"wrote {path}")
    if args.json:
        doc = reports[measured[0]] if len(measured) == 1 else {"columns": reports}
        doc = dict(doc)
        doc["stopping_test"] = rf.stop_test(opts)
        with atomic_output(args.json) as fh:
            json.dump(doc, fh, indent=2, default=_json_default)
            fh.write("\n")
        print(f"wrote {os.path.abspath(args.json)}")
    return 0


def _json_default(o):
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.bool_):
        return bool(o)
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")
