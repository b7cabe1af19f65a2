"""`pysig demo [--out DIR] [--channel lc1|lc2] [--csv FILE]`

The weighing chain on a real recording bundled with the package: two load
cells read by an HX711 at 10 Hz while 10-lb weights are put on and taken off
by hand, with real read glitches (mvsivaselvan/CIE324-Swing-Project, MIT).
Calibrates counts -> lb on the plateaus it finds, runs the raw signal, the
paper's chain, a plain Kalman filter, the recommended chain and the default
chain, auto (the C code, through Cython), prints a table and writes a picture into DIR (default: the
current directory), printing its path."""
import os

from ...weigh import (RECORDING_CHANNELS, analyse_recording, bundled_recording, load_recording,
                      plot_recording)
from ...errors import InputFileError

COLUMNS = ("config", "glitches passed", "plateaus missed", "settle max (s)",
           "plateau err (lb)", "noise (lb)")


def register(sub):
    p = sub.add_parser("demo", help="the weighing chain on a bundled real HX711 recording",
                       description=__doc__)
    p.add_argument("--out", metavar="DIR", default=".",
                   help="directory for the picture (default: the current directory)")
    p.add_argument("--channel", choices=RECORDING_CHANNELS, default="lc1")
    p.add_argument("--csv", help="another copy of hx711_steps_10hz.csv (default: the bundled one)")
    p.set_defaults(func=run)


def _table(rows):
    cells = [COLUMNS] + [
        (c, f"{r['glitches_passed']}/{r['glitches']}", f"{r['plateaus_missed']}/{r['plateaus']}",
         "never" if r["settle_s_max"] is None else f"{r['settle_s_max']:.1f}",
         f"{r['plateau_err_lb_max']:.3f}", f"{r['plateau_noise_lb']:.3f}")
        for c, r in rows.items()]
    widths = [max(len(row[i]) for row in cells) for i in range(len(COLUMNS))]
    lines = ["  ".join(v.rjust(w) if i else v.ljust(w) for i, (v, w) in enumerate(zip(row, widths)))
             for row in cells]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def demo(path, out_dir, channel):
    if not os.path.isdir(out_dir):
        raise InputFileError(f"--out {out_dir}: not a directory")
    d = load_recording(path)
    res = analyse_recording(d["t_s"], d[f"{channel}_counts"])
    cal = res["calibration"]
    print(f"pysig demo: real HX711 recording (hx711_steps_10hz, {d['t_s'].size} samples at 10 Hz), "
          f"channel {channel}")
    print("  source: github.com/mvsivaselvan/CIE324-Swing-Project (MIT licence, bundled with it)")
    print(f"  calibration on {len(res['plateaus'])} plateaus found automatically "
          f"(0-10-20-30-40-30-20-10-0 lb): {cal.counts_per_unit:.1f} counts/lb, "
          f"linearity error {cal.linearity_err_pct_fs:.3f} % of 40 lb")
    print()
    print(_table(res["rows"]))
    print()
    print("  paper_chain: the weighing paper's parameters; its limit filter (A0 = 2 kg) refuses each 10-lb step.")
    print("  recommended: lock-out fix, motion-aware settling, zero tracking; thresholds from a fixed R.")
    print("  auto: the default, Chain(): the same with every threshold following the noise it measures.")
    png = os.path.join(out_dir, f"pysig_demo_{channel}.png")
    plot_recording(png, d["t_s"], res,
                           f"pysig demo: weighing chain on a real HX711 recording ({channel})")
    print(f"\npicture: {os.path.abspath(png)}")
    return res


def run(args):
    if args.csv:
        demo(args.csv, args.out, args.channel)
    else:
        with bundled_recording() as path:
            demo(path, args.out, args.channel)
