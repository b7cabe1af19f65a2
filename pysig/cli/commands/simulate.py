"""`pysig simulate OUT.csv [--seed N] [--load-steps 0:0,5:30,20:0] [--noise-uv-rms 0.3] ...`

A load-cell run as the weighing paper's hardware would see it (pysig.sim._loadcell:
an L6D-like cell into a 24-bit ADS1232-like ADC), written as CSV with the
columns t, counts, ref_kg.  Every disturbance is an option, off unless
given; the same options and seed give the same file.  Feed the result to
`pysig filter OUT.csv --column counts`."""
from dataclasses import fields

from ...errors import RangeError
from ...sim import LoadCellParams, simulate_loadcell, write_loadcell_run


def _steps(text):
    """'0:0,5:30,20:0' -> ((0.0, 0.0), (5.0, 30.0), (20.0, 0.0))"""
    try:
        pairs = [item.split(":") for item in text.split(",") if item.strip()]
        return tuple((float(t), float(kg)) for t, kg in pairs)
    except ValueError:
        raise RangeError(f"--load-steps {text!r}: expected t:kg pairs separated by commas, "
                         "e.g. 0:0,5:30,20:0") from None


def register(sub):
    p = sub.add_parser("simulate", help="simulate a load-cell run (CSV t, counts, ref_kg)",
                       description=__doc__)
    p.add_argument("output", metavar="OUT.csv")
    p.add_argument("--seed", type=int, default=0)
    defaults = LoadCellParams()
    for f in fields(LoadCellParams):
        flag = "--" + f.name.replace("_", "-")
        if f.name == "load_steps":
            p.add_argument(flag, default="0:0", help="t:kg pairs, the load from each time on "
                           "(default 0:0)")
        elif f.name == "impulse_polarity":
            p.add_argument(flag, choices=("+", "-", "both"), default=defaults.impulse_polarity)
        else:
            p.add_argument(flag, type=float, default=getattr(defaults, f.name),
                           help=f"(default {getattr(defaults, f.name)!r})")
    p.set_defaults(func=run)


def run(args):
    kwargs = {f.name: getattr(args, f.name) for f in fields(LoadCellParams)}
    kwargs["load_steps"] = _steps(args.load_steps)
    params = LoadCellParams(**kwargs)
    sim = simulate_loadcell(params, seed=args.seed)
    write_loadcell_run(args.output, sim)
    print(f"wrote {args.output}: {sim['t'].size} samples at {params.rate_hz:g} samples/s, "
          f"{params.counts_per_kg:.1f} counts/kg, zero {params.zero_counts:.0f} counts, seed {args.seed}")
