"""`pysig fit IN.csv [IN2.csv ...] --temp temp --columns x,y,z --order 2|auto --t0 25 -o model.json`

Fit the temperature-compensation model (per axis, least-squares polynomial
f(T), correction delta(T) = f(T) - f(T0)) and write it as JSON.  Several
input files are joined (for example one per chamber temperature).  Prints
the temperature groups found, the cross-validated error per order and the
fixed-point format chosen."""
import numpy as np

from ...tcomp import fit as tfit
from ...errors import InputFileError, SaturationError
from ...io import read_csv


def register(sub):
    p = sub.add_parser("fit", help="fit a temperature-compensation model (JSON)", description=__doc__)
    p.add_argument("inputs", nargs="+", metavar="IN.csv")
    p.add_argument("--temp", default="temp", help="temperature column, °C (default: temp)")
    p.add_argument("--columns", required=True, help="1 to 3 reading columns, comma separated")
    p.add_argument("--order", default="2", help="polynomial order 1..8 or 'auto' (default 2)")
    p.add_argument("--t0", type=float, default=25.0, help="reference temperature T0, °C (default 25)")
    p.add_argument("-o", "--output", required=True, metavar="model.json")
    p.set_defaults(func=run)


def parse_order(text):
    if text == "auto":
        return "auto"
    try:
        return int(text)
    except ValueError:
        raise InputFileError(f"fit: --order must be an integer 1..{tfit.MAX_FIT_ORDER} or 'auto', "
                             f"got {text!r}") from None


def read_inputs(paths, temp, columns):
    parts = [read_csv(p, [temp] + columns) for p in paths]
    for path, part in zip(paths, parts):        # name the file and row, not an index in the join
        for c in columns:
            i = tfit.first_saturated(part[c])
            if i is not None:
                raise SaturationError(f"{path}: row {i + 2}, column '{c}': {tfit.saturated_reading(part[c][i])}")
    return {c: np.concatenate([d[c] for d in parts]) for c in [temp] + columns}


def run(args):
    columns = [c.strip() for c in args.columns.split(",") if c.strip()]
    if not 1 <= len(columns) <= 3:
        raise InputFileError(f"fit: --columns needs 1 to 3 column names, got {args.columns!r}")
    order = parse_order(args.order)
    data = read_inputs(args.inputs, args.temp, columns)
    temp = data[args.temp]
    groups = tfit.temperature_groups(temp)
    model = tfit.fit_tcomp(temp, {c: data[c] for c in columns}, order=order, t0=args.t0,
                           temp_column=args.temp, groups=groups, what=", ".join(args.inputs))
    print(f"temperatures: {groups.count} groups: {groups.describe()}")
    if "cv" in model.report:
        print(tfit.format_cv_table(model.report["cv"]))
        print(f"order chosen: {model.order} ({model.report['order_rule']})")
    for a, name in enumerate(model.axes):
        info = model.report["per_axis"][name]
        print(f"{name}: order {model.order}, in-sample RMS {info['rms']:.4g}, f(T0) {model.f_t0[a]:.6g}, "
              f"fixed point Q{model.q[a]} (bound {model.error_bound_lsb[a]:.2g} LSB)")
    print(f"calibrated range {model.t_lo:.2f}..{model.t_hi:.2f} °C, T0 {model.t0:g} °C")
    model.save(args.output)
    print(f"wrote {args.output}")
