"""What the weighing benches' command lines share: the same options, the
real recording they run on (the one given, else ../shared/data's copy, else
the one bundled with pysig) and how their JSON and plot are written."""
import argparse
import os
from pathlib import Path

from pysig.io import atomic_output
from pysig.weigh import bundled_recording

SHARED_RECORDING = (Path(__file__).resolve().parents[2].parent / "shared" / "data" / "hx711_steps_10hz"
                    / "hx711_steps_10hz.csv")


def parse_args(doc, plot_name, seeds, argv=None):
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--json", help="write the rows here")
    ap.add_argument("--plot", metavar="DIR", help=f"write {plot_name} into DIR")
    ap.add_argument("--csv", help="real recording (default: ../shared/data copy, else the bundled one)")
    ap.add_argument("--seeds", type=int, default=seeds, help="noise seeds per cell")
    return ap.parse_args(argv)


def on_recording(csv, rows_of):
    """rows_of(path) on the recording the options name."""
    if csv:
        return rows_of(csv)
    if SHARED_RECORDING.exists():
        return rows_of(SHARED_RECORDING)
    with bundled_recording() as path:
        return rows_of(path)


def write_outputs(out, args, plot_name, write_json, plot):
    """The JSON (atomically) and the plot the options ask for."""
    if args.json:
        with atomic_output(args.json) as fh:
            write_json(out, fh)
        print(f"\nwrote {args.json}")
    if args.plot:
        os.makedirs(args.plot, exist_ok=True)
        plot(out, Path(args.plot) / plot_name)
        print(f"wrote {Path(args.plot) / plot_name}")


def log_log_axes(ax, hline, vline, xlabel, ylabel, title, vline_style="--"):
    """Both weighing benches' scatter plots: log-log, the goal as a dashed
    horizontal line, the range limit as a vertical one, a small legend."""
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.axhline(hline, color="k", lw=0.7, ls="--")
    ax.axvline(vline, color="k", lw=0.6, ls=vline_style)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend(fontsize=7, ncol=2)
