"""Tables in and out (CSV or Parquet by the file's suffix) with errors that
name the file, row and column.

Parsing and writing are pyarrow's (multi-threaded C++); this module checks
what it returns.  When a conversion fails, a vectorised scan of that column
finds the first offending cell, so the message still says where.  Rows are
counted as in a spreadsheet: in a CSV the header is row 1 and the first data
row is row 2; a Parquet file has no header row, so its first row is row 1.

CSV as people export them (the one place these rules live):

* a UTF-8 byte-order mark (Excel's "CSV UTF-8") is stripped;
* the delimiter is detected from the header row: the most frequent of
  ``,`` ``;`` and tab (European spreadsheets write ``;``), unless one is
  forced (`csv_delimiter`, the CLI's ``--delimiter``); decimal commas are
  not read (such a cell is "not a number", named by row and column);
* a missing value is an empty cell or a cell holding ``nan``, ``NaN``,
  ``NAN``, ``-nan``, ``NA`` or ``N/A`` (and a null in Parquet): every one
  is the same missing value, NaN in the returned column, so every command
  treats it alike: commands that need each value refuse it (NonFiniteError,
  "missing value (empty or nan)", naming row and column), and the float
  filter replaces it as an impulse and counts it.

Output is written to a temporary file beside the target and renamed into
place, so a failure never leaves a partial file (see `atomic_path`).
Streaming (bounded memory, chunk by chunk) is in pysig.io_stream."""

__all__ = ["csv_delimiter", "MISSING_VALUES", "MISSING_TEXT", "read_csv", "read_table", "read_header", "write_csv", "read_json", "write_json", "atomic_output", "atomic_path", "check_time_column", "read_time_column", "TIME_UNITS", "check_finite", "numeric_column", "from_numpy", "to_table", "row_label", "is_parquet"]
import csv
import json
import os
import re
import tempfile
from contextlib import contextmanager
from contextvars import ContextVar

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.csv as pcsv
import pyarrow.parquet as pq

from .errors import InputFileError, ModelFileError, NonFiniteError, OutputFileError

PARQUET_SUFFIXES = (".parquet", ".pq")
DELIMITERS = (",", ";", "\t")
MISSING_VALUES = ["", "nan", "NaN", "NAN", "-nan", "NA", "N/A"]
MISSING_TEXT = "missing value (empty or nan)"
_forced_delimiter = ContextVar("pysig_csv_delimiter", default=None)


@contextmanager
def csv_delimiter(delimiter):
    """Within the block, read every CSV with `delimiter` (None: detect it).

    Examples
    --------
    >>> _ = open("semi.csv", "w").write("t;x\\n0;1.5\\n1;2.5\\n")
    >>> read_csv("semi.csv")["x"]                  # detected
    array([1.5, 2.5])
    >>> with csv_delimiter(","):
    ...     read_header("semi.csv")
    ['t;x']
    """
    if delimiter is not None and delimiter not in DELIMITERS:
        raise InputFileError(f"--delimiter must be ',', ';' or 'tab', got {delimiter!r}")
    token = _forced_delimiter.set(delimiter)
    try:
        yield
    finally:
        _forced_delimiter.reset(token)


def detect_delimiter(line):
    """The forced delimiter, else the most frequent of DELIMITERS in the
    header `line` (',' when it holds none: a one-column file)."""
    forced = _forced_delimiter.get()
    if forced is not None:
        return forced
    counts = [line.count(d) for d in DELIMITERS]
    return DELIMITERS[counts.index(max(counts))] if max(counts) else ","


def is_parquet(path):
    """True when `path` names a Parquet file (by its suffix)."""
    return str(path).lower().endswith(PARQUET_SUFFIXES)


def row_label(path, index):
    """The row number a user sees for 0-based data row `index`."""
    return int(index) + (1 if is_parquet(path) else 2)


# ---- header ------------------------------------------------------------------
def _csv_header(path):
    """(names, lines before the data, delimiter): the first non-blank line,
    parsed; a byte-order mark is not part of the first name."""
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            skipped = 0
            for line in fh:
                skipped += 1
                if line.strip():
                    delim = detect_delimiter(line)
                    return [h.strip() for h in next(csv.reader([line], delimiter=delim))], skipped, delim
    except OSError as exc:
        raise InputFileError(f"{path}: cannot read: {exc.strerror}") from None
    except (UnicodeDecodeError, csv.Error) as exc:
        raise InputFileError(f"{path}: not a text CSV file: {exc}") from None
    raise InputFileError(f"{path}: empty file (no header, no data)")


