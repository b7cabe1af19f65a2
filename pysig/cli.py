"""Command line: `pysig <command> ...`.

Each command lives in its own module under pysig/commands/ and provides
`register(subparsers)`, which adds a parser whose `func(args)` does the work.
A PysigError becomes one line on stderr and the error's own exit status;
output files are written atomically, so a failure leaves none behind."""
import argparse
import importlib
import pkgutil
import sys

from . import commands
from .errors import PysigError


def build_parser():
    parser = argparse.ArgumentParser(prog="pysig", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for info in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
        module = importlib.import_module(f"{commands.__name__}.{info.name}")
        module.register(sub)
    return parser


def main(argv=None):
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        result = args.func(args)
    except PysigError as exc:
        print(f"pysig {args.command}: error: {exc}", file=sys.stderr)
        return exc.exit_status
    return 0 if result is None else int(result)


if __name__ == "__main__":
    sys.exit(main())
