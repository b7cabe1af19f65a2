"""`pysig fit IN.csv [IN2.csv ...] --temp temp --columns x,y,z [--model auto|poly:N|table:K|table:auto] -o model.json`

Fit a temperature-compensation model per axis, delta(T) = f(T) - f(T0), and
write it as JSON.  `--model auto` (the default) chooses the family
(polynomial or table) and its size by blocked cross-validation over
temperature: the cheapest on the MCU (measured cycles, then bytes) within
5 % of the best CV error; the table of every family and size is printed,
with the CV error per held-out block.  `--order N` is `--model poly:N`
(`--order auto`: `--model poly:auto`).  `--temp-unit raw`: the temperature
column holds the sensor's integer codes (int16 or uint16), which the model
and the firmware use directly; `--temp-scale/--temp-offset` only print °C.
Warns about calibration gaps wider than a CV block and thin blocks
(`--strict` refuses them)."""
import sys

import numpy as np

from ...tcomp import CELSIUS, MAX_FIT_ORDER, first_saturated, fit_model, raw_code, saturated_reading
from ...errors import InputFileError, SaturationError
from ...io import read_csv


def register(sub):
    p = sub.add_parser("fit", help="fit a temperature-compensation model (JSON)", description=__doc__)
    p.add_argument("inputs", nargs="+", metavar="IN.csv")
    p.add_argument("--temp", default="temp", help="temperature column (default: temp)")
    p.add_argument("--columns", required=True, help="1 to 3 reading columns, comma separated")
    p.add_argument("--model", default=None,
                   help="auto (default), poly:N, poly:auto, table:K or table:auto")
    p.add_argument("--order", default=None, help="polynomial order 1..8 or 'auto' (= --model poly:...)")
    p.add_argument("--t0", type=float, default=None,
                   help="reference temperature T0 in the column's unit (default 25 °C, or mid-range)")
    p.add_argument("--temp-unit", choices=("c", "raw"), default="c",
                   help="c: °C (default); raw: the sensor's integer temperature codes")
    p.add_argument("--temp-scale", type=float, default=None, help="raw codes: °C per code (printing only)")
    p.add_argument("--temp-offset", type=float, default=None, help="raw codes: °C at code 0 (printing only)")
    p.add_argument("--value-scale", type=float, default=1.0,
                   help="the firmware's int16 reading = column value x this (default 1)")
    p.add_argument("--prefer", choices=("cycles", "bytes"), default="cycles",
                   help="what 'cheapest' ranks first (default cycles)")
    p.add_argument("--strict", action="store_true", help="refuse coverage gaps instead of warning")
    p.add_argument("-o", "--output", required=True, metavar="model.json")
    p.set_defaults(func=run)


def model_spec(args):
    if args.model is not None and args.order is not None:
        raise InputFileError("fit: give --model or --order, not both")
    if args.order is None:
        return args.model or "auto"
    if args.order == "auto":
        return "poly:auto"
    try:
        return f"poly:{int(args.order)}"
    except ValueError:
        raise InputFileError(f"fit: --order must be an integer 1..{MAX_FIT_ORDER} or 'auto', "
                             f"got {args.order!r}") from None


def read_inputs(paths, temp, columns):
    parts = [read_csv(p, [temp] + columns) for p in paths]
    for path, part in zip(paths, parts):        # name the file and row, not an index in the join
        for c in columns:
            i = first_saturated(part[c])
            if i is not None:
                raise SaturationError(f"{path}: row {i + 2}, column '{c}': {saturated_reading(part[c][i])}")
    return {c: np.concatenate([d[c] for d in parts]) for c in [temp] + columns}


def run(args):
    columns = [c.strip() for c in args.columns.split(",") if c.strip()]
    if not 1 <= len(columns) <= 3:
        raise InputFileError(f"fit: --columns needs 1 to 3 column names, got {args.columns!r}")
    spec = model_spec(args)
    data = read_inputs(args.inputs, args.temp, columns)
    temp = data[args.temp]
    where = ", ".join(args.inputs)
    if args.temp_unit == "raw":
        temp_code = raw_code(temp, args.temp_scale, args.temp_offset, what=f"{where}: column '{args.temp}'")
    else:
        if args.temp_scale is not None or args.temp_offset is not None:
            raise InputFileError("fit: --temp-scale/--temp-offset apply to --temp-unit raw only")
        temp_code = CELSIUS
    result = fit_model(temp, {c: data[c] for c in columns}, spec=spec, t0=args.t0,
                              temp_code=temp_code, value_scale=args.value_scale, strict=args.strict,
                              temp_column=args.temp, prefer=args.prefer, what=where)
    for line in result.lines:
        print(line)
    for w in result.warnings:
        print(f"warning: {w}", file=sys.stderr)
    result.model.save(args.output)
    print(f"wrote {args.output}")