def _parquet_file(path):
    try:
        return pq.ParquetFile(path)
    except OSError as exc:
        if not os.path.exists(path):
            raise InputFileError(f"{path}: cannot read: no such file") from None
        raise InputFileError(f"{path}: not a Parquet file: {exc}") from None
    except pa.ArrowException as exc:
        raise InputFileError(f"{path}: not a Parquet file: {exc}") from None


def read_header(path):
    """Column names of a CSV (its header row) or Parquet file (its schema).
    InputFileError for an unreadable or empty file, or a name given twice
    (which of the two columns is meant cannot be known)."""
    if is_parquet(path):
        names = list(_parquet_file(path).schema_arrow.names)
    else:
        names, _, _ = _csv_header(path)
    seen = set()
    for j, name in enumerate(names):
        if name in seen:
            raise InputFileError(f"{path}: row 1 (header), column {j + 1}: the name '{name}' is given "
                                 f"twice (columns {names.index(name) + 1} and {j + 1}); rename one")
        seen.add(name)
    return names


def require_columns(path, header, wanted):
    for name in wanted:
        if name not in header:
            raise InputFileError(f"{path}: row 1 (header): missing column '{name}' "
                                 f"(columns are: {', '.join(header)})")


# ---- locating a bad cell -----------------------------------------------------
def first_unconvertible(strings, to=None):
    """Index of the first cell of a string array that does not convert to
    `to` (float64 by default; as pyarrow converts), or None.  Halves the
    range with one vectorised cast per step: O(n) work, no Python loop over
    cells.  For float64 a missing value (MISSING_VALUES) converts (to NaN)."""
    strings = pc.utf8_trim_whitespace(strings)
    if to is None:
        to = pa.float64()
        strings = pc.if_else(pc.is_in(strings, pa.array(MISSING_VALUES)), "nan", strings)

    def ok(lo, hi):
        try:
            pc.cast(strings.slice(lo, hi - lo), to)
            return True
        except (pa.ArrowInvalid, pa.ArrowNotImplementedError):
            return False
    lo, hi = 0, len(strings)
    if ok(lo, hi):
        return None
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if ok(lo, mid):
            lo = mid
        else:
            hi = mid
    return lo


def not_a_number(path, index, name, cell):
    return InputFileError(f"{path}: row {row_label(path, index)}, column '{name}': "
                          f"not a number: {cell!r}")


# ---- numpy <-> arrow without pandas -----------------------------------------
# pyarrow's pa.array(ndarray) and Array.to_numpy() import pandas when it is
# installed (~0.4 s and ~50 MB on every run); numeric buffers need neither.
def from_numpy(a):
    """A pyarrow Array over a 1-D numeric ndarray (booleans as int64 0/1)."""
    a = np.asarray(a)
    if a.dtype == bool:
        a = a.astype(np.int64)
    if a.dtype.kind not in "iuf":
        return pa.array(a)
    a = np.ascontiguousarray(a)
    return pa.Array.from_buffers(pa.from_numpy_dtype(a.dtype), a.size, [None, pa.py_buffer(a)])


def float64_values(array):
    """The values of a null-free numeric pyarrow (Chunked)Array as a float64 ndarray."""
    if isinstance(array, pa.ChunkedArray):
        array = array.chunk(0) if array.num_chunks == 1 else array.combine_chunks()
    if array.type != pa.float64():
        array = array.cast(pa.float64())
    return np.frombuffer(array.buffers()[1], dtype=np.float64, count=len(array), offset=array.offset * 8)


# ---- numeric columns ---------------------------------------------------------
def numeric_column(path, name, array, offset=0):
    """A pyarrow column as float64 numpy, a missing value (null) as NaN;
    InputFileError (file, row, column) for a type that is not numbers."""
    typ = array.type
    if not (pa.types.is_floating(typ) or pa.types.is_integer(typ) or pa.types.is_decimal(typ)):
        if pa.types.is_string(typ) or pa.types.is_large_string(typ):
            i = first_unconvertible(array)
            if i is not None:
                raise not_a_number(path, offset + i, name, array[i].as_py())
            array = pc.cast(pc.utf8_trim_whitespace(array), pa.float64())
        else:
            raise InputFileError(f"{path}: column '{name}' holds {typ}, not numbers "
                                 f"(expected an integer or floating-point column)")
    if array.null_count:                        # a missing value: NaN, as an empty or nan cell
        array = pc.fill_null(array.cast(pa.float64()), float("nan"))
    return float64_values(array)


