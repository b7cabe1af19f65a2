"""`pysig export model.json --format json|c|image -o FILE [--sequence N] [--name PREFIX] [--compact]`

json: the model, checked and rewritten.  c: a C header with const arrays
and the arguments of sig_tcomp_init_q / sig_tcomp_init_f (a polynomial) or
sig_pwl_init_q16 (a table).  image: the
coefficient image for non-volatile memory (csrc/include/sig_image.h), with the given
sequence number, which sig_tmodel_load_image reads whatever the family: a
table's section (sig_pwl.h), the int32 offset section (sig_tcomp_load_image), or with
--compact the compact section (sig_tcomp16_load_image: int16 multiplicands,
pysig.tcomp._quant.quantize_compact), refused with a RangeError when the model
does not fit the compact form; a model of raw temperature codes adds the
temperature-code section (sig_tmodel.h)."""
from ...tcomp import c_header, image_bytes, load
from ...errors import InputFileError, RangeError
from ...io import atomic_output


def register(sub):
    p = sub.add_parser("export", help="export a model as JSON, a C header or an NVM image",
                       description=__doc__)
    p.add_argument("model", metavar="model.json")
    p.add_argument("--format", choices=("json", "c", "image"), required=True)
    p.add_argument("--sequence", type=int, default=1, help="image sequence number (default 1)")
    p.add_argument("--name", default="tcomp", help="C identifier prefix (default tcomp)")
    p.add_argument("--compact", action="store_true",
                   help="image: the compact int16 form (sig_tcomp16) instead of the int32 one")
    p.add_argument("-o", "--output", required=True)
    p.set_defaults(func=run)


def run(args):
    model = load(args.model)
    if args.compact and args.format != "image":
        raise InputFileError(f"export: --compact applies to --format image only, not {args.format}")
    if args.format == "json":
        model.save(args.output)
    elif args.format == "c":
        if not args.name.isidentifier():
            raise InputFileError(f"export: --name {args.name!r} is not a C identifier")
        text = c_header(model, args.name)
        with atomic_output(args.output) as fh:
            fh.write(text)
    else:
        if not 0 <= args.sequence <= 0xFFFFFFFF:
            raise RangeError(f"export: --sequence {args.sequence} outside 0..4294967295")
        data = image_bytes(model, args.sequence, compact=args.compact,
                           what=f"{args.model}: compact form" if args.compact else args.model)
        with atomic_output(args.output, "wb") as fh:
            fh.write(data)
    print(f"wrote {args.output} ({args.format}{', compact' if args.compact else ''})")
