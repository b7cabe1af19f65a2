"""The fleet fit on Dask: the same batched fit (pysig.fleet._fit), one
call per partition of a dask.dataframe whose partitions hold whole devices.

Each log file (or each file of a Parquet dataset partitioned by device) is
one input partition, read by pysig.io on a worker (so errors name the file
and row as locally); the frame is shuffled on the device column, so every
device's rows meet in one partition, wherever they were logged; each
partition runs the batched fit and returns one row per device.  The driver
only gathers those rows (a few hundred bytes per device) and writes the
outputs, so the same code spreads over many machines: point --scheduler at
a cluster whose workers see the logs (a shared or object file system).

Needs the optional extra: ``pip install 'pysig[fleet]'``."""
import numpy as np

from ..errors import PysigError
from ._fit import FleetFit, fit_fleet
from ._data import check_conflicts, expand_logs, read_log

FIELDS_1 = ["ok", "order", "n_temps", "samples", "t_lo", "t_hi", "t_center", "u_mul", "u_shift"]
FIELDS_A = ["f_t0", "q", "bound", "rms", "cv_rms", "drift"]


def _read(item, index, device, temp, readings):
    path, consts = item
    t = read_log(path, consts, device, temp, readings).to_pandas()
    t["source"] = np.int64(index)
    return t


def _log_meta(n_axes):
    import pandas as pd
    return pd.DataFrame({"device": pd.Series([], dtype=object), "temp": pd.Series([], dtype=float),
                         **{f"value{i}": pd.Series([], dtype=float) for i in range(n_axes)},
                         "source": pd.Series([], dtype=np.int64)})


def _fit_partition(pdf, axes, model, t0, files, max_coef):
    """One partition (pandas) -> one row per device with every FleetFit field."""
    import pandas as pd
    serial = pdf["device"].to_numpy(dtype=object)
    devices, dev = np.unique(serial, return_inverse=True)
    values = pdf[[f"value{i}" for i in range(len(axes))]].to_numpy(dtype=float)
    temp = pdf["temp"].to_numpy(dtype=float)
    if len(devices) == 0:
        return _empty(axes, max_coef)
    check_conflicts(files, dev, pdf["source"].to_numpy(), temp, values, devices)
    f = fit_fleet(dev, temp, values, devices, axes, model=model, t0=t0)
    out = {"device": devices.astype(str), "reason": f.reason.astype(str)}
    for name in FIELDS_1:
        out[name] = getattr(f, name)
    for name in FIELDS_A:
        arr = getattr(f, name)
        for i in range(len(axes)):
            out[f"{name}_{i}"] = arr[:, i]
    for i in range(len(axes)):
        for k in range(max_coef):
            out[f"coef_{i}_{k}"] = f.coef[:, i, k] if k < f.coef.shape[2] else 0.0
            out[f"coef_q_{i}_{k}"] = f.coef_q[:, i, k] if k < f.coef_q.shape[2] else 0
    return pd.DataFrame(out)


def _empty(axes, max_coef):
    import pandas as pd
    cols = {"device": pd.Series([], dtype=object), "reason": pd.Series([], dtype=object)}
    for name in FIELDS_1:
        cols[name] = pd.Series([], dtype=bool if name == "ok" else np.int64)
    for name in FIELDS_A:
        for i in range(len(axes)):
            cols[f"{name}_{i}"] = pd.Series([], dtype=np.int64 if name == "q" else float)
    for i in range(len(axes)):
        for k in range(max_coef):
            cols[f"coef_{i}_{k}"] = pd.Series([], dtype=float)
            cols[f"coef_q_{i}_{k}"] = pd.Series([], dtype=np.int64)
    return pd.DataFrame(cols)


def connect(scheduler=None, workers=2, processes=True):
    """A distributed Client: to `scheduler` (an address), or a local cluster
    of `workers` single-threaded workers."""
    import logging
    from distributed import Client, LocalCluster
    logging.getLogger("distributed.shuffle").setLevel(logging.ERROR)   # per-shuffle notices on stderr
    if scheduler:
        return Client(scheduler)
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=processes,
                           dashboard_address=":0", silence_logs=logging.ERROR)
    return Client(cluster)


def fit_fleet_dask(paths, device, temp, columns, model="auto", t0=25.0, client=None,
                   partitions=None):
    """The fleet fit on Dask; returns the FleetFit the local engine returns
    (devices sorted by serial).  `client`: a distributed Client (default:
    the current one); `partitions`: output partitions of the shuffle
    (default: one per input file, at least two per worker)."""
    import dask.dataframe as dd
    items = expand_logs(paths)
    files = [f for f, _ in items]
    max_coef = (int(model) if model != "auto" else 8) + 1
    frame = dd.from_map(_read, items, list(range(len(items))), device=device, temp=temp,
                        readings=list(columns), meta=_log_meta(len(columns)), enforce_metadata=False)
    n_out = partitions or max(len(items), 2 * max(1, len(client.scheduler_info()["workers"])) if client else 2)
    frame = frame.shuffle("device", npartitions=n_out)
    meta = _empty(list(columns), max_coef)
    parts = frame.map_partitions(_fit_partition, list(columns), model, t0, files, max_coef, meta=meta)
    try:
        df = (client.compute(parts).result() if client else parts.compute())
    except PysigError:
        raise
    df = df.sort_values("device", kind="stable").reset_index(drop=True)
    return _as_fleet_fit(df, list(columns), t0, max_coef)


def _as_fleet_fit(df, axes, t0, max_coef):
    A = len(axes)
    arr = {name: df[name].to_numpy() for name in FIELDS_1}
    per = {name: np.stack([df[f"{name}_{i}"].to_numpy() for i in range(A)], 1) for name in FIELDS_A}
    coef = np.stack([np.stack([df[f"coef_{i}_{k}"].to_numpy(float) for k in range(max_coef)], 1)
                     for i in range(A)], 1)
    coef_q = np.stack([np.stack([df[f"coef_q_{i}_{k}"].to_numpy(np.int64) for k in range(max_coef)], 1)
                       for i in range(A)], 1)
    top = int(arr["order"].max()) + 1 if len(df) else 1
    return FleetFit(devices=df["device"].to_numpy(dtype=object), axes=axes, t0=float(t0),
                    ok=arr["ok"].astype(bool), reason=df["reason"].to_numpy(dtype=object),
                    order=arr["order"].astype(np.int64), n_temps=arr["n_temps"].astype(np.int64),
                    samples=arr["samples"].astype(np.int64), t_lo=arr["t_lo"].astype(np.int64),
                    t_hi=arr["t_hi"].astype(np.int64), t_center=arr["t_center"].astype(np.int64),
                    u_mul=arr["u_mul"].astype(np.int64), u_shift=arr["u_shift"].astype(np.int64),
                    coef=coef[:, :, :top], f_t0=per["f_t0"], q=per["q"].astype(np.int64),
                    coef_q=coef_q[:, :, :top], bound=per["bound"], rms=per["rms"],
                    cv_rms=per["cv_rms"], drift=per["drift"])