def check_finite(path, name, x, offset=0):
    """NonFiniteError naming the first missing value (NaN) or infinity."""
    bad = np.flatnonzero(~np.isfinite(x))
    if bad.size:
        i = int(bad[0])
        what = MISSING_TEXT if np.isnan(x[i]) else f"non-finite value {float(x[i])!r}"
        raise NonFiniteError(f"{path}: row {row_label(path, offset + i)}, column '{name}': {what}")


# ---- whole tables ------------------------------------------------------------
def csv_options(path, header, skipped, numeric, strings=(), block_size=None, threads=True,
                delimiter=","):
    """pyarrow CSV options (read, convert, parse): our stripped header,
    `numeric` columns as float64 with MISSING_VALUES as null (missing),
    `strings` as text, other columns inferred; the file's delimiter."""
    types = {n: pa.float64() for n in numeric}
    types.update({n: pa.string() for n in strings})
    read = pcsv.ReadOptions(column_names=header, skip_rows=skipped, use_threads=threads,
                            **({"block_size": block_size} if block_size else {}))
    convert = pcsv.ConvertOptions(column_types=types, null_values=MISSING_VALUES, strings_can_be_null=False,
                                  quoted_strings_can_be_null=False)
    parse = pcsv.ParseOptions(delimiter=delimiter)
    return read, convert, parse


def _short_row(path, header, row, expected, actual):
    """InputFileError for a row whose cell count differs from the header's."""
    if actual < expected:
        return InputFileError(f"{path}: row {row}, column '{header[actual]}': not a number: '' (the row has "
                              f"{actual} cells, the header {expected})")
    return InputFileError(f"{path}: row {row}: {actual} cells, the header has {expected}")


# pyarrow's message for a row of the wrong length; it carries the row number
# (counted like ours: the header is row 1) only when read on one thread
_WRONG_CELL_COUNT = re.compile(r"Row #(\d+): Expected (\d+) columns, got (\d+)")


def short_row_error(path, header, skipped, delimiter):
    """The InputFileError naming the first row whose cell count differs from
    the header's, or None.  Only called after a read failed: it reads every
    column as text on one thread, so pyarrow's message says which row.
    pyarrow's invalid-row callback would say it too, but no Python object may
    be handed to pyarrow: its worker threads release what they hold after the
    read returns, and one released while the interpreter exits takes the GIL
    there and aborts the process after the work is done ("terminate called
    without an active exception"; core dumps showed the callback released on
    a pool thread, apache/arrow#34314)."""
    read, convert, parse = csv_options(path, header, skipped, (), strings=header, threads=False,
                                       delimiter=delimiter)
    try:
        with pcsv.open_csv(path, read_options=read, convert_options=convert, parse_options=parse) as reader:
            for _ in reader:
                pass
    except pa.ArrowInvalid as exc:
        found = _WRONG_CELL_COUNT.search(str(exc))
        if found:
            return _short_row(path, header, *(int(g) for g in found.groups()))
    return None


def _read_csv_table(path, header, skipped, delimiter, wanted, numeric, strings):
    read, convert, parse = csv_options(path, header, skipped, numeric, strings, delimiter=delimiter)
    convert.include_columns = list(wanted)
    try:
        return pcsv.read_csv(path, read_options=read, convert_options=convert, parse_options=parse)
    except pa.ArrowInvalid as exc:
        short = short_row_error(path, header, skipped, delimiter)
        if short is not None:
            raise short from None
        raise locate_conversion_error(path, header, skipped, delimiter, numeric, exc) from None


def locate_conversion_error(path, header, skipped, delimiter, numeric, exc):
    """The named error for a failed CSV conversion: scan the numeric columns
    as text for the first cell that is not a number (a missing value is not
    an error here)."""
    for name in numeric:
        read, convert, parse = csv_options(path, header, skipped, (), strings=(name,), delimiter=delimiter)
        convert.include_columns = [name]
        texts = pcsv.read_csv(path, read_options=read, convert_options=convert, parse_options=parse)[name]
        offset = 0
        for chunk in texts.chunks:
            i = first_unconvertible(chunk)
            if i is not None:
                return not_a_number(path, offset + i, name, chunk[i].as_py())
            offset += len(chunk)
    return InputFileError(f"{path}: cannot parse: {exc}")


