"""`pysig apply IN.csv --model model.json|image.bin -o OUT.csv [--fixed] [--temp T --columns x,y,z]`

Apply a temperature-compensation model: OUT.csv is IN.csv's columns plus
<axis>_comp for each model axis and `tcomp_clamped` (1 where the temperature
was outside the calibrated range and was clamped to it).  The default is the
float64 model; --fixed runs the firmware's fixed-point C code on the model's
image (sig_tmodel_load_image + sig_tmodel_apply: temperature rounded to the
model's int16 unit, reading = round(value x value scale) within int16).
Given a coefficient image (`pysig export --format image`) the firmware's C
loader reads it, whatever model family it holds.  The model file or image
says which temperature source (°C or raw codes) and value scale it was
fitted with, and apply uses them: --temp-unit and --value-scale are needed
only for an image of an older pysig that does not record them, and a flag
that contradicts the file is refused.  An image names no columns: give
--temp and --columns.  A run in which most rows fall outside the
calibrated range is refused (the temperature column or its unit is almost
surely not the one the model was fitted on)."""
import numpy as np

from ...tcomp import (TempCode, apply, apply_image, calibrated_range, image_units, load, load_image,
                      require_mostly_in_range)
from ...errors import InputFileError
from ...io import read_csv, write_csv


def register(sub):
    p = sub.add_parser("apply", help="apply a temperature-compensation model to a CSV",
                       description=__doc__)
    p.add_argument("input", metavar="IN.csv")
    p.add_argument("--model", required=True, metavar="model.json")
    p.add_argument("--fixed", action="store_true", help="use the fixed-point C path")
    p.add_argument("--temp", help="temperature column (default: the model's)")
    p.add_argument("--columns", help="reading columns, comma separated (default: the model's axes)")
    p.add_argument("--temp-unit", choices=("c", "raw"), default=None,
                   help="c (°C) or raw codes: only for an image that does not record it (default: the file's)")
    p.add_argument("--value-scale", type=float, default=None,
                   help="firmware int16 = round(value x this): only for an image that does not record it "
                        "(default: the file's)")
    p.add_argument("-o", "--output", required=True, metavar="OUT.csv")
    p.set_defaults(func=run)


def is_image(path):
    try:
        with open(path, "rb") as fh:
            return fh.read(4) == b"psig"
    except OSError:
        return False


def _resolve_units(args, temp_code, value_scale, where):
    """The file's temperature source and value scale, checked against the
    flags: a flag may repeat the file, or fill what an older image does not
    record, never contradict it."""
    if args.temp_unit is not None and args.temp_unit != temp_code.unit:
        raise InputFileError(f"apply: --temp-unit {args.temp_unit} contradicts {where}, fitted on "
                             f"{'raw sensor codes' if temp_code.unit == 'raw' else '°C'}: leave the flag out")
    if args.value_scale is not None:
        if value_scale is not None and not np.isclose(args.value_scale, value_scale, rtol=1e-6, atol=0):
            raise InputFileError(f"apply: --value-scale {args.value_scale:g} contradicts {where}, fitted "
                                 f"with value scale {value_scale:g}: leave the flag out")
        value_scale = args.value_scale
    return value_scale if value_scale is not None else 1.0


def run(args):
    image = is_image(args.model)
    if image:
        with open(args.model, "rb") as fh:
            data_img = fh.read()
        c = load_image(data_img, where=args.model)      # the firmware's loader judges it first
        units = image_units(data_img, where=args.model)
        if not (args.temp and args.columns):
            raise InputFileError(f"apply: {args.model} is a coefficient image, which names no columns: "
                                 f"give --temp and --columns")
        temp_col, axes = args.temp, [x.strip() for x in args.columns.split(",") if x.strip()]
        if len(axes) != c.n_axes:
            raise InputFileError(f"apply: the image has {c.n_axes} axes, --columns names {len(axes)}")
        temp_code = units.temp_code
        if units.value_scale is None and args.temp_unit == "raw" and temp_code.unit != "raw":
            temp_code = TempCode(unit="raw")            # an older image: int16 codes, no section said so
        value_scale = _resolve_units(args, temp_code, units.value_scale, args.model)
        expected = f"the image expects {'raw sensor codes' if temp_code.unit == 'raw' else '°C'}"
    else:
        model = load(args.model)
        temp_col = args.temp or model.temp_column
        axes = [x.strip() for x in args.columns.split(",")] if args.columns else model.axes
        if len(axes) != len(model.axes):
            raise InputFileError(f"apply: the model has {len(model.axes)} axes, --columns names {len(axes)}")
        temp_code = model.temp_code
        _resolve_units(args, temp_code, model.value_scale, args.model)
        lo, hi = calibrated_range(model)
        expected = f"the model's calibrated range is {temp_code.label(lo)} .. {temp_code.label(hi)}"
    data = read_csv(args.input)
    missing = [col for col in [temp_col] + axes if col not in data]
    if missing:
        raise InputFileError(f"{args.input}: missing column(s) {', '.join(missing)} needed by the model "
                             f"(columns are: {', '.join(data)})")
    readings = [data[a] for a in axes]
    if image:
        corrected, clamped = apply_image(data_img, data[temp_col], readings, temp_code, value_scale,
                                         where=args.model)
        how = (f"the C loader ({c.family} model, {c.code_kind} temperature code, value scale "
               f"{value_scale:g}{'' if units.value_scale is not None else ' given: the image does not record it'})")
    else:
        corrected, clamped = apply(model, data[temp_col], readings, fixed=args.fixed)
        how = f"{model.family} model, {'fixed-point C' if args.fixed else 'float64'}"
    require_mostly_in_range(clamped, data[temp_col], temp_code, temp_col, expected, where=args.input)
    out = dict(data)
    for name, values in zip(axes, corrected):
        out[name + "_comp"] = values
    out["tcomp_clamped"] = clamped.astype(np.int64)
    write_csv(args.output, out)
    n = int(np.count_nonzero(clamped))
    print(f"wrote {args.output}: {len(clamped)} rows through {how}, {n} with the temperature clamped "
          f"to the calibrated range")
