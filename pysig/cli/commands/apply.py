"""`pysig apply IN.csv --model model.json|image.bin -o OUT.csv [--fixed] [--temp T --columns x,y,z]`

Apply a temperature-compensation model: OUT.csv is IN.csv's columns plus
<axis>_comp for each model axis and `tcomp_clamped` (1 where the temperature
was outside the calibrated range and was clamped to it).  The default is the
float64 model; --fixed runs the firmware's fixed-point C code (temperature
rounded to 0.01 °C, readings must be int16).  Given a coefficient image
(`pysig export --format image`), the firmware's C loader parses it and the
fixed-point path runs: sig_tcomp16 when the image holds the compact section
(`export --compact`), sig_tcomp otherwise; the image names no columns, so
--temp and --columns say which to use."""
import numpy as np

from ...tcomp import model as tmodel
from ...tcomp import quant
from ...errors import InputFileError, ModelFileError, NonFiniteError, RangeError
from ...io import read_csv, write_csv
from ...status import Status, Warn


def register(sub):
    p = sub.add_parser("apply", help="apply a temperature-compensation model to a CSV",
                       description=__doc__)
    p.add_argument("input", metavar="IN.csv")
    p.add_argument("--model", required=True, metavar="model.json")
    p.add_argument("--fixed", action="store_true", help="use the fixed-point C path")
    p.add_argument("--temp", help="temperature column (default: the model's)")
    p.add_argument("--columns", help="reading columns, comma separated (default: the model's axes)")
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
    from ...tcomp._tcomp import TcompQ
    return compensate_fixed(TcompQ.from_fields(**model.fixed_fields()), temp, readings)


def compensate_fixed(c, temp, readings):
    """The C fixed-point path (a TcompQ or Tcomp16Q): temperature to 0.01 °C (clipped to
    int16, then clamped and flagged by C), readings must be int16."""
    temp = np.asarray(temp, dtype=float)
    bad = np.flatnonzero(~np.isfinite(temp))
    if bad.size:
        raise NonFiniteError(f"apply: temperature: non-finite value at index {int(bad[0])}")
    x = np.column_stack(readings)
    if np.any(x != np.round(x)) or x.min() < -32768 or x.max() > 32767:
        raise RangeError("apply: the fixed-point path needs integer int16 readings")
    t = quant.to_centi(np.clip(temp, -327.68, 327.67))
    out, status = c.apply(t, x)
    return [out[:, a].astype(np.int64) for a in range(out.shape[1])], (status & Warn.WARN_CLAMPED).astype(bool)


def is_image(path):
    try:
        with open(path, "rb") as fh:
            return fh.read(4) == b"psig"
    except OSError:
        return False


def load_image(data, where):
    """The C model of a coefficient image: Tcomp16Q when it holds the compact
    section, else TcompQ; the C loaders decide what is valid."""
    from ...tcomp._tcomp import TcompQ, image_find_section
    from ...tcomp._tcomp16 import Tcomp16Q
    from ...store.image import SECTION_COMPACT_POLY, SECTION_OFFSET_POLY
    st = image_find_section(data, SECTION_COMPACT_POLY)[0]
    if st == 0:
        return Tcomp16Q.from_image(data, where=where)
    if st == Status.ERR_EMPTY and image_find_section(data, SECTION_OFFSET_POLY)[0] == Status.ERR_EMPTY:
        raise ModelFileError(f"{where}: the image holds neither an offset-polynomial nor a compact section")
    return TcompQ.from_image(data, where=where)


def run(args):
    image = is_image(args.model)
    if image:
        with open(args.model, "rb") as fh:
            c = load_image(fh.read(), args.model)
        if not (args.temp and args.columns):
            raise InputFileError(f"apply: {args.model} is a coefficient image, which names no columns: "
                                 f"give --temp and --columns")
        temp_col, axes = args.temp, [x.strip() for x in args.columns.split(",") if x.strip()]
        if len(axes) != c.n_axes:
            raise InputFileError(f"apply: the image has {c.n_axes} axes, --columns names {len(axes)}")
        f = c.fields()
        lo, hi = f["t_lo"] / quant.T_PER_DEGC, f["t_hi"] / quant.T_PER_DEGC
    else:
        model = tmodel.load(args.model)
        temp_col = args.temp or model.temp_column
        axes = [x.strip() for x in args.columns.split(",")] if args.columns else model.axes
        if len(axes) != len(model.axes):
            raise InputFileError(f"apply: the model has {len(model.axes)} axes, --columns names {len(axes)}")
        lo, hi = model.t_lo, model.t_hi
    data = read_csv(args.input)
    missing = [col for col in [temp_col] + axes if col not in data]
    if missing:
        raise InputFileError(f"{args.input}: missing column(s) {', '.join(missing)} needed by the model "
                             f"(columns are: {', '.join(data)})")
    if image:
        corrected, clamped = compensate_fixed(c, data[temp_col], [data[a] for a in axes])
    else:
        corrected, clamped = compensate(model, data[temp_col], [data[a] for a in axes], fixed=args.fixed)
    out = dict(data)
    for name, values in zip(axes, corrected):
        out[name + "_comp"] = values
    out["tcomp_clamped"] = clamped.astype(np.int64)
    write_csv(args.output, out)
    n = int(np.count_nonzero(clamped))
    print(f"wrote {args.output}: {len(clamped)} rows, {n} with the temperature clamped to "
          f"{lo:.2f}..{hi:.2f} °C")
