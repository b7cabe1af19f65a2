"""Command line: `pysig <command> ...`.

Each command lives in its own module under pysig/cli/commands/ and provides
`register(subparsers)`, which adds a parser whose `func(args)` does the work.
A PysigError becomes one line on stderr and the error's own exit status;
output files are written atomically, so a failure leaves none behind."""
import argparse
import importlib
import os
import pkgutil
import sys

from . import commands
from .. import __version__
from ..errors import PysigError
from ..io import csv_delimiter

DELIMITER_NAMES = {"tab": "\t", "\\t": "\t"}       # how a tab is typed on a command line


def command_names():
    return sorted(info.name for info in pkgutil.iter_modules(commands.__path__))


def build_parser(only=None):
    """The full parser, or (`only`) one command's: importing a command pulls
    in what it needs (refine loads statsmodels, ~1.5 s), so `pysig filter`
    imports only the filter command."""
    parser = argparse.ArgumentParser(prog="pysig", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"pysig {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in ([only] if only else command_names()):
        module = importlib.import_module(f"{commands.__name__}.{name}")
        module.register(sub)
    for command in sub.choices.values():        # every command reads CSV through pysig.io
        command.add_argument("--delimiter", default=None,
                             help="CSV delimiter: ',', ';' or 'tab' (default: detected from the header row)")
    return parser


def _requested_command(argv):
    """The command named by the first non-option argument, if it is one."""
    for arg in argv:
        if not arg.startswith("-"):
            name = arg.replace("-", "_")            # calibrate-scale lives in calibrate_scale.py
            return name if name in command_names() else None
    return None


def main(argv=None):
    if argv is None:
        argv = sys.argv[1:]
    parser = build_parser(_requested_command(argv))
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        with csv_delimiter(DELIMITER_NAMES.get(args.delimiter, args.delimiter)):
            result = args.func(args)
    except PysigError as exc:
        print(f"pysig {args.command}: error: {exc}", file=sys.stderr)
        return exc.exit_status
    return 0 if result is None else int(result)


def entry():
    """The `pysig` program: main(), its output flushed, then the process ends
    at once with main's status.  The interpreter's teardown is skipped: a
    native thread pool (pyarrow's) still winding down while the interpreter
    exits can abort the process after the work is done and its files are
    written ("terminate called without an active exception", exit -6;
    apache/arrow#34314), which would turn a good run, or a refused one, into
    a crash.  pysig.io already hands pyarrow no Python object on its normal
    paths (the known trigger); this is the second guard.  Every output is
    closed before main returns (atomic writes), so nothing is left for the
    teardown to do."""
    status = main()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):       # a closed pipe: nothing more to deliver
            pass
    os._exit(status)


if __name__ == "__main__":
    entry()
