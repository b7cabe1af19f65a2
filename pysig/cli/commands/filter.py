"""`pysig filter IN.csv --column counts -o OUT.csv [--preset auto|paper|adaptive|recommended] [--fixed]`

Run the weighing chain (limit -> anti-pulse -> Kalman -> stability) over one
column.  IN and OUT may each be CSV or Parquet (.parquet), by suffix.  The
input is streamed in chunks with the chain's state carried across them, so
memory stays bounded whatever the file's size (--in-memory reads it whole;
the output is byte for byte the same).  A progress bar shows on stderr when
it is a terminal.  OUT is IN's columns (the filtered column as float64) plus
`filtered` and `stable` (1/0), and
with --status the chain's status bits per sample (4 impulse replaced,
16 lock-out re-seed, 32 motion restart, 64 tare applied, 1 clamped,
128 measured noise at its floor: a stuck sensor, 256 a pour followed as a
ramp).  The summary tells impulses (replaced samples after which the load
did not move) from samples of load motion (pysig.weigh.EventCounter).

The default preset, `auto`, needs no sensor constant and no unit: it
measures the noise on the fly and every threshold (A0, motion band,
stability step, zero-tracking band and rate) follows it; an explicit --R
(signal units squared) fixes the noise instead.  `recommended` is tuned
on a real HX711 recording and expects HX711-class counts (1000 counts per
lb) unless --units-per-kg says otherwise; `paper` reproduces the weighing paper's
parameters exactly (kg signal by default).  Every parameter option is in kg (variances in kg^2) and is
converted to signal units with --units-per-kg.  The presets `recommended`
and `adaptive` derive their thresholds from --R, the variance of one reading
of your sensor (--A0 auto = A0-sigmas * sqrt(R); --motion-band auto =
motion-sigmas * sqrt(R / (window - 2))): give your sensor's R and they follow.  --fixed runs the firmware's
fixed-point C code on integer codes: a column that is not integers is
refused (no silent rounding); --scale-factor K multiplies it into integer
codes first (e.g. 10 for grams read in 0.1 g steps) and divides the output
back.  A missing sample (an empty or nan cell, pysig.io) is replaced as an
impulse and counted; the fixed form refuses it.

--cal cal.json (from `pysig calibrate-scale`) turns counts into mass: the
chain runs on the mass (float), or on the codes minus the calibration's zero
(--fixed, the output times its gain), and OUT's filtered column is the mass,
named `filtered_<unit>`."""
import numpy as np
import pyarrow as pa

from ...weigh import CODE_MAX, PRESETS, Chain, EventCounter, load_calibration
from ...errors import InputFileError, NonFiniteError, RangeError, SaturationError
from ...io import MISSING_TEXT, from_numpy, numeric_column, read_header, read_table, row_label
from ...io_stream import iter_batches, progress, table_sink



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
    p.add_argument("--preset", choices=sorted(PRESETS), default="auto")
    p.add_argument("--fixed", action="store_true", help="use the fixed-point C path (integer codes)")
    p.add_argument("--scale-factor", type=float, default=None, metavar="K",
                   help="--fixed: multiply the column by K into integer codes (the output is divided back)")
    p.add_argument("--cal", metavar="cal.json",
                   help="scale calibration (pysig calibrate-scale): write the filtered mass")
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
    p.add_argument("--in-memory", action="store_true",
                   help="read the whole input at once (default: stream it in chunks, the chain's "
                        "state carried across them; the output is the same)")
    p.add_argument("--chunk-mb", type=float, default=1.0,
                   help="streaming chunk size, MB of CSV text (Parquet: MB/16 rows)")
    p.set_defaults(func=run)


def _check_fixed_codes(path, column, x, offset, factor=None):
    """The fixed form takes finite integer ADC codes within its 25-bit range."""
    bad = np.flatnonzero(~np.isfinite(x))
    if bad.size:
        v = float(x[bad[0]])
        what = MISSING_TEXT if np.isnan(v) else f"non-finite value {v!r}"
        raise NonFiniteError(f"{path}: row {row_label(path, offset + int(bad[0]))}, column '{column}': "
                             f"{what} (the fixed form takes ADC codes)")
    frac = np.flatnonzero(x != np.rint(x))
    if frac.size:
        i = int(frac[0])
        scaled = f" (times --scale-factor {factor:g})" if factor is not None else ""
        raise RangeError(f"{path}: row {row_label(path, offset + i)}, column '{column}': {x[i]:.17g}{scaled} "
                         f"is not an integer code and the fixed form would round it; scale the column "
                         f"to integer codes with --scale-factor K (e.g. 10 for readings in steps of 0.1), "
                         f"or leave out --fixed")
    beyond = np.flatnonzero(np.abs(x) > CODE_MAX)
    if beyond.size:
        i = int(beyond[0])
        raise SaturationError(f"{path}: row {row_label(path, offset + i)}, column '{column}': code "
                              f"{x[i]:.17g} beyond the fixed form's +-{CODE_MAX} (25-bit) range")


