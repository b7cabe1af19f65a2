"""Streaming tables: read a CSV or Parquet file chunk by chunk and write the
result chunk by chunk, so memory stays bounded on files larger than RAM.

Readers yield ``(offset, batch)``: `offset` is the 0-based index of the
batch's first data row in the file, so every error still names the row
(pysig.io.row_label).  The CSV reader fixes each column's type from the first
block (pyarrow's streaming reader); a column whose later rows no longer fit
that type is an InputFileError naming the column and the rows where it
changed.  The writer renames its temporary file over the target only when
every chunk was written (pysig.io.atomic_path)."""

__all__ = ["iter_batches", "table_sink", "progress"]
import sys
from contextlib import contextmanager

import pyarrow as pa
import pyarrow.csv as pcsv
import pyarrow.parquet as pq

from .errors import InputFileError, OutputFileError
from .io import (CSV_WRITE_OPTIONS, _csv_header, _parquet_file, atomic_path,
                 csv_header_line, csv_options, short_row_error, first_unconvertible, is_parquet,
                 not_a_number, read_header, require_columns, row_label)

CSV_BLOCK_BYTES = 1 << 20        # ~60 000 rows of a two-column log per chunk (larger blocks made pyarrow hold more in flight)
PARQUET_BATCH_ROWS = 1 << 16


def iter_batches(path, numeric=(), strings=(), columns=None, block_bytes=CSV_BLOCK_BYTES,
                 batch_rows=PARQUET_BATCH_ROWS):
    """Yield ``(offset, pyarrow.RecordBatch)`` over a CSV or Parquet file.

    Parameters
    ----------
    path : str or path-like
        CSV (header row) or Parquet (by suffix).
    numeric : sequence of str
        CSV columns parsed as float64 (Parquet columns keep their stored type;
        convert them with pysig.io.numeric_column).
    strings : sequence of str
        CSV columns kept as text.
    columns : sequence of str, optional
        Columns to read (default all).
    block_bytes, batch_rows : int
        Chunk size: bytes of CSV text, rows of Parquet.

    Raises
    ------
    InputFileError
        As pysig.io.read_table, found while streaming.
    """
    header = read_header(path)
    wanted = list(header if columns is None else columns)
    require_columns(path, header, [*numeric, *strings, *wanted])
    if is_parquet(path):
        yield from _parquet_batches(path, wanted, batch_rows)
    else:
        yield from _csv_batches(path, header, wanted, numeric, strings, block_bytes)


def _parquet_batches(path, wanted, batch_rows):
    pf = _parquet_file(path)
    if pf.metadata.num_rows == 0:
        raise InputFileError(f"{path}: header only, no data rows")
    offset = 0
    try:
        for batch in pf.iter_batches(batch_size=batch_rows, columns=wanted):
            yield offset, batch
            offset += batch.num_rows
    except (OSError, pa.ArrowException) as exc:
        raise InputFileError(f"{path}: cannot read Parquet data after row {offset}: {exc}") from None


def _csv_batches(path, header, wanted, numeric, strings, block_bytes):
    _, skipped, delimiter = _csv_header(path)
    read, convert, parse = csv_options(path, header, skipped, numeric, strings, block_size=block_bytes,
                                       threads=False, delimiter=delimiter)
    convert.include_columns = wanted
    offset = 0
    try:
        # closed where the batches end, not left to the garbage collector
        with pcsv.open_csv(path, read_options=read, convert_options=convert, parse_options=parse) as reader:
            for batch in reader:
                if batch.num_rows:
                    yield offset, batch.select(wanted)
                    offset += batch.num_rows
    except pa.ArrowInvalid as exc:
        short = short_row_error(path, header, skipped, delimiter)
        if short is not None:
            raise short from None
        raise _stream_conversion_error(path, header, skipped, delimiter, numeric, offset, exc) from None
    if offset == 0:
        raise InputFileError(f"{path}: header only, no data rows")


def _stream_conversion_error(path, header, skipped, delimiter, numeric, offset, exc):
    """The named error for a conversion that failed mid-stream: a bad cell in
    a numeric column (found by re-reading that column as text, in chunks), or
    a column whose type changed after the first block."""
    for name in numeric:
        read, convert, parse = csv_options(path, header, skipped, (), strings=(name,), threads=False,
                                           delimiter=delimiter)
        convert.include_columns = [name]
        start = 0
        with pcsv.open_csv(path, read_options=read, convert_options=convert, parse_options=parse) as reader:
            for batch in reader:
                i = first_unconvertible(batch.column(0))
                if i is not None:
                    return not_a_number(path, start + i, name, batch.column(0)[i].as_py())
                start += batch.num_rows
    text = str(exc)
    column = ""
    if "column #" in text:
        j = int(text.split("column #")[1].split(":")[0])
        column = f", column '{header[j]}'" if j < len(header) else ""
    return InputFileError(
        f"{path}: rows after {row_label(path, offset - 1)}{column}: the column's type changes "
        f"from what its first rows showed ({text.split(': ', 1)[-1]}); read the file whole "
        f"(--in-memory) or make the column's values one type")


class _Sink:
    """Appends record batches to one open CSV or Parquet writer."""

    def __init__(self, path, tmp):
        self.path, self._tmp = path, tmp
        self._writer = self._fh = None
        self.rows = 0

    def write(self, batch):
        """Append a pyarrow RecordBatch or Table (the first one fixes the schema)."""
        try:
            if self._writer is None:
                if is_parquet(self.path):
                    self._writer = pq.ParquetWriter(self._tmp, batch.schema)
                else:
                    self._fh = pa.OSFile(str(self._tmp), "wb")     # pyarrow's own file: no Python object in its C++
                    self._fh.write(csv_header_line(batch.schema.names))
                    self._writer = pcsv.CSVWriter(self._fh, batch.schema,
                                                  write_options=pcsv.WriteOptions(**CSV_WRITE_OPTIONS))
            if isinstance(batch, pa.Table):
                self._writer.write_table(batch)
            else:
                self._writer.write_batch(batch)
        except OSError as exc:
            raise OutputFileError(f"{self.path}: cannot write: {exc}") from exc
        self.rows += batch.num_rows

    def close(self):
        try:
            if self._writer is not None:
                self._writer.close()
            if self._fh is not None:
                self._fh.close()
        except OSError as exc:
            raise OutputFileError(f"{self.path}: cannot write: {exc}") from exc


@contextmanager
def table_sink(path):
    """Write record batches to CSV or Parquet (by suffix), atomically:
    ``with table_sink(path) as sink: sink.write(batch)``.  The file appears
    only when the block ends without an exception; nothing is left otherwise."""
    with atomic_path(path) as tmp:
        sink = _Sink(path, tmp)
        try:
            yield sink
        finally:
            sink.close()


@contextmanager
def progress(path, unit="rows"):
    """A tqdm bar on stderr while stderr is a terminal, silent otherwise;
    yields ``update(n)``.  Parquet files know their row count up front."""
    total = None
    if is_parquet(path):
        try:
            total = _parquet_file(path).metadata.num_rows
        except InputFileError:
            total = None
    enabled = sys.stderr.isatty()
    if not enabled:
        yield lambda n: None
        return
    from tqdm import tqdm
    with tqdm(total=total, unit=unit, unit_scale=True, file=sys.stderr, leave=False) as bar:
        yield bar.update
