"""Fleet calibration at production scale: 10^5 devices x 4 chamber
temperatures x 3 axes, one row per device and temperature (the plateau
means a production chamber logs), fitted by pysig.fleet._fit.fit_fleet
(every device at once) and written by pysig.fleet._report (a model
JSON and an NVM image with the device id per device, the summary CSV, the
plots).

fit_s is the batched fit alone (best of --repeat, every run in fit_runs_s;
its thread CPU time is recorded beside it, which other people's load on a
shared machine inflates less), write_s the output directory once.  --dask-workers 1 2 also times the
same fit through `--engine dask` on a local cluster of that many worker
processes, reading a Parquet dataset partitioned by device (the scaling
figures of the README).  The 1-minute load average is recorded.

    python bench/fleet_fit.py --json bench/results/fleet_fit.json [--dask-workers 1 2] [--plot bench/results]
"""
import argparse
import os
import platform
import shutil
import tempfile
import time

import numpy as np

from pysig.io import write_json
from pysig.fleet._fit import fit_fleet
from pysig.fleet._report import DEFAULT_K, fleet_plots, screen, write_fleet

TEMPS = (0.0, 25.0, 50.0, 70.0)


def make_fleet(devices, temps=TEMPS, seed=0):
    """Per device its own offset (sd 300 LSB), slope (1 +- 0.3 LSB/°C) and
    curvature per axis, plateau temperatures +-0.05 °C, 2 LSB noise; 0.2 %
    of the units drift 5x more (the ones screening should flag)."""
    rng = np.random.default_rng(seed)
    dev = np.repeat(np.arange(devices), len(temps))
    temp = np.tile(np.asarray(temps), devices) + rng.normal(0, 0.05, dev.size)
    off = rng.normal(0, 300, (devices, 3))
    s1 = rng.normal(1.0, 0.3, (devices, 3))
    s1[rng.random(devices) < 0.002] *= 5
    s2 = rng.normal(0.01, 0.002, (devices, 3))
    y = off[dev] + s1[dev] * temp[:, None] + s2[dev] * temp[:, None] ** 2
    y = np.round(y + rng.normal(0, 2, y.shape))
    serials = np.array([f"SN{d:07d}" for d in range(devices)], dtype=object)
    return dev, temp, y, serials


def time_fit(dev, temp, y, serials, model, repeat):
    """(fit, best wall s, best CPU s, every run's wall s): the first run in
    a fresh process pays numpy's first-touch page faults, so all are kept."""
    best, best_cpu, fit, runs = float("inf"), float("inf"), None, []
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.thread_time()
        fit = fit_fleet(dev, temp, y, serials, ["x", "y", "z"], model=model)
        c1, t1 = time.thread_time(), time.perf_counter()
        best, best_cpu = min(best, t1 - t0), min(best_cpu, c1 - c0)
        runs.append(t1 - t0)
    return fit, best, best_cpu, runs


def time_dask(dev, temp, y, serials, model, workers, tmp, partitions):
    import pyarrow as pa
    import pyarrow.parquet as pq
    from pysig.fleet._dask import connect, fit_fleet_dask
    ds = os.path.join(tmp, "dataset")
    if not os.path.isdir(ds):
        bucket = dev % partitions            # partitioned by device: each device in one file
        os.makedirs(ds)
        for b in range(partitions):
            sel = bucket == b
            pq.write_table(pa.table({"serial": serials[dev[sel]].astype(str), "temp": temp[sel],
                                     "x": y[sel, 0], "y": y[sel, 1], "z": y[sel, 2]}),
                           os.path.join(ds, f"part-{b:03d}.parquet"))
    with connect(workers=workers, processes=True) as client:
        client.wait_for_workers(workers)
        t0 = time.perf_counter()
        fit = fit_fleet_dask([ds], "serial", "temp", ["x", "y", "z"], model, client=client,
                             partitions=partitions)
        return fit, time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--devices", type=int, default=100_000)
    ap.add_argument("--model", default="auto", help="auto or an order (default auto)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--dask-workers", type=int, nargs="*", default=[])
    ap.add_argument("--partitions", type=int, default=16)
    ap.add_argument("--plot", metavar="DIR", help="also write the two fleet plots into DIR")
    ap.add_argument("--json")
    args = ap.parse_args()
    model = args.model if args.model == "auto" else int(args.model)
    dev, temp, y, serials = make_fleet(args.devices)
    fit, fit_s, fit_cpu, runs = time_fit(dev, temp, y, serials, model, args.repeat)
    out = {"devices": args.devices, "temps": len(TEMPS), "axes": 3, "rows": int(dev.size),
           "model": args.model, "fit_s": fit_s, "fit_cpu_s": fit_cpu, "fit_runs_s": runs, "fitted": int(fit.ok.sum()),
           "orders": {f"poly:{n}": int(c) for n, c in enumerate(np.bincount(fit.order[fit.ok])) if c},
           "load_avg_1min": os.getloadavg()[0], "cpus": os.cpu_count(), "python": platform.python_version()}
    if args.plot:
        os.makedirs(args.plot, exist_ok=True)
        flagged, _, spread = screen(fit, DEFAULT_K)
        fleet_plots(fit, flagged, spread, DEFAULT_K, args.plot)
    tmp = tempfile.mkdtemp(prefix="pysig-fleet-bench-")
    try:
        if not args.no_write:
            t0 = time.perf_counter()
            flagged, _, _ = write_fleet(fit, os.path.join(tmp, "out"))
            out["write_s"] = time.perf_counter() - t0
            out["flagged"] = int(flagged.sum())
            out["files_written"] = len(os.listdir(os.path.join(tmp, "out")))
        for w in args.dask_workers:
            dfit, secs = time_dask(dev, temp, y, serials, model, w, tmp, args.partitions)
            same = bool(np.array_equal(dfit.coef_q, fit.coef_q) and np.array_equal(dfit.order, fit.order))
            out.setdefault("dask", []).append({"workers": w, "partitions": args.partitions,
                                               "read_shuffle_fit_s": secs, "equal_to_local": same,
                                               "load_avg_1min": os.getloadavg()[0]})
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"| devices | temps | axes | fit_s (cpu) | write_s | fitted | flagged |")
    print(f"|---:|---:|---:|---:|---:|---:|---:|")
    print(f"| {out['devices']} | {out['temps']} | {out['axes']} | {fit_s:.3f} ({fit_cpu:.3f}) | "
          f"{out.get('write_s', float('nan')):.1f} | {out['fitted']} | {out.get('flagged', '-')} |")
    for d in out.get("dask", []):
        print(f"dask, {d['workers']} worker(s): read + shuffle + fit {d['read_shuffle_fit_s']:.2f} s "
              f"(equal to local: {d['equal_to_local']})")
    print(f"load average {out['load_avg_1min']:.2f} on {out['cpus']} CPUs")
    if args.json:
        os.makedirs(os.path.dirname(os.path.abspath(args.json)), exist_ok=True)
        write_json(args.json, out, allow_nan=True)


if __name__ == "__main__":
    main()
