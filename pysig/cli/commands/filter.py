"""`pysig filter IN.csv --column counts -o OUT.csv [--preset paper|adaptive|recommended] [--fixed]`

Run the weighing chain (limit -> anti-pulse -> Kalman -> stability) over one
column.  OUT.csv is IN.csv's columns plus `filtered` and `stable` (1/0), and
with --status the chain's status bits per sample (4 impulse replaced,
16 lock-out re-seed, 32 motion restart, 64 tare applied, 1 clamped).

The default preset, `recommended`, is tuned on a real HX711 recording and
expects HX711-class counts (1000 counts per lb) unless --units-per-kg says
otherwise; `paper` reproduces the weighing paper's parameters exactly (kg signal by
default).  Every parameter option is in kg (variances in kg^2) and is
converted to signal units with --units-per-kg.  The presets `recommended`
and `adaptive` derive their thresholds from --R, the variance of one reading
of your sensor (--A0 auto = A0-sigmas * sqrt(R); --motion-band auto =
motion-sigmas * sqrt(R / (window - 2))): give your sensor's R and they follow.  --fixed runs the firmware's
fixed-point C code (samples rounded to integer codes)."""
import numpy as np

from ...weigh.chain import PRESETS, Chain
from ...errors import InputFileError, NonFiniteError, SaturationError
from ...reference.chain import CODE_MAX
from ...io import read_csv, write_csv



def _kg_or_auto(text):
    """A number (kg) or 'auto' (derived from R by the preset's rule)."""
    return "auto" if text.strip().lower() == "auto" else float(text)


# option -> (parameter name, type, help)
PARAMS = [
    ("--A0", "A0", _kg_or_auto, "limit filter threshold, kg, or 'auto' (A0-sigmas * sqrt(R))"),
    ("--A0-sigmas", "A0_sigmas", float, "A0 'auto': sigmas of one reading (sqrt(R))"),
    ("--window", "window", int, "anti-pulse window N (3..32)"),
    ("--Q", "Q", float, "Kalman process noise, kg^2"),
    ("--R", "R", float, "Kalman measurement noise, kg^2"),
    ("--x0", "x0", float, "Kalman initial state, kg"),
    ("--P0", "P0", float, "Kalman initial variance, kg^2"),
    ("--stable-step", "stable_step", float, "stability: max change between outputs, kg"),
    ("--stable-count", "stable_count", int, "stability: successive samples within the step"),
    ("--lockout-n", "lockout_n", int, "lock-out fix: rejections on one side before re-seeding (0 = off)"),
    ("--motion-band", "motion_band", _kg_or_auto,
     "motion mode: |window mean - estimate| that means motion, kg (0 = off), or 'auto' "
     "(motion-sigmas * sqrt(R / (window - 2)))"),
    ("--motion-sigmas", "motion_sigmas", float, "motion band 'auto': sigmas of the window mean"),
    ("--motion-count", "motion_count", int, "motion mode: successive samples beyond the band"),
    ("--zero-band", "zero_band", float, "zero tracking band around zero, kg (0 = off)"),
    ("--zero-rate", "zero_rate", float, "zero tracking: max offset change per sample, kg"),
]


def register(sub):
    p = sub.add_parser("filter", help="run the weighing filter chain over a CSV column",
                       description=__doc__)
    p.add_argument("input", metavar="IN.csv")
    p.add_argument("--column", required=True, help="column holding the samples")
    p.add_argument("-o", "--output", required=True, metavar="OUT.csv")
    p.add_argument("--preset", choices=sorted(PRESETS), default="recommended")
    p.add_argument("--fixed", action="store_true", help="use the fixed-point C path")
    p.add_argument("--units-per-kg", type=float, default=None,
                   help="signal units per kg (default: the preset's)")
    p.add_argument("--seed-first", dest="seed_first", action="store_true", default=None,
                   help="start the Kalman filter from the first sample")
    p.add_argument("--no-seed-first", dest="seed_first", action="store_false",
                   help="start the Kalman filter from x0")
    for opt, name, typ, text in PARAMS:
        p.add_argument(opt, dest=name, type=typ, default=None, help=text)
    p.add_argument("--tare", action="store_true",
                   help="tare at the first stable output (the output is then net of it)")
    p.add_argument("--status", action="store_true", help="add the per-sample status column")
    p.set_defaults(func=run)


def _keep_integers(a):
    """Columns that hold only whole numbers are written back as integers."""
    if a.size and np.all(np.isfinite(a)) and np.all(a == np.round(a)) and np.all(np.abs(a) < 2**53):
        return a.astype(np.int64)
    return a


def run(args):
    data = read_csv(args.input, allow_nonfinite=True)
    if args.column not in data:
        raise InputFileError(f"{args.input}: row 1 (header), column '{args.column}': missing "
                             f"(columns are: {', '.join(data)})")
    x = data[args.column]
    bad = np.flatnonzero(~np.isfinite(x))
    if args.fixed and bad.size:
        raise NonFiniteError(f"{args.input}: row {int(bad[0]) + 2}, column '{args.column}': "
                             f"non-finite value {float(x[bad[0]])!r} (the fixed form takes ADC codes)")
    if args.fixed:
        beyond = np.flatnonzero(np.abs(x) > CODE_MAX)
        if beyond.size:
            i = int(beyond[0])
            raise SaturationError(f"{args.input}: row {i + 2}, column '{args.column}': code {x[i]:.17g} "
                                  f"beyond the fixed form's +-{CODE_MAX} (25-bit) range")
    overrides = {name: getattr(args, name) for _, name, _, _ in PARAMS}
    overrides["seed_first"] = args.seed_first
    chain = Chain(preset=args.preset, fixed=args.fixed, units_per_kg=args.units_per_kg, **overrides)
    if args.tare:
        chain.tare()
    filtered, stable, status = chain.process(x, flags=True)
    out = {name: _keep_integers(col) for name, col in data.items()}
    out["filtered"] = filtered
    out["stable"] = stable.astype(np.int64)
    if args.status:
        out["status"] = status.astype(np.int64)
    write_csv(args.output, out)
    rejected = int(np.count_nonzero(status & 4))
    print(f"wrote {args.output}: {x.size} rows, preset {args.preset}"
          f"{' (fixed point)' if args.fixed else ''}, {rejected} samples replaced as impulses, "
          f"stable on {np.mean(stable) * 100:.1f} % of rows")
