"""`pysig apply IN.csv --model model.json -o OUT.csv [--fixed]`

Apply a temperature-compensation model: OUT.csv is IN.csv's columns plus
<axis>_comp for each model axis and `tcomp_clamped` (1 where the temperature
was outside the calibrated range and was clamped to it).  The default is the
float64 model; --fixed runs the firmware's fixed-point C code (temperature
rounded to 0.01 °C, readings must be int16)."""
import numpy as np

from .. import model as tmodel
from .. import quant
from ..errors import NonFiniteError
from ..io import read_csv, write_csv


def register(sub):
    p = sub.add_parser("apply", help="apply a temperature-compensation model to a CSV",
                       description=__doc__)
    p.add_argument("input", metavar="IN.csv")
    p.add_argument("--model", required=True, metavar="model.json")
    p.add_argument("--fixed", action="store_true", help="use the fixed-point C path")
    p.add_argument("-o", "--output", required=True, metavar="OUT.csv")
    p.set_defaults(func=run)


def compensate(model, temp, readings, fixed=False):
    """(list of corrected arrays, clamped flags) for readings per axis."""
    temp = np.asarray(temp, dtype=float)
    bad = np.flatnonzero(~np.isfinite(temp))
    if bad.size:
        raise NonFiniteError(f"apply: temperature: non-finite value at index {int(bad[0])}")
    if not fixed:
        return model.apply_float(temp, readings), model.clamped(temp)
    from .._tcomp import TcompQ
    c = TcompQ.from_fields(**model.fixed_fields())
    t = np.clip(quant.to_centi(np.clip(temp, -327.68, 327.67)), -32768, 32767)
    out, status = c.apply(t, np.column_stack(readings))
    return [out[:, a].astype(np.int64) for a in range(out.shape[1])], (status & 1).astype(bool)


def run(args):
    model = tmodel.load(args.model)
    data = read_csv(args.input)
    wanted = [model.temp_column] + model.axes
    missing = [c for c in wanted if c not in data]
    if missing:
        from ..errors import InputFileError
        raise InputFileError(f"{args.input}: missing column(s) {', '.join(missing)} needed by the model "
                             f"(columns are: {', '.join(data)})")
    corrected, clamped = compensate(model, data[model.temp_column], [data[a] for a in model.axes],
                                    fixed=args.fixed)
    out = dict(data)
    for name, values in zip(model.axes, corrected):
        out[name + "_comp"] = values
    out["tcomp_clamped"] = clamped.astype(np.int64)
    write_csv(args.output, out)
    n = int(np.count_nonzero(clamped))
    print(f"wrote {args.output}: {len(clamped)} rows, {n} with the temperature clamped to "
          f"{model.t_lo:.2f}..{model.t_hi:.2f} °C")
