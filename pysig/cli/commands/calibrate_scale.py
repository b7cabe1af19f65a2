"""`pysig calibrate-scale READINGS.csv --mass kg --counts counts -o cal.json [--header cal.h] [--unit kg]`
`pysig calibrate-scale LOG.csv --column C --masses 0,52.7,... (--time t | --rate HZ) -o cal.json`

Least-squares scale calibration, counts -> mass, with pysig.lsq, the same
solver as the temperature fit.  Two inputs:

- a table of readings at standard masses (--mass, --counts: one row per
  reading, or one mean per mass; the weighing paper averages 5 readings per
  mass);
- a raw log of one column (--column) during which the masses were put on
  (--masses, in the order the loads first appear): the still loads are found
  in the log itself (pysig.weigh.plateaus_at_masses, the plateau
  finder of `pysig demo`), each load's plateaus are matched to its mass, and
  the line is fitted through their median readings.  The rate comes from a
  time column (--time: seconds or ISO 8601 date-times) or --rate.

Prints the sensitivity and, with three or more distinct masses, the
linearity error (a line through two masses fits them whatever the cell
does); writes the calibration as JSON (`pysig filter --cal` takes it) and,
with --header, a C header with the arguments of sig_scale_init_q16 (Q16.16
mass out) and sig_scale_init_f."""
import numpy as np

from ...errors import InputFileError, InsufficientDataError, RangeError, SaturationError
from ...io import atomic_output, check_time_column, read_csv, read_time_column
from ...weigh import calibrate, first_saturated, plateaus_at_masses, saturated_count


def _masses(text):
    try:
        return [float(v) for v in text.split(",")]
    except ValueError:
        raise InputFileError(f"--masses {text!r}: comma-separated numbers expected") from None


def register(sub):
    p = sub.add_parser("calibrate-scale", help="fit counts -> mass from standard masses (JSON, C header)",
                       description=__doc__)
    p.add_argument("input", metavar="READINGS.csv")
    p.add_argument("--mass", default="kg", help="table: mass column (default: kg)")
    p.add_argument("--counts", default="counts", help="table: ADC counts column (default: counts)")
    p.add_argument("--column", help="log: the raw readings column (with --masses)")
    p.add_argument("--masses", type=_masses, metavar="M1,M2,...",
                   help="log: the masses put on, in the order the loads first appear")
    p.add_argument("--time", help="log: time column in seconds or ISO 8601 date-times (gives the rate)")
    p.add_argument("--rate", type=float, help="log: samples per second (instead of --time)")
    p.add_argument("--min-plateau-s", type=float, default=3.0,
                   help="log: shortest still load, seconds (default 3)")
    p.add_argument("--unit", default="kg", help="mass unit, for the record (default: kg)")
    p.add_argument("-o", "--output", required=True, metavar="cal.json")
    p.add_argument("--header", metavar="cal.h", help="also write a C header")
    p.add_argument("--name", default="scale_cal", help="C identifier prefix (default scale_cal)")
    p.set_defaults(func=run)


def _check_saturation(path, column, x):
    i = first_saturated(x)
    if i is not None:
        raise SaturationError(f"{path}: row {i + 2}, column '{column}': {saturated_count(x[i])}")


def _from_log(args):
    """(readings, masses, what) from a raw log: the plateaus it holds."""
    if (args.time is None) == (args.rate is None):
        raise InputFileError("a log needs its rate: give --time COLUMN (seconds) or --rate HZ")
    x = read_csv(args.input, [args.column])[args.column]
    _check_saturation(args.input, args.column, x)
    if args.time:
        t, _ = read_time_column(args.input, args.time)
        check_time_column(args.input, args.time, t)
        if x.size < 2:
            raise InsufficientDataError(f"{args.input}: {x.size} rows, a log needs at least 2")
        rate = 1.0 / float(np.median(np.diff(t)))
    else:
        rate = args.rate
    if not (np.isfinite(rate) and rate > 0):
        raise RangeError(f"--rate {rate!r}: must be a finite number > 0 (samples per second)")
    plateaus = plateaus_at_masses(x, args.masses, rate, min_s=args.min_plateau_s)
    levels = [p.level for p in plateaus]
    masses = [p.nominal for p in plateaus]
    return levels, masses, (f"{len(plateaus)} plateaus found in {args.input} "
                            f"({len(args.masses)} loads)")


def run(args):
    if not (args.name.isascii() and args.name.isidentifier()):
        raise InputFileError(f"--name {args.name!r} is not a C identifier (ASCII letters, digits, _; no leading digit)")
    if (args.column is None) != (args.masses is None):
        raise InputFileError("a log needs both --column and --masses (a table: --mass and --counts)")
    if args.masses is not None:
        counts, masses, what = _from_log(args)
    else:
        d = read_csv(args.input, [args.mass, args.counts])
        _check_saturation(args.input, args.counts, d[args.counts])
        counts, masses = d[args.counts], d[args.mass]
        what = f"{d[args.mass].size} readings"
    cal = calibrate(counts, masses, unit=args.unit)
    off, mant, shift = cal.fixed()
    if args.header:
        # the header's temporary file first: a header that cannot be written
        # (say, a missing directory) leaves no JSON behind either
        with atomic_output(args.header) as fh:
            fh.write(cal.c_header(args.name))
            cal.save(args.output)
    else:
        cal.save(args.output)
    print(f"{what}: sensitivity {cal.counts_per_unit:.3f} counts/{cal.unit}, "
          f"zero {cal.offset_counts:.1f} counts, {cal.linearity_text()}, "
          f"residual rms {cal.residual_rms:.4g} {cal.unit}")
    print(f"fixed point: offset {off}, gain_mant {mant}, gain_shift {shift} (Q16.16 {cal.unit} out)")
    print(f"wrote {args.output}" + (f" and {args.header}" if args.header else ""))
