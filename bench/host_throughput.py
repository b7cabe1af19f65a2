"""Host throughput of the weighing chain: M samples/s on one 10^7-sample
float64 array (an HX711-like load-cell signal: steps, noise, read glitches).

Measured in one run on the same array: the C chain through Cython (float
and fixed), each stage alone,
filterpy's KalmanFilter on the Kalman stage alone (on a slice, scaled), and
numpy.copyto of the array (the memory-speed floor).  Every row is the best
of --repeat runs (the machine may be shared: best-of filters out other
people's load, it does not make the code faster).  Only the work is timed:
imports and the construction of each filter object happen before the clock
starts (a fresh object per run).  The C Kalman stage and filterpy run the
same filter (same Q, R, x0, P0); their outputs on the slice are compared
before the ratio is printed.  The headline figures are
wall-clock; the `*_cpu` fields divide by the thread's CPU time instead
(time.thread_time: the C loops run in the calling thread), which other
processes on a loaded machine inflate less.  The 1-minute load average is
recorded next to them.

    python bench/host_throughput.py --json results/host_throughput.json
"""
import argparse
import json
import os
import platform
import time

import numpy as np
from filterpy.kalman import KalmanFilter

import pysig.weigh as C
from pysig.io import atomic_output

UPK = 1000.0 / 0.45359237          # HX711 counts per kg
KALMAN = dict(Q=1e-7 * UPK**2, R=0.05 * UPK**2, x0=UPK, P0=10 * UPK**2)


