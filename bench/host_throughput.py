"""Host throughput of the weighing chain: M samples/s on one 10^7-sample
float64 array (an HX711-like load-cell signal: steps, noise, read glitches).

Measured in one run on the same array: the C chain through Cython (float
and fixed), each stage alone, the pure-Python reference (on a slice, scaled),
filterpy's KalmanFilter on the Kalman stage alone (on a slice, scaled), and
numpy.copyto of the array (the memory-speed floor).  Each figure is the
best of --repeat runs (the machine may be shared: best-of filters out other
people's load, it does not make the code faster).

    python bench/host_throughput.py --json results/host_throughput.json
"""
import argparse
import json
import os
import platform
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from pysig import chain as C  # noqa: E402
from pysig.reference import chain as R  # noqa: E402


def make_signal(n, seed=0):
    """Levels 0..40 lb in 10-lb steps at ~1000 counts/lb, 70 counts noise,
    a read glitch near -2^23 every ~300 samples."""
    rng = np.random.default_rng(seed)
    levels = 5800 + 10000 * rng.integers(0, 5, size=n // 150 + 1)
    x = np.repeat(levels, 150)[:n].astype(float) + rng.normal(0, 70, n)
    x[rng.integers(0, n, size=n // 300)] = -8387000.0
    return np.round(x)


def best_time(fn, repeat):
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def msps(n, seconds):
    return n / seconds / 1e6


def filterpy_kalman(z, Q=1e-7 * 2204.6**2, R_=0.05 * 2204.6**2, x0=2204.6, P0=10 * 2204.6**2):
    from filterpy.kalman import KalmanFilter
    kf = KalmanFilter(dim_x=1, dim_z=1)
    kf.F[:] = 1.0
    kf.H[:] = 1.0
    kf.Q[:] = Q
    kf.R[:] = R_
    kf.x[:] = x0
    kf.P[:] = P0
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

    x = make_signal(args.n)
    part = x[:args.slice]
    rows = []

    def measure(name, make, data, key):
        def run():
            obj = make()
            obj.process(data)
        t = best_time(run, args.repeat if data.size > args.slice else 1)
        rows.append((name, key, data.size, t, msps(data.size, t)))

    upk = 1000.0 / 0.45359237          # HX711 counts per kg
    measure("chain (C, float)", lambda: C.Chain(), x, "chain_msps")
    measure("chain (C, fixed)", lambda: C.Chain(fixed=True), x, "chain_fixed_msps")
    measure("limit stage (C, float)", lambda: C.LimitFilter(a0=2000.0, lockout_n=3), x, "limit_msps")
    measure("anti-pulse stage (C, float)", lambda: C.AntiPulse(window=12), x, "antipulse_msps")
    measure("Kalman stage (C, float)", lambda: C.Kalman1(Q=1e-7 * upk**2, R=0.05 * upk**2, x0=upk,
                                                        P0=10 * upk**2), x, "kalman_msps")
    measure("stability stage (C, float)", lambda: C.StabilityDetector(step=10.0, count=1), x, "stable_msps")
    measure("limit stage (C, fixed)", lambda: C.LimitFilter(a0=2000.0, lockout_n=3, fixed=True), x,
            "limit_fixed_msps")
    measure("anti-pulse stage (C, fixed)", lambda: C.AntiPulse(window=12, fixed=True), x, "antipulse_fixed_msps")
    measure("Kalman stage (C, fixed)", lambda: C.Kalman1(Q=1e-7 * upk**2, R=0.05 * upk**2, x0=upk,
                                                        P0=10 * upk**2, fixed=True), x, "kalman_fixed_msps")
    measure("reference chain (Python, float)", lambda: R.Chain(), part, "reference_msps")
    t = best_time(lambda: filterpy_kalman(part), 1)
    rows.append(("filterpy KalmanFilter (Kalman stage)", "filterpy_kalman_msps", part.size, t, msps(part.size, t)))
    dst = np.empty_like(x)
    t = best_time(lambda: np.copyto(dst, x), max(args.repeat, 5))
    rows.append(("numpy.copyto (memory floor)", "copy_msps", x.size, t, msps(x.size, t)))
    # machine-speed yardstick: one dependent floating-point add per sample
    # (any recursive filter is bound by such a chain; the chain has several)
    t = best_time(lambda: np.cumsum(x, out=dst), max(args.repeat, 3))
    rows.append(("numpy.cumsum (one dependent add/sample)", "cumsum_msps", x.size, t, msps(x.size, t)))

    fig = {key: round(v, 4) for _, key, _, _, v in rows}
    fig["kalman_over_filterpy"] = round(fig["kalman_msps"] / fig["filterpy_kalman_msps"], 1)
    fig["copy_over_chain"] = round(fig["copy_msps"] / fig["chain_msps"], 2)
    fig["n"] = args.n
    fig["slice"] = args.slice
    fig["repeat"] = args.repeat
    fig["machine"] = f"{platform.machine()} {platform.processor() or ''} {os.cpu_count()} cpus".strip()
    fig["load_avg_1min"] = os.getloadavg()[0]

    print(f"{'what':40s} {'samples':>10s} {'seconds':>9s} {'M samples/s':>12s}")
    for name, _, n, t, v in rows:
        print(f"{name:40s} {n:10d} {t:9.4f} {v:12.3f}")
    print(f"Kalman stage / filterpy: {fig['kalman_over_filterpy']:.0f}x (target >= 1000x); "
          f"chain {fig['chain_msps']:.1f} M/s (target >= 50); copy / chain: {fig['copy_over_chain']:.1f}x "
          f"(target <= 10x); 1-min load average {fig['load_avg_1min']:.2f}")
    if args.json:
        from pysig.io import atomic_output
        with atomic_output(args.json) as fh:
            json.dump(fig, fh, indent=2)
            fh.write("\n")
        print(f"wrote {args.json}")
    return fig


if __name__ == "__main__":
    main()