def read_table(path, columns=None, numeric=None, strings=()):
    """Read a CSV or Parquet file into a pyarrow Table.

    Parameters
    ----------
    path : str or path-like
        ``.parquet``/``.pq`` is read as Parquet, anything else as CSV with a
        header row.
    columns : list of str, optional
        Columns to return, in this order (default: all, in file order).
    numeric : list of str, optional
        Columns that must hold numbers: returned as float64; default: all of
        `columns` that are not in `strings`.
    strings : list of str, optional
        Columns read as text (CSV) or kept as stored (Parquet).

    Raises
    ------
    InputFileError
        Unreadable, empty or header-only file, a name given twice in the
        header, a missing column, a non-numeric cell or a Parquet column of
        the wrong type: the message names the file, row and column.
    """
    header = read_header(path)
    wanted = list(header if columns is None else columns)
    require_columns(path, header, wanted)
    if numeric is None:
        numeric = [n for n in wanted if n not in strings]
    if is_parquet(path):
        try:
            table = _parquet_file(path).read(columns=wanted)
        except (OSError, pa.ArrowException) as exc:
            raise InputFileError(f"{path}: cannot read Parquet data: {exc}") from None
        out = {n: table[n] for n in wanted}
        for n in numeric:
            out[n] = from_numpy(numeric_column(path, n, out[n]))
        for n in strings:
            if not (pa.types.is_string(out[n].type) or pa.types.is_integer(out[n].type)):
                raise InputFileError(f"{path}: column '{n}' holds {out[n].type}, expected text or integers")
        table = pa.table(out)
    else:
        _, skipped, delimiter = _csv_header(path)
        table = _read_csv_table(path, header, skipped, delimiter, wanted, numeric, strings)
        table = table.select(wanted)
    if table.num_rows == 0:
        raise InputFileError(f"{path}: header only, no data rows")
    return table


