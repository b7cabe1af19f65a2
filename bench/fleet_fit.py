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

Screening (--screening, the second table): generated fleets of several
sizes, noise levels, temperature counts and samples per temperature, every
sample logged (the within-plateau noise is what the screening measures),
each with 15 planted bad units (too much curvature: 3x the fleet's on one
axis; a noisy channel: 3x the noise on one axis) and 6 with a shape beyond
the fleet's order (a cubic term, reported apart: it needs more temperatures
than the order to be seen).  It counts the good units flagged and the bad
ones caught by pysig.fleet.screen at its default false-flag rate.

    python bench/fleet_fit.py --json bench/results/fleet_fit.json [--dask-workers 1 2] [--plot bench/results]
    python bench/fleet_fit.py --screening-only --json bench/results/fleet_fit.json

--screening-only leaves the timing figures of an existing JSON as they are
(a timing is only worth its machine's load) and writes the screening
table into it, with the 10^5-device fleet's flags under the same screening.
"""
import argparse
import os
import platform
import shutil
import tempfile
import time

import numpy as np

from pysig.io import read_json, write_json
from pysig.fleet._fit import fit_fleet
from pysig.fleet._report import DEFAULT_FALSE_FLAG_RATE, fleet_plots, screen, write_fleet

TEMPS = (0.0, 25.0, 50.0, 70.0)


def make_fleet(devices, temps=TEMPS, seed=0, with_injected=False):
    """Per device its own offset (sd 300 LSB), slope (1 +- 0.3 LSB/°C) and
    curvature per axis, plateau temperatures +-0.05 °C, 2 LSB noise; 0.2 %
    of the units drift 5x more (the ones screening should flag)."""
    rng = np.random.default_rng(seed)
    dev = np.repeat(np.arange(devices), len(temps))
    temp = np.tile(np.asarray(temps), devices) + rng.normal(0, 0.05, dev.size)
    off = rng.normal(0, 300, (devices, 3))
    s1 = rng.normal(1.0, 0.3, (devices, 3))
    injected = rng.random(devices) < 0.002
    s1[injected] *= 5
    s2 = rng.normal(0.01, 0.002, (devices, 3))
    y = off[dev] + s1[dev] * temp[:, None] + s2[dev] * temp[:, None] ** 2
    y = np.round(y + rng.normal(0, 2, y.shape))
    serials = np.array([f"SN{d:07d}" for d in range(devices)], dtype=object)
    return (dev, temp, y, serials, injected) if with_injected else (dev, temp, y, serials)


BASE = {"devices": 3000, "temps": 4, "per_temp": 20, "noise": 2.0}
SCREENING_FLEETS = [BASE, {**BASE, "devices": 300}, {**BASE, "devices": 20000},
                    {**BASE, "noise": 0.5}, {**BASE, "noise": 8.0}, {**BASE, "temps": 3}, {**BASE, "temps": 6},
                    {**BASE, "per_temp": 5}, {**BASE, "temps": 6, "per_temp": 5, "noise": 8.0}]
PLANTED = 15                # too much curvature / a noisy channel, alternately
CURVATURE = 0.01            # the fleet's mean curvature, LSB/°C^2
SHAPE_PLANTED = 6           # a cubic term: a shape beyond the fleet's order


def make_sample_fleet(devices, temps, per_temp, noise, seed=0):
    """Every sample of a chamber run: per device its offset (sd 300 LSB),
    slope (1 +- 0.3 LSB/°C) and curvature (0.01 +- 0.002 LSB/°C^2) per axis,
    `temps` plateaus over 0..70 °C held to +-0.05 °C, `per_temp` samples
    each, white noise `noise` LSB, readings rounded to LSB.  Planted:
    PLANTED bad units (on one axis: curvature 3x the fleet's mean, or 3x
    the fleet's noise) and
    SHAPE_PLANTED with a cubic term (+-8 LSB at the range ends) on x.
    Returns dev, temp, y, serials, {device: kind}."""
    rng = np.random.default_rng(seed)
    plateaus = np.linspace(0.0, 70.0, temps)
    dev = np.repeat(np.arange(devices), temps * per_temp)
    temp = np.tile(np.repeat(plateaus, per_temp), devices) + rng.normal(0, 0.05, dev.size)
    off = rng.normal(0, 300, (devices, 3))
    s1 = rng.normal(1.0, 0.3, (devices, 3))
    s2 = rng.normal(CURVATURE, 0.2 * CURVATURE, (devices, 3))
    sigma = np.full((devices, 3), float(noise))
    cubic = np.zeros(devices)
    chosen = rng.choice(devices, PLANTED + SHAPE_PLANTED, replace=False)
    kinds = {}
    for j, d in enumerate(chosen):
        axis = rng.integers(3)
        if j >= PLANTED:
            cubic[d], kinds[d] = 2e-4, "shape"
        elif j % 2:
            sigma[d, axis] *= 3
            kinds[d] = "noisy channel"
        else:
            s2[d, axis] = 3 * CURVATURE
            kinds[d] = "curvature"
    y = off[dev] + s1[dev] * temp[:, None] + s2[dev] * temp[:, None] ** 2
    y[:, 0] += cubic[dev] * (temp - 35.0) ** 3
    y = np.round(y + rng.normal(0, 1, y.shape) * sigma[dev])
    serials = np.array([f"SN{d:07d}" for d in range(devices)], dtype=object)
    return dev, temp, y, serials, kinds


def screening_row(cfg, seed=0):
    dev, temp, y, serials, kinds = make_sample_fleet(seed=seed, **cfg)
    fit = fit_fleet(dev, temp, y, serials, ["x", "y", "z"])
    flagged, _, spread = screen(fit)
    good = np.ones(len(serials), dtype=bool)
    good[list(kinds)] = False
    caught = {k: [int(flagged[d]) for d, kk in kinds.items() if kk == k] for k in set(kinds.values())}
    bad = [d for d, k in kinds.items() if k != "shape"]
    return {**cfg, "false_flag_rate_built_for": DEFAULT_FALSE_FLAG_RATE,
            "good_units": int(good.sum()), "good_flagged": int(flagged[good].sum()),
            "good_flagged_share": float(flagged[good].mean()),
            "bad_planted": len(bad), "bad_caught": int(flagged[bad].sum()),
            "bad_caught_share": float(flagged[bad].mean()),
            "caught_by_kind": {k: f"{sum(v)}/{len(v)}" for k, v in sorted(caught.items())},
            "good_flagged_by_test": {n: int(o[good].sum()) for n, (_, _, o) in spread.items() if o[good].any()},
            "orders": {f"poly:{n}": int(c) for n, c in enumerate(np.bincount(fit.order[fit.ok])) if c}}


def screening_table(rows):
    print(f"| devices | temps | samples/temp | noise LSB | good flagged | bad caught | curvature | noisy channel | "
          f"shape beyond the order |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        k = r["caught_by_kind"]
        print(f"| {r['devices']} | {r['temps']} | {r['per_temp']} | {r['noise']:g} | {r['good_flagged']} "
              f"({100 * r['good_flagged_share']:.2f} %) | {r['bad_caught']}/{r['bad_planted']} | "
              f"{k.get('curvature', '-')} | {k.get('noisy channel', '-')} | {k.get('shape', '-')} |")


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
    ap.add_argument("--screening", action="store_true", help="also run the screening table")
    ap.add_argument("--screening-only", action="store_true", help="only the screening table")
    ap.add_argument("--json")
    args = ap.parse_args()
    model = args.model if args.model == "auto" else int(args.model)
    if args.screening or args.screening_only:
        rows = [screening_row(cfg) for cfg in SCREENING_FLEETS]
        screening_table(rows)
        if args.screening_only:
            dev, temp, y, serials, injected = make_fleet(args.devices, with_injected=True)
            flagged, _, _ = screen(fit_fleet(dev, temp, y, serials, ["x", "y", "z"], model=model))
            caught, others = int(flagged[injected].sum()), int(flagged[~injected].sum())
            print(f"{args.devices} devices, one row per temperature: {int(flagged.sum())} flagged: "
                  f"{caught} of the {int(injected.sum())} injected high-drift units, {others} others "
                  f"({others / (~injected).sum():.2%})")
            if args.json:
                out = read_json(args.json, "bench JSON") if os.path.exists(args.json) else {}
                out.update(screening=rows, flagged=int(flagged.sum()), injected=int(injected.sum()),
                           injected_flagged=caught, others_flagged=others)
                write_json(args.json, out, allow_nan=True)
            return
    dev, temp, y, serials = make_fleet(args.devices)
    fit, fit_s, fit_cpu, runs = time_fit(dev, temp, y, serials, model, args.repeat)
    out = {"devices": args.devices, "temps": len(TEMPS), "axes": 3, "rows": int(dev.size),
           "model": args.model, "fit_s": fit_s, "fit_cpu_s": fit_cpu, "fit_runs_s": runs, "fitted": int(fit.ok.sum()),
           "orders": {f"poly:{n}": int(c) for n, c in enumerate(np.bincount(fit.order[fit.ok])) if c},
           "load_avg_1min": os.getloadavg()[0], "cpus": os.cpu_count(), "python": platform.python_version()}
    if args.plot:
        os.makedirs(args.plot, exist_ok=True)
        flagged, _, spread = screen(fit)
        fleet_plots(fit, flagged, spread, args.plot)
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
    if args.screening:
        out["screening"] = rows
    if args.json:
        os.makedirs(os.path.dirname(os.path.abspath(args.json)), exist_ok=True)
        write_json(args.json, out, allow_nan=True)


if __name__ == "__main__":
    main()
