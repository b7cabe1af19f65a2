"""Fleet logs in: long-format tables (one row per device and sample), CSV or
Parquet, one file, many files, or a directory (a Parquet dataset partitioned
by device: ``serial=A123/part-0.parquet`` puts serial A123 on every row of
that file).

Checks, each an InputFileError naming the file (and row where there is one):
a missing device, temperature or reading column, a null or empty serial, and
the same serial in two files with conflicting data (the same temperature
reading with different values: two units logged under one serial, or one
unit logged twice by mistake)."""
import os
from dataclasses import dataclass
from urllib.parse import unquote

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc

from ..errors import InputFileError
from ..io import float64_values, read_header, read_table, require_columns, row_label

LOG_SUFFIXES = (".csv", ".parquet", ".pq")


@dataclass
class FleetLog:
    """Rows of all logs: device index (into `devices`, sorted by name), the
    file each row came from (index into `files`), temperature and readings."""
    devices: np.ndarray
    dev: np.ndarray
    source: np.ndarray
    files: list
    temp: np.ndarray
    values: np.ndarray
    axes: list


def expand_logs(paths):
    """Files to read: each path as given, or the log files under a directory
    (sorted), with the ``key=value`` directory names on their way as
    constant columns.  Returns [(file, {column: value})]."""
    out = []
    for path in paths:
        path = str(path)
        if os.path.isdir(path):
            found = []
            for root, dirs, files in os.walk(path):
                dirs.sort()
                for name in sorted(files):
                    if name.lower().endswith(LOG_SUFFIXES) and not name.startswith((".", "_")):
                        full = os.path.join(root, name)
                        parts = os.path.relpath(root, path).split(os.sep)
                        consts = dict(unquote(p).split("=", 1) for p in parts if "=" in p)
                        found.append((full, consts))
            if not found:
                raise InputFileError(f"{path}: a directory with no .csv or .parquet log in it")
            out.extend(found)
        else:
            out.append((path, {}))
    return out


def read_log(path, constants, device, temp, columns):
    """One log as a pyarrow Table (device as text, the others float64)."""
    header = read_header(path)
    in_file = [device] if device not in constants else []
    require_columns(path, header, [*in_file, temp, *columns])
    table = read_table(path, [*in_file, temp, *columns], numeric=[temp, *columns], strings=in_file)
    if device in constants:
        serial = pa.array([constants[device]] * table.num_rows, pa.string())
    else:
        serial = table[device]
        if not pa.types.is_string(serial.type):
            serial = pc.cast(serial, pa.string())
        missing = pc.or_(pc.is_null(serial), pc.equal(pc.utf8_trim_whitespace(serial), ""))
        if pc.any(missing).as_py():
            i = int(np.flatnonzero(missing.to_numpy(zero_copy_only=False))[0])
            raise InputFileError(f"{path}: row {row_label(path, i)}, column '{device}': empty serial")
    return pa.table({"device": serial, "temp": table[temp],
                     **{f"value{i}": table[c] for i, c in enumerate(columns)}})


def check_conflicts(files, dev, source, temp, values, devices):
    """InputFileError when a serial appears in two files that disagree: a row
    with the same temperature in both but different readings."""
    per_dev_files = np.zeros(len(devices), dtype=np.int64)
    order = np.lexsort((source, dev))
    d_s, f_s = dev[order], source[order]
    new = np.r_[True, (d_s[1:] != d_s[:-1]) | (f_s[1:] != f_s[:-1])]
    np.add.at(per_dev_files, d_s[new], 1)
    shared = per_dev_files > 1
    if not np.any(shared):
        return
    rows = np.flatnonzero(shared[dev])
    o = rows[np.lexsort((source[rows], temp[rows], dev[rows]))]
    same = (dev[o][1:] == dev[o][:-1]) & (temp[o][1:] == temp[o][:-1]) & (source[o][1:] != source[o][:-1])
    differ = same & np.any(values[o][1:] != values[o][:-1], axis=1)
    if np.any(differ):
        j = int(np.flatnonzero(differ)[0])
        a, b = o[j], o[j + 1]
        raise InputFileError(
            f"{files[source[a]]} and {files[source[b]]}: serial '{devices[dev[a]]}' has conflicting "
            f"data (at {temp[a]:g} °C the readings differ: {values[a].tolist()} vs "
            f"{values[b].tolist()}): two units under one serial, or one unit logged twice")


def load_fleet(paths, device, temp, columns):
    """Read and check every log; devices sorted by serial.

    Parameters
    ----------
    paths : list of str
        Files (CSV or Parquet) or directories of them.
    device, temp : str
        Column names of the serial and the temperature (°C).
    columns : list of str
        Reading columns (1..3), int16 sensor codes.

    Returns
    -------
    FleetLog
    """
    files = expand_logs(paths)
    tables = [read_log(f, consts, device, temp, columns) for f, consts in files]
    source = np.repeat(np.arange(len(tables)), [t.num_rows for t in tables])
    table = pa.concat_tables(tables)
    serial = table["device"].combine_chunks()
    devices = pc.unique(serial)
    devices = pc.take(devices, pc.sort_indices(devices))
    dev = float64_values(pc.index_in(serial, value_set=devices)).astype(np.int64)
    temp_a = float64_values(table["temp"])
    values = np.column_stack([float64_values(table[f"value{i}"]) for i in range(len(columns))])
    devices = np.asarray(devices.to_pylist(), dtype=object)
    check_conflicts([f for f, _ in files], dev, source, temp_a, values, devices)
    return FleetLog(devices=devices, dev=dev, source=source, files=[f for f, _ in files],
                    temp=temp_a, values=values, axes=list(columns))