def _batches(args):
    """(offset, batch) of the input: one batch in memory, chunks otherwise."""
    if args.in_memory:
        yield 0, read_table(args.input, numeric=[args.column], strings=())
    else:
        yield from iter_batches(args.input, numeric=[args.column],
                                block_bytes=max(1, int(args.chunk_mb * (1 << 20))),
                                batch_rows=max(1, int(args.chunk_mb * (1 << 20)) // 16))


def _input_map(args):
    """(samples -> chain input, chain output -> written value, name of the
    filtered column) for --cal / --scale-factor."""
    if args.scale_factor is not None:
        if not args.fixed:
            raise InputFileError("--scale-factor scales a column into the integer codes of --fixed: "
                                 "add --fixed (the float chain takes any unit)")
        if args.cal:
            raise InputFileError("--scale-factor and --cal: the calibration maps the raw codes to "
                                 "mass, give one of them")
        k = args.scale_factor
        if not (np.isfinite(k) and k > 0):
            raise RangeError(f"--scale-factor {k!r}: must be a finite number > 0")
        return (lambda x: x * k), (lambda y: y / k), "filtered"
    if args.cal:
        cal = load_calibration(args.cal)
        name = f"filtered_{cal.unit}"
        if args.fixed:
            zero = cal.fixed()[0]          # the firmware's zero, in whole codes
            return (lambda x: x - zero), (lambda y: y * cal.gain), name
        return cal.to_mass, (lambda y: y), name
    return (lambda x: x), (lambda y: y), "filtered"


def run(args):
    header = read_header(args.input)
    if args.column not in header:
        raise InputFileError(f"{args.input}: row 1 (header), column '{args.column}': missing "
                             f"(columns are: {', '.join(header)})")
    overrides = {name: getattr(args, name) for _, name, _, _ in PARAMS}
    overrides["seed_first"] = args.seed_first
    to_chain, from_chain, filtered_name = _input_map(args)
    chain = Chain(preset=args.preset, fixed=args.fixed, units_per_kg=args.units_per_kg, **overrides)
    if args.tare:
        chain.tare()
    rows = stable_rows = missing = 0
    events = EventCounter()
    with table_sink(args.output) as sink, progress(args.input) as advance:
        for offset, batch in _batches(args):
            x = numeric_column(args.input, args.column, batch[args.column], offset)
            xin = to_chain(x)
            if args.fixed:
                _check_fixed_codes(args.input, args.column, xin, offset, args.scale_factor)
            filtered, stable, status = chain.process(xin, flags=True)
            filtered = from_chain(filtered)
            cols = {name: batch[name] for name in batch.column_names}
            cols[args.column] = from_numpy(x)
            cols[filtered_name] = from_numpy(filtered)
            cols["stable"] = from_numpy(stable.astype(np.int64))
            if args.status:
                cols["status"] = from_numpy(status.astype(np.int64))
            make = pa.Table.from_arrays if isinstance(batch, pa.Table) else pa.RecordBatch.from_arrays
            sink.write(make(list(cols.values()), names=list(cols)))
            rows += x.size
            missing += int(np.count_nonzero(np.isnan(x)))
            events.update(status)
            stable_rows += int(np.count_nonzero(stable))
            advance(x.size)
    counts = events.finish()
    print(f"wrote {args.output}: {rows} rows, {filtered_name}, preset {args.preset}"
          f"{' (fixed point)' if args.fixed else ''}, {counts['impulses']} samples replaced as impulses"
          f"{f' ({missing} missing: empty or nan)' if missing else ''}, "
          f"{counts['motion_samples']} samples of load motion (steps, pours, swings), "
          f"stable on {stable_rows / max(rows, 1) * 100:.1f} % of rows")