def make_signal(n, seed=0):
    """Levels 0..40 lb in 10-lb steps at ~1000 counts/lb, 70 counts noise,
    a read glitch near -2^23 every ~300 samples."""
    rng = np.random.default_rng(seed)
    levels = 5800 + 10000 * rng.integers(0, 5, size=n // 150 + 1)
    x = np.repeat(levels, 150)[:n].astype(float) + rng.normal(0, 70, n)
    x[rng.integers(0, n, size=n // 300)] = -8387000.0
    return np.round(x)


def best_time(work, repeat, setup=lambda: None):
    """(best wall-clock seconds, best thread CPU seconds, last result) over
    `repeat` runs of work(setup()); setup() runs before the clock starts."""
    best, best_cpu, result = float("inf"), float("inf"), None
    for _ in range(repeat):
        arg = setup()
        t0, c0 = time.perf_counter(), time.thread_time()
        result = work(arg)
        c1, t1 = time.thread_time(), time.perf_counter()
        best, best_cpu = min(best, t1 - t0), min(best_cpu, c1 - c0)
    return best, best_cpu, result


def msps(n, seconds):
    return n / seconds / 1e6


def filterpy_filter(Q, R, x0, P0):
    """filterpy's KalmanFilter set up as the scalar random-walk filter of
    the Kalman stage (F = H = 1)."""
    kf = KalmanFilter(dim_x=1, dim_z=1)
    kf.F[:] = 1.0
    kf.H[:] = 1.0
    kf.Q[:] = Q
    kf.R[:] = R
    kf.x[:] = x0
    kf.P[:] = P0
    return kf


def filterpy_run(kf, z):
    """The timed work: predict + update per sample, the estimate kept."""
    out = np.empty(z.size)
    for i, v in enumerate(z):
        kf.predict()
        kf.update(v)
        out[i] = kf.x[0, 0]
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10_000_000, help="samples in the array")
    ap.add_argument("--slice", type=int, default=20_000, help="samples for the pure-Python figures")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json", metavar="FILE")
    args = ap.parse_args(argv)

    load_before = os.getloadavg()[0]
    x = make_signal(args.n)
    part = x[:args.slice]
    rows = []

    def measure(name, make, data, key):
        t, c, out = best_time(lambda obj: obj.process(data), args.repeat, setup=make)
        rows.append((name, key, data.size, t, msps(data.size, t), msps(data.size, c)))
        return out
    measure("chain (C, float, batch path)", lambda: C.Chain("recommended"), x, "chain_msps")
    measure("chain (C, fixed)", lambda: C.Chain("recommended", fixed=True), x, "chain_fixed_msps")
    measure("default chain (C, float, noise measured, batch path)", lambda: C.Chain(), x, "chain_auto_msps")
    measure("default chain (C, fixed, noise measured)", lambda: C.Chain(fixed=True), x, "chain_auto_fixed_msps")
    # the other presets, float (the default is to be as fast as the fastest, within 20 %)
    measure("paper preset chain (C, float)", lambda: C.Chain("paper", units_per_kg=UPK), x, "chain_paper_msps")
    measure("adaptive preset chain (C, float)", lambda: C.Chain("adaptive", units_per_kg=UPK), x,
            "chain_adaptive_msps")
    measure("limit stage (C, float)", lambda: C.LimitFilter(a0=2000.0, lockout_n=3), x, "limit_msps")
    measure("anti-pulse stage (C, float)", lambda: C.AntiPulse(window=12), x, "antipulse_msps")
    measure("Kalman stage (C, float)", lambda: C.Kalman1(**KALMAN), x, "kalman_msps")
    measure("stability stage (C, float)", lambda: C.StabilityDetector(step=10.0, count=1), x, "stable_msps")
    measure("limit stage (C, fixed)", lambda: C.LimitFilter(a0=2000.0, lockout_n=3, fixed=True), x,
            "limit_fixed_msps")
    measure("anti-pulse stage (C, fixed)", lambda: C.AntiPulse(window=12, fixed=True), x, "antipulse_fixed_msps")
    measure("Kalman stage (C, fixed)", lambda: C.Kalman1(**KALMAN, fixed=True), x, "kalman_fixed_msps")
    t, c, fp_out = best_time(lambda kf: filterpy_run(kf, part), args.repeat, setup=lambda: filterpy_filter(**KALMAN))
    rows.append(("filterpy KalmanFilter (Kalman stage)", "filterpy_kalman_msps", part.size, t, msps(part.size, t),
                 msps(part.size, c)))
    # like against like: the C stage computes filterpy's estimates on the slice
    c_out = C.Kalman1(**KALMAN).process(part)
    kalman_vs_filterpy = float(np.max(np.abs(np.asarray(c_out, dtype=float) - fp_out)))
    if not kalman_vs_filterpy <= 1e-6 * float(np.max(np.abs(fp_out))):
        raise SystemExit(f"C Kalman stage and filterpy differ by {kalman_vs_filterpy} on the slice")
    dst = np.empty_like(x)
    t, c, _ = best_time(lambda d: np.copyto(d, x), args.repeat, setup=lambda: dst)
    rows.append(("numpy.copyto (memory floor)", "copy_msps", x.size, t, msps(x.size, t), msps(x.size, c)))
    # machine-speed yardstick: one dependent floating-point add per sample
    # (any recursive filter is bound by such a chain; the chain has several)
    t, c, _ = best_time(lambda d: np.cumsum(x, out=d), args.repeat, setup=lambda: dst)
    rows.append(("numpy.cumsum (one dependent add/sample)", "cumsum_msps", x.size, t, msps(x.size, t),
                 msps(x.size, c)))

    fig = {key: round(v, 4) for _, key, _, _, v, _ in rows}
    fig.update({key + "_cpu": round(v, 4) for _, key, _, _, _, v in rows})
    fig["kalman_over_filterpy"] = round(fig["kalman_msps"] / fig["filterpy_kalman_msps"], 1)
    presets = {"recommended": "chain_msps", "paper": "chain_paper_msps", "adaptive": "chain_adaptive_msps"}
    fastest = max(presets, key=lambda k: fig[presets[k]])
    fig["fastest_preset"] = fastest
    fig["auto_over_fastest_preset"] = round(fig["chain_auto_msps"] / fig[presets[fastest]], 3)
    fig["auto_over_fastest_preset_cpu"] = round(fig["chain_auto_msps_cpu"] / fig[presets[fastest] + "_cpu"], 3)
    fig["kalman_over_filterpy_cpu"] = round(fig["kalman_msps_cpu"] / fig["filterpy_kalman_msps_cpu"], 1)
    fig["copy_over_chain"] = round(fig["copy_msps"] / fig["chain_msps"], 2)
    fig["copy_over_chain_cpu"] = round(fig["copy_msps_cpu"] / fig["chain_msps_cpu"], 2)
    fig["kalman_vs_filterpy_max_abs_diff"] = kalman_vs_filterpy
    fig["n"] = args.n
    fig["slice"] = args.slice
    fig["repeat"] = args.repeat
    fig["machine"] = f"{platform.machine()} {platform.processor() or ''} {os.cpu_count()} cpus".strip()
    fig["load_avg_1min_before"] = load_before
    fig["load_avg_1min"] = os.getloadavg()[0]

    print(f"{'what':40s} {'samples':>10s} {'seconds':>9s} {'M samples/s':>12s} {'M/s per CPU s':>14s}")
    for name, _, n, t, v, vc in rows:
        print(f"{name:40s} {n:10d} {t:9.4f} {v:12.3f} {vc:14.3f}")
    print(f"Kalman stage / filterpy: {fig['kalman_over_filterpy']:.0f}x (per CPU second "
          f"{fig['kalman_over_filterpy_cpu']:.0f}x; target >= 1000x; outputs agree within "
          f"{fig['kalman_vs_filterpy_max_abs_diff']:.2g}); "
          f"chain {fig['chain_msps']:.1f} M/s (target >= 50); copy / chain: {fig['copy_over_chain']:.1f}x "
          f"(target <= 10x); per CPU second: chain {fig['chain_msps_cpu']:.1f} M/s, copy / chain "
          f"{fig['copy_over_chain_cpu']:.1f}x; 1-min load average {fig['load_avg_1min_before']:.2f} before, "
          f"{fig['load_avg_1min']:.2f} after")
    print(f"default chain (auto) {fig['chain_auto_msps']:.1f} M/s (target >= 50), "
          f"{fig['auto_over_fastest_preset']:.2f} of the fastest preset ({fastest}; target >= 0.8), "
          f"{fig['auto_over_fastest_preset_cpu']:.2f} per CPU second")
    if args.json:
        with atomic_output(args.json) as fh:
            json.dump(fig, fh, indent=2)
            fh.write("\n")
        print(f"wrote {args.json}")
    return fig


if __name__ == "__main__":
    main()
