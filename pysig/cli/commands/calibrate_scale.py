"""`pysig calibrate-scale READINGS.csv --mass kg --counts counts -o cal.json [--header cal.h] [--unit kg]`

Least-squares scale calibration, counts -> mass, from readings at standard
masses (one row per reading, or one mean per mass: the weighing paper averages 5
readings per mass), with pysig.lsq, the same solver as the temperature fit.
Prints the sensitivity and the linearity error; writes the calibration as
JSON and, with --header, a C header with the arguments of sig_scale_init_q16
(Q16.16 mass out) and sig_scale_init_f."""
from ...errors import InputFileError, SaturationError
from ...io import atomic_output, read_csv
from ...weigh import calibrate, first_saturated, saturated_count


def register(sub):
    p = sub.add_parser("calibrate-scale", help="fit counts -> mass from standard masses (JSON, C header)",
                       description=__doc__)
    p.add_argument("input", metavar="READINGS.csv")
    p.add_argument("--mass", default="kg", help="mass column (default: kg)")
    p.add_argument("--counts", default="counts", help="ADC counts column (default: counts)")
    p.add_argument("--unit", default="kg", help="mass unit, for the record (default: kg)")
    p.add_argument("-o", "--output", required=True, metavar="cal.json")
    p.add_argument("--header", metavar="cal.h", help="also write a C header")
    p.add_argument("--name", default="scale_cal", help="C identifier prefix (default scale_cal)")
    p.set_defaults(func=run)


def run(args):
    if not (args.name.isascii() and args.name.isidentifier()):
        raise InputFileError(f"--name {args.name!r} is not a C identifier (ASCII letters, digits, _; no leading digit)")
    d = read_csv(args.input, [args.mass, args.counts])
    i = first_saturated(d[args.counts])
    if i is not None:
        raise SaturationError(f"{args.input}: row {i + 2}, column '{args.counts}': "
                              f"{saturated_count(d[args.counts][i])}")
    cal = calibrate(d[args.counts], d[args.mass], unit=args.unit)
    off, mant, shift = cal.fixed()
    if args.header:
        # the header's temporary file first: a header that cannot be written
        # (say, a missing directory) leaves no JSON behind either
        with atomic_output(args.header) as fh:
            fh.write(cal.c_header(args.name))
            cal.save(args.output)
    else:
        cal.save(args.output)
    print(f"{d[args.mass].size} readings: sensitivity {cal.counts_per_unit:.3f} counts/{cal.unit}, "
          f"zero {cal.offset_counts:.1f} counts, linearity error {cal.linearity_err_pct_fs:.4f} % of "
          f"{cal.full_scale:g} {cal.unit}, residual rms {cal.residual_rms:.4g} {cal.unit}")
    print(f"fixed point: offset {off}, gain_mant {mant}, gain_shift {shift} (Q16.16 {cal.unit} out)")
    print(f"wrote {args.output}" + (f" and {args.header}" if args.header else ""))
