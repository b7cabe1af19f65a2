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

    Parameters
    ----------
    path : path-like
        The CSV file.
    columns : sequence of str, optional
        The columns to return (all when None).
    allow_nonfinite : bool, optional
        Accept NaN and inf cells.

    Returns
    -------
    dict
        name -> float64 ndarray, in file order.

    Raises
    ------
    InputFileError
        Naming the file, row (1-based, the header is row 1) and column: an
        unreadable or empty file, a header-only file, a missing column, a
        non-numeric cell.
    NonFiniteError
        A NaN or inf cell, unless `allow_nonfinite`.

    Examples
    --------
    >>> _ = open("in.csv", "w").write("t,counts\\n0.0,1000\\n0.1,1002\\n")
    >>> read_csv("in.csv", ["counts"])
    {'counts': array([1000., 1002.])}
    >>> _ = open("bad.csv", "w").write("t,counts\\n0.0,1000\\n0.1,x\\n")
    >>> read_csv("bad.csv")
    Traceback (most recent call last):
        ...
    pysig.errors.InputFileError: bad.csv: row 3, column 'counts': not a number: 'x'
    """
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
    """Check that a time column read by `read_csv` strictly increases.

    Parameters
    ----------
    path : path-like
        The file the column came from (for the message).
    name : str
        The column's name (for the message).
    t : ndarray
        The times.

    Raises
    ------
    InputFileError
        A duplicate or decreasing time, named by its row (the header is
        row 1).

    Examples
    --------
    >>> import numpy as np
    >>> check_time_column("in.csv", "t", np.array([0.0, 0.1, 0.2]))
    >>> check_time_column("in.csv", "t", np.array([0.0, 0.1, 0.1]))
    Traceback (most recent call last):
        ...
    pysig.errors.InputFileError: in.csv: row 4, column 't': duplicate time 0.1 after 0.1
    """
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
    """Write a file all or nothing: a context manager that opens a temporary
    file beside `path` and renames it over `path` only when the block
    finishes without an exception (else the temporary is removed and an
    existing `path` is left as it was).

    Parameters
    ----------
    path : path-like
        The file to write.
    mode : str, optional
        "w" (text) or "wb" (binary).
    **kwargs
        Passed to `open` (newline, encoding, ...).

    Yields
    ------
    file object
        The temporary file.

    Raises
    ------
    OutputFileError
        The directory cannot be written or the rename fails.

    Examples
    --------
    >>> with atomic_output("out.txt") as fh:
    ...     _ = fh.write("done\\n")
    >>> open("out.txt").read()
    'done\\n'
    >>> with atomic_output("out.txt") as fh:
    ...     _ = fh.write("half")
    ...     raise ValueError("stopped half way")
    Traceback (most recent call last):
        ...
    ValueError: stopped half way
    >>> open("out.txt").read()             # unchanged
    'done\\n'
    """
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
    """Write columns as a CSV file, atomically (see `atomic_output`).

    Parameters
    ----------
    path : path-like
        The file to write.
    columns : dict
        name -> 1-D array, all of one length.  Integer and bool arrays are
        written as integers, floats with repr precision (they read back
        exactly).

    Raises
    ------
    OutputFileError
        The file cannot be written; nothing is left behind.

    Examples
    --------
    >>> import numpy as np
    >>> write_csv("out.csv", {"t": np.array([0.0, 0.1]), "stable": np.array([False, True])})
    >>> print(open("out.csv").read(), end="")
    t,stable
    0.0,0
    0.1,1
    """
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
