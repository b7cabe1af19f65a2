"""CSV input and output with errors that name the file, row and column.

Parsing is the standard library's csv module; this file only checks what it
returns and turns it into float64 columns.  Output is written to a temporary
file beside the target and renamed into place, so a failure never leaves a
partial file."""
import csv
import math
import os
import tempfile
from contextlib import contextmanager

import numpy as np

from .errors import InputFileError, NonFiniteError, OutputFileError


def read_csv(path, columns=None, allow_nonfinite=False):
    """Read a numeric CSV with a header row.

    Returns a dict name -> float64 ndarray for the requested `columns` (all
    columns when None), in file order.  Raises InputFileError naming the
    file, row (1-based, header is row 1) and column for an empty file, a
    header-only file, a missing column or a non-numeric cell, and
    NonFiniteError for NaN/inf unless `allow_nonfinite`."""
    try:
        with open(path, newline="") as fh:
            rows = list(csv.reader(fh))
    except OSError as exc:
        raise InputFileError(f"{path}: cannot read: {exc.strerror}") from None
    except (UnicodeDecodeError, csv.Error) as exc:
        raise InputFileError(f"{path}: not a text CSV file: {exc}") from None
    rows = [r for r in rows if r and any(c.strip() for c in r)]
    if not rows:
        raise InputFileError(f"{path}: empty file (no header, no data)")
    header = [h.strip() for h in rows[0]]
    if len(rows) == 1:
        raise InputFileError(f"{path}: header only, no data rows")
    wanted = header if columns is None else list(columns)
    for name in wanted:
        if name not in header:
            raise InputFileError(
                f"{path}: missing column '{name}' (columns are: {', '.join(header)})")
    index = {name: header.index(name) for name in wanted}
    out = {name: np.empty(len(rows) - 1) for name in wanted}
    for i, row in enumerate(rows[1:]):
        for name, j in index.items():
            cell = row[j].strip() if j < len(row) else ""
            try:
                value = float(cell)
            except ValueError:
                raise InputFileError(
                    f"{path}: row {i + 2}, column '{name}': not a number: {cell!r}") from None
            if not allow_nonfinite and not math.isfinite(value):
                raise NonFiniteError(
                    f"{path}: row {i + 2}, column '{name}': non-finite value {cell!r}")
            out[name][i] = value
    return out


def check_time_column(path, name, t):
    """Times must be strictly increasing: duplicates and unsorted rows are
    named by their row (header is row 1)."""
    dt = np.diff(t)
    bad = np.flatnonzero(dt <= 0)
    if bad.size:
        i = int(bad[0])
        what = "duplicate" if dt[i] == 0 else "decreasing (unsorted)"
        raise InputFileError(
            f"{path}: row {i + 3}, column '{name}': {what} time {float(t[i + 1])!r} after {float(t[i])!r}")


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextmanager
def atomic_output(path, mode="w", **kwargs):
    """Open a temporary file beside `path`; rename it over `path` only when
    the block finishes without an exception."""
    directory = os.path.dirname(os.path.abspath(path))
    try:
        fd, tmp = tempfile.mkstemp(prefix=".pysig-", dir=directory)
    except OSError as exc:
        raise OutputFileError(f"{path}: cannot write: {exc.strerror}") from exc
    try:
        with os.fdopen(fd, mode, **kwargs) as fh:
            yield fh
        os.chmod(tmp, 0o666 & ~_umask())        # mkstemp makes 0600; give what open() would
        try:
            os.replace(tmp, path)
        except OSError as exc:
            raise OutputFileError(f"{path}: cannot write: {exc.strerror}") from exc
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def write_csv(path, columns):
    """Write a dict name -> 1-D array as CSV, atomically.  Integer-valued
    arrays are written as integers, floats with repr precision."""
    names = list(columns)
    arrays = [np.asarray(columns[n]) for n in names]
    with atomic_output(path, newline="") as fh:
        w = csv.writer(fh)
        w.writerow(names)
        for row in zip(*arrays):
            w.writerow([_fmt(v) for v in row])


def _fmt(v):
    if isinstance(v, (np.integer, int, np.bool_, bool)):
        return str(int(v))
    return repr(float(v))
