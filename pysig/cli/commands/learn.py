"""`pysig learn LOG --temp T --columns x[,y,z] [--still COL] [--temp-unit raw] [--start model.json|.bin] -o DIR`

Replay a field log through the device learner (the C code, as firmware runs
it): the model in use corrects every sample, still samples teach the
learner, a solve runs every --solve-every samples and a model it commits
(validated on held-out temperature bins, better than the one in use by the
margin) is loaded at once.  Writes DIR/replay.csv (the input columns,
<axis>_comp, still, stale, extrapolated, model_sequence), DIR/model.bin
(the last committed image: `pysig apply --model DIR/model.bin`),
DIR/commits.json (every solve and commit) and DIR/learn.png.  Readings are
int16 sensor codes (the learner learns offsets up to +-2047 LSB); without
--still every sample counts as still; the bins are chosen to cover the log
and the start model's range."""
import numpy as np

from ...errors import InputFileError, ModelFileError, RangeError
from ...io import read_csv
from ...learn import LearnConfig, replay, write_outputs
from ...tcomp import CELSIUS, image_bytes, load, raw_code


def register(sub):
    p = sub.add_parser("learn", help="replay a field log through the device learner", description=__doc__)
    p.add_argument("log", metavar="LOG")
    p.add_argument("--temp", required=True, help="temperature column")
    p.add_argument("--columns", required=True, help="reading columns, comma separated (1..3)")
    p.add_argument("--still", help="stillness column (non-zero: still); default every sample")
    p.add_argument("--temp-unit", choices=("c", "raw"), default="c",
                   help="temperature column in °C (default) or raw integer codes")
    p.add_argument("--start", metavar="model.json|.bin", help="the model in use at the start")
    p.add_argument("--solve-every", type=int, default=60, help="samples between solves (default 60)")
    p.add_argument("--period", type=int, default=24 * 60, help="samples between commits (default 1440)")
    p.add_argument("--min-count", type=int, default=30, help="still samples that cover a bin (default 30)")
    p.add_argument("-o", "--output", required=True, metavar="DIR")
    p.set_defaults(func=run)


def _temp_code(args, temp):
    if args.temp_unit == "c":
        return CELSIUS
    return raw_code(temp)


def _start_image(path, what):
    if path is None:
        return None
    try:
        with open(path, "rb") as fh:
            data = fh.read()
    except OSError as e:        # as `apply --model` says it
        raise ModelFileError(f"{path}: cannot read: {e.strerror}") from None
    if data[:4] == b"psig":
        return data
    return image_bytes(load(path), what=what)


def run(args):
    axes = [c.strip() for c in args.columns.split(",") if c.strip()]
    if not 1 <= len(axes) <= 3:
        raise InputFileError(f"learn: --columns names {len(axes)} columns; the learner takes 1 to 3")
    wanted = [args.temp, *axes] + ([args.still] if args.still else [])
    data = read_csv(args.log, columns=wanted)
    temp = data[args.temp]
    code = _temp_code(args, temp)
    t = code.to_t(temp, what=f"{args.log}: column {args.temp}")
    raw = np.stack([data[a] for a in axes], 1)
    # rows counted as the CSV reader does: the header is row 1
    frac = np.flatnonzero(raw != np.rint(raw))
    if frac.size:
        i = int(frac[0])
        raise RangeError(f"{args.log}: row {i // len(axes) + 2}, column '{axes[i % len(axes)]}': "
                         f"{float(raw.flat[i]):g} is not an integer sensor code; the learner takes int16 codes")
    wide = np.flatnonzero((raw < -32768) | (raw > 32767))
    if wide.size:
        i = int(wide[0])
        raise RangeError(f"{args.log}: row {i // len(axes) + 2}, column '{axes[i % len(axes)]}': "
                         f"{float(raw.flat[i]):g} does not fit the int16 reading the learner takes")
    still = data[args.still] != 0 if args.still else np.ones(len(t), dtype=bool)
    start = _start_image(args.start, "learn")
    config = LearnConfig.for_log(t, len(axes), start, code_kind=code.code_kind, period=args.period,
                                 min_count=args.min_count)
    try:
        result = replay(t, raw.astype(np.int64), still, config, start_image=start, solve_every=args.solve_every)
    except ModelFileError as e:     # the start image: name the file
        raise ModelFileError(f"{args.start}: {e}") from None
    paths = write_outputs(result, args.output, axes, raw, temp, args.temp, still)
    print(f"learn: {len(t)} samples, {int(still.sum())} still; bins {config.n_bins} x {1 << config.bin_shift} "
          f"from t={config.t_base}; {len(result.commits)} commit(s)"
          + (f", last sequence {result.commits[-1]['sequence']}" if result.commits else "")
          + f"; stale on {int(result.stale.sum())} samples")
    for p in paths.values():
        print(f"  wrote {p}")
