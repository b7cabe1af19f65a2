"""`pysig apply IN.csv --model model.json|image.bin -o OUT.csv [--fixed] [--temp T --columns x,y,z]`

Apply a temperature-compensation model: OUT.csv is IN.csv's columns plus
<axis>_comp for each model axis and `tcomp_clamped` (1 where the temperature
was outside the calibrated range and was clamped to it).  The default is the
float64 model; --fixed runs the firmware's fixed-point C code on the model's
image (sig_tmodel_load_image + sig_tmodel_apply: temperature rounded to the
model's int16 unit, readings x value scale must be int16).  Given a
coefficient image (`pysig export --format image`) the firmware's C loader
reads it, whatever model family it holds; the image names no columns and
no units, so --temp and --columns say which to use, --temp-unit raw passes
the column's integer codes to the firmware as they are, and --value-scale
says what multiplies a reading into the firmware's int16 code."""
import numpy as np

from ...tcomp import CELSIUS, TempCode, apply, apply_image, load, load_image
from ...errors import InputFileError
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
    p.add_argument("--temp-unit", choices=("c", "raw"), default=None,
                   help="an image's temperature column: c (°C, default) or raw integer codes")
    p.add_argument("--value-scale", type=float, default=None,
                   help="an image's reading scale: firmware int16 = value x this (default 1)")
    p.add_argument("-o", "--output", required=True, metavar="OUT.csv")
    p.set_defaults(func=run)


def is_image(path):
    try:
        with open(path, "rb") as fh:
            return fh.read(4) == b"psig"
    except OSError:
        return False


def run(args):
    image = is_image(args.model)
    if image:
        with open(args.model, "rb") as fh:
            data_img = fh.read()
        c = load_image(data_img, where=args.model)      # the firmware's loader judges it first
        if not (args.temp and args.columns):
            raise InputFileError(f"apply: {args.model} is a coefficient image, which names no columns: "
                                 f"give --temp and --columns")
        temp_col, axes = args.temp, [x.strip() for x in args.columns.split(",") if x.strip()]
        if len(axes) != c.n_axes:
            raise InputFileError(f"apply: the image has {c.n_axes} axes, --columns names {len(axes)}")
        temp_code = TempCode(unit="raw") if args.temp_unit == "raw" else CELSIUS
    else:
        if args.temp_unit is not None or args.value_scale is not None:
            raise InputFileError("apply: --temp-unit and --value-scale are for images; a JSON model "
                                 "carries its own")
        model = load(args.model)
        temp_col = args.temp or model.temp_column
        axes = [x.strip() for x in args.columns.split(",")] if args.columns else model.axes
        if len(axes) != len(model.axes):
            raise InputFileError(f"apply: the model has {len(model.axes)} axes, --columns names {len(axes)}")
    data = read_csv(args.input)
    missing = [col for col in [temp_col] + axes if col not in data]
    if missing:
        raise InputFileError(f"{args.input}: missing column(s) {', '.join(missing)} needed by the model "
                             f"(columns are: {', '.join(data)})")
    readings = [data[a] for a in axes]
    if image:
        corrected, clamped = apply_image(data_img, data[temp_col], readings, temp_code,
                                         args.value_scale or 1.0, where=args.model)
        how = f"the C loader ({c.family} model, {c.code_kind} temperature code)"
    else:
        corrected, clamped = apply(model, data[temp_col], readings, fixed=args.fixed)
        how = f"{model.family} model, {'fixed-point C' if args.fixed else 'float64'}"
    out = dict(data)
    for name, values in zip(axes, corrected):
        out[name + "_comp"] = values
    out["tcomp_clamped"] = clamped.astype(np.int64)
    write_csv(args.output, out)
    n = int(np.count_nonzero(clamped))
    print(f"wrote {args.output}: {len(clamped)} rows through {how}, {n} with the temperature clamped "
          f"to the calibrated range")