def read_csv(path, columns=None, allow_nonfinite=False):
    """Read numeric columns of a CSV or Parquet file (by its suffix).

    Parameters
    ----------
    path : path-like
        ``.parquet``/``.pq`` is read as Parquet, anything else as CSV with a
        header row.
    columns : sequence of str, optional
        The columns to return, in this order (all, in file order, when None).
    allow_nonfinite : bool, optional
        Accept NaN and inf cells.

    Returns
    -------
    dict
        name -> float64 ndarray, in the order asked.

    Raises
    ------
    InputFileError
        Naming the file, row (1-based; a CSV's header is row 1, a Parquet
        file's first row is row 1) and column: an unreadable or empty file,
        a header-only file, a missing column or a name given twice, a
        non-numeric or empty cell.
    NonFiniteError
        A missing value (an empty or nan cell) or an inf cell, unless
        `allow_nonfinite` (then a missing value is NaN).

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
    table = read_table(path, columns)
    out = {}
    for name in table.column_names:
        x = numeric_column(path, name, table[name])
        if not allow_nonfinite:
            check_finite(path, name, x)
        out[name] = x
    return out


def check_time_column(path, name, t):
    """Check that a time column read by `read_csv` strictly increases.

    Parameters
    ----------
    path : path-like
        The file the column came from (for the message and the row
        numbering: a CSV's header is row 1, a Parquet file has none).
    name : str
        The column's name (for the message).
    t : ndarray
        The times.

    Raises
    ------
    InputFileError
        A duplicate or decreasing time, named by its row.

    Examples
    --------
    >>> import numpy as np
    >>> check_time_column("in.csv", "t", np.array([0.0, 0.1, 0.2]))
    >>> check_time_column("in.csv", "t", np.array([0.0, 0.1, 0.1]))
    Traceback (most recent call last):
        ...
    pysig.errors.InputFileError: in.csv: row 4, column 't': duplicate time 0.1 after 0.1
    >>> check_time_column("in.parquet", "t", np.array([0.0, 0.2, 0.1]))
    Traceback (most recent call last):
        ...
    pysig.errors.InputFileError: in.parquet: row 3, column 't': decreasing (unsorted) time 0.1 after 0.2
    """
    dt = np.diff(t)
    bad = np.flatnonzero(dt <= 0)
    if bad.size:
        i = int(bad[0])
        what = "duplicate" if dt[i] == 0 else "decreasing (unsorted)"
        raise InputFileError(
            f"{path}: row {row_label(path, i + 1)}, column '{name}': {what} time "
            f"{float(t[i + 1])!r} after {float(t[i])!r}")


TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6}


def _as_seconds(timestamps):
    """A pyarrow timestamp array as float64 seconds since 1970 (its own clock
    when it has no zone)."""
    micro = pc.cast(timestamps.cast(pa.timestamp("us", tz=timestamps.type.tz)), pa.int64())
    return float64_values(micro) * 1e-6


def _parse_date_times(path, name, texts):
    """Seconds of a text column of ISO 8601 date-times: all without a zone
    (read on their own clock) or all with one (converted to UTC)."""
    trimmed = pc.utf8_trim_whitespace(texts)
    naive, zoned = pa.timestamp("us"), pa.timestamp("us", tz="UTC")
    first_bad = {}
    for typ in (naive, zoned):
        first_bad[typ] = first_unconvertible(trimmed, typ)
        if first_bad[typ] is None:
            return _as_seconds(pc.cast(trimmed, typ))
    # the cells before first_bad[typ] all read as typ, and no cell reads as
    # both: so the later first_bad is the first cell that the form of the
    # cells before it does not read; if the other form reads it, the column
    # mixes the two, else that cell is the bad one
    j = max(first_bad.values())
    cell_j = trimmed.slice(j, 1)
    if any(first_unconvertible(cell_j, typ) is None for typ in (naive, zoned)):
        raise InputFileError(f"{path}: column '{name}' mixes date-times with a zone (Z, +02:00) and "
                             f"without one: give one kind of time throughout")
    cell = trimmed[j].as_py()
    if cell is None or cell in MISSING_VALUES:
        raise NonFiniteError(f"{path}: row {row_label(path, j)}, column '{name}': {MISSING_TEXT}")
    raise InputFileError(f"{path}: row {row_label(path, j)}, column '{name}': not a number nor an "
                         f"ISO 8601 date-time (2026-03-01T12:00:00, optional fraction and zone): {cell!r}")


def read_time_column(path, name, unit=None):
    """Read a time column in seconds: numbers (in `unit`) or date-times.

    Parameters
    ----------
    path : path-like
        A CSV or Parquet file.
    name : str
        The time column.
    unit : {"s", "ms", "us"}, optional
        The unit of a numeric column (seconds when None).  Date-times carry
        their own unit, so giving "ms" or "us" for them is an error.

    Returns
    -------
    (ndarray, str)
        float64 seconds (date-times: since 1970, on their own clock when
        they carry no zone, in UTC when they do) and the column's kind,
        "number" or "date-time".  Not checked for order: see
        `check_time_column`.

    Raises
    ------
    InputFileError
        A cell that is neither a number nor an ISO 8601 date-time, a column
        mixing kinds, or a unit other than seconds given for date-times.
    NonFiniteError
        A missing or infinite time.

    Examples
    --------
    >>> _ = open("log.csv", "w").write("time,x\\n2026-03-01T12:00:00,1\\n2026-03-01T12:00:02.5,2\\n")
    >>> t, kind = read_time_column("log.csv", "time")
    >>> kind, t - t[0]
    ('date-time', array([0. , 2.5]))
    """
    table = read_table(path, [name], numeric=[])
    column = table[name]
    column = column.chunk(0) if column.num_chunks == 1 else column.combine_chunks()
    typ = column.type
    textual = pa.types.is_string(typ) or pa.types.is_large_string(typ)
    if column.null_count and (textual or pa.types.is_timestamp(typ) or pa.types.is_date(typ)):
        i = int(np.flatnonzero(np.asarray(column.is_null()))[0])
        raise NonFiniteError(f"{path}: row {row_label(path, i)}, column '{name}': {MISSING_TEXT}")
    if pa.types.is_timestamp(typ) or pa.types.is_date(typ):
        kind, t = "date-time", _as_seconds(pc.cast(column, pa.timestamp("us")) if pa.types.is_date(typ)
                                           else column)
    elif textual:
        # a column whose first cell is a number holds numbers (a bad cell
        # among them is named as not a number)
        if first_unconvertible(column.slice(0, 1)) is None:
            kind, t = "number", numeric_column(path, name, column)
        else:
            kind, t = "date-time", _parse_date_times(path, name, column)
    else:
        kind, t = "number", numeric_column(path, name, column)
    check_finite(path, name, t)
    if kind == "date-time":
        if unit not in (None, "s"):
            raise InputFileError(f"{path}: column '{name}' holds date-times, which carry their own unit: "
                                 f"drop --time-unit {unit}")
        return t, kind
    return t * TIME_UNITS[unit or "s"], kind


# ---- atomic output -----------------------------------------------------------
def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextmanager
def atomic_path(path):
    """A temporary path beside `path`, renamed over it only when the block
    finishes without an exception (and removed otherwise)."""
    directory = os.path.dirname(os.path.abspath(path))
    try:
        fd, tmp = tempfile.mkstemp(prefix=".pysig-", dir=directory)
        os.close(fd)
    except OSError as exc:
        raise OutputFileError(f"{path}: cannot write: {exc.strerror}") from exc
    try:
        yield tmp
        os.chmod(tmp, 0o666 & ~_umask())        # mkstemp makes 0600; give what open() would
        try:
            os.replace(tmp, path)
        except OSError as exc:
            raise OutputFileError(f"{path}: cannot write: {exc.strerror}") from exc
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


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
    with atomic_path(path) as tmp:
        with open(tmp, mode, **kwargs) as fh:
            yield fh


# ---- writing -----------------------------------------------------------------
def as_arrow(values):
    """One output column as a pyarrow array: booleans as 0/1 integers."""
    if isinstance(values, (pa.Array, pa.ChunkedArray)):
        return values.cast(pa.int64()) if pa.types.is_boolean(values.type) else values
    return from_numpy(values)


def to_table(columns):
    """A pyarrow Table from a Table or a dict name -> 1-D array."""
    if isinstance(columns, pa.Table):
        return columns
    return pa.table({name: as_arrow(v) for name, v in columns.items()})


def csv_header_line(names):
    """The header row as bytes (plain names, quoted only where CSV needs it)."""
    import io as _io
    buf = _io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow(names)
    return buf.getvalue().encode()


CSV_WRITE_OPTIONS = dict(include_header=False, quoting_style="needed")


def write_csv(path, columns):
    """Write columns atomically (see `atomic_path`): as Parquet when `path`
    ends in .parquet/.pq, as CSV with a header row otherwise.

    Parameters
    ----------
    path : path-like
        The file to write.
    columns : dict or pyarrow.Table
        name -> 1-D array, all of one length (or a Table).  Integer arrays
        are written as integers, booleans as 1/0, floats in the shortest
        form that reads back to the same double.

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
    0,0
    0.1,1
    >>> write_csv("out.parquet", {"t": np.array([0.0, 0.1])})
    >>> read_csv("out.parquet")
    {'t': array([0. , 0.1])}
    """
    table = to_table(columns)
    with atomic_path(path) as tmp:
        try:
            if is_parquet(path):
                pq.write_table(table, tmp)
            else:
                with pa.OSFile(str(tmp), "wb") as fh:          # pyarrow's own file: no Python object in its C++
                    fh.write(csv_header_line(table.column_names))
                    pcsv.write_csv(table, fh, write_options=pcsv.WriteOptions(**CSV_WRITE_OPTIONS))
        except OSError as exc:
            raise OutputFileError(f"{path}: cannot write: {exc}") from exc


def read_json(path, what):
    """The JSON document in `path`.

    Raises ModelFileError naming the file when it cannot be read or is not
    JSON; `what` names the kind of file expected ("JSON model file" ...)."""
    try:
        with open(path) as fh:
            return json.load(fh)
    except OSError as exc:
        raise ModelFileError(f"{path}: cannot read: {exc.strerror}") from None
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ModelFileError(f"{path}: not a {what}: {exc}") from None


def write_json(path, d, allow_nan=False):
    """`d` as indented JSON, all or nothing (atomic_output); NaN refused
    unless allow_nan (a benchmark's missing figure)."""
    text = json.dumps(d, indent=2, allow_nan=allow_nan) + "\n"
    with atomic_output(path) as fh:
        fh.write(text)
