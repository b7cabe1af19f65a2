"""The weighing chain on a real HX711 step recording: behaviour on a
sensor the presets were not tuned on.

    python bench/real_recordings.py --json real.json --plot DIR [--csv FILE]

Reads ../shared/data/hx711_steps_10hz/hx711_steps_10hz.csv (or the copy
bundled in pysig/data, or --csv), calibrates lc1 and lc2 counts -> lb on the
plateaus found automatically, runs raw / paper_chain / kalman / recommended
(and recommended_fixed: the firmware's fixed-point chain on codes) and
prints and writes, per channel and configuration: glitches_passed,
plateaus_missed, settle_s_max, plateau_err_lb_max, plateau_noise_lb; for
the no-load channels lc3..lc6 zero noise and zero drift before and after
filtering.  "auto" is the package default (noise measured on the fly),
"auto_fixed" its fixed-point form on codes.  One PNG per channel in DIR.

JSON: {"rows": [...loaded-channel rows...], "zero_rows": [...],
"calibration": {...}, "definitions": {...}, "source": ...}.
"""
import argparse
import hashlib
import json
import os
from pathlib import Path


from pysig.weigh import _recording as recording
from pysig.io import atomic_output

HERE = Path(__file__).resolve().parent

SHARED = HERE.parent.parent / "shared" / "data" / "hx711_steps_10hz" / "hx711_steps_10hz.csv"
CONFIGS = recording.CONFIGS + ("recommended_fixed", "auto_fixed")


def fmt(v, nd=3):
    if v is None:
        return "never"
    if isinstance(v, float):
        return f"{v:.{nd}f}"
    return str(v)


def run(csv_path, plot_dir=None):
    d = recording.load(csv_path)
    t = d["t_s"]
    rows, zero_rows, cals = [], [], {}
    for ch in recording.LOADED:
        res = recording.analyse_loaded(t, d[f"{ch}_counts"], configs=CONFIGS)
        cal = res["calibration"]
        cals[ch] = {"counts_per_lb": cal.counts_per_unit, "zero_counts": cal.offset_counts,
                    "linearity_err_pct_fs": cal.linearity_err_pct_fs,
                    "residual_rms_lb": cal.residual_rms,
                    "plateaus": [{"from_s": float(t[p.start]), "to_s": float(t[p.stop - 1]),
                                  "nominal_lb": p.nominal, "level_counts": p.level}
                                 for p in res["plateaus"]],
                    "glitch_indices": [int(g) for g in res["glitches"]]}
        for config in CONFIGS:
            rows.append({"channel": ch, "config": config, **res["rows"][config]})
        if plot_dir:
            recording.plot_channel(Path(plot_dir) / f"hx711_{ch}.png", t, res,
                                   f"hx711_steps_10hz {ch}: hand-placed 10-lb steps (real HX711 data)")
    lb_per_count = 1.0 / cals["lc1"]["counts_per_lb"]
    for ch in recording.UNLOADED:
        res = recording.analyse_zero(t, d[f"{ch}_counts"], lb_per_count, configs=CONFIGS)
        for config in CONFIGS:
            zero_rows.append({"channel": ch, "config": config, **res["rows"][config]})
        if plot_dir:
            recording.plot_channel(Path(plot_dir) / f"hx711_{ch}.png", t, res,
                                   f"hx711_steps_10hz {ch}: no load (lb with lc1's sensitivity)",
                                   nominal=False)
    digest = hashlib.sha256(Path(csv_path).read_bytes()).hexdigest()
    return {"source": {"file": Path(csv_path).name, "sha256": digest,
                       "origin": "github.com/mvsivaselvan/CIE324-Swing-Project (MIT)"},
            "rows": rows, "zero_rows": zero_rows, "calibration": cals,
            "definitions": recording.METRICS}


def print_tables(out):
    for ch, c in out["calibration"].items():
        print(f"{ch}: {c['counts_per_lb']:.1f} counts/lb, zero {c['zero_counts']:.0f} counts, "
              f"linearity error {c['linearity_err_pct_fs']:.3f} % of 40 lb, "
              f"{len(c['plateaus'])} plateaus found, glitches at samples {c['glitch_indices']}")
    head = ("channel", "config", "glitches_passed", "plateaus_missed", "settle_s_max",
            "plateau_err_lb_max", "plateau_noise_lb")
    print()
    print(" | ".join(head))
    print(" | ".join("---" for _ in head))
    for r in out["rows"]:
        print(" | ".join([r["channel"], r["config"], f"{r['glitches_passed']}/{r['glitches']}",
                          f"{r['plateaus_missed']}/{r['plateaus']}", fmt(r["settle_s_max"], 1),
                          fmt(r["plateau_err_lb_max"]), fmt(r["plateau_noise_lb"])]))
    print()
    for config in ("recommended", "auto"):
        print(f"settle time per step (s), {config}: " + "; ".join(
            f"{r['channel']}: {', '.join(fmt(s, 1) for s in r['settle_s'])} (hand + swing: "
            f"{', '.join(fmt(s, 1) for s in r['motion_s'])})"
            for r in out["rows"] if r["config"] == config))
    head = ("channel", "config", "glitches_passed", "zero_noise_lb", "zero_drift_lb")
    print()
    print(" | ".join(head))
    print(" | ".join("---" for _ in head))
    for r in out["zero_rows"]:
        print(" | ".join([r["channel"], r["config"], f"{r['glitches_passed']}/{r['glitches']}",
                          fmt(r["zero_noise_lb"]), fmt(r["zero_drift_lb"])]))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", help="write the table here")
    ap.add_argument("--plot", metavar="DIR", help="write one PNG per channel into DIR")
    ap.add_argument("--csv", help="recording (default: ../shared/data copy, else the bundled one)")
    args = ap.parse_args(argv)
    if args.plot:
        os.makedirs(args.plot, exist_ok=True)
    if args.csv:
        out = run(args.csv, args.plot)
    elif SHARED.exists():
        out = run(SHARED, args.plot)
    else:
        with recording.bundled_csv() as path:
            out = run(path, args.plot)
    print_tables(out)
    if args.json:
        with atomic_output(args.json) as fh:
            json.dump(out, fh, indent=1, default=float)
        print(f"\nwrote {args.json}")
    if args.plot:
        print(f"wrote {len(recording.LOADED) + len(recording.UNLOADED)} PNGs into {args.plot}")


if __name__ == "__main__":
    main()
