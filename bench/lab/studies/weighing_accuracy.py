"""The weighing paper's accuracy experiment on the load-cell simulator, and
the settling after a load change of the motion-aware chain.

`run(n_seeds)` returns every figure as a JSON-ready dict;
bench/weighing_accuracy.py prints it as tables.

Setup (every figure is a median and a worst case over --seeds seeds):
- Cell and ADC: pysig.sim._loadcell defaults (0.15 mV/kg, ADS1232-like
  24-bit, PGA 128, Vref 5 V, 10 samples/s) with a terminal nonlinearity of
  0.02 % of full scale (a C3-class cell).
- Calibration: standard masses 10, 15, ..., 50 kg, each the mean of 5 raw
  readings, taken in quiet conditions (ADC noise only, 0.02 uV rms), fitted
  by pysig.weigh._calibration.calibrate (pysig.lsq): sensitivity and linearity error.
- Accuracy runs ("the factory floor"): each mass on the cell from power-up,
  60 s at 10 samples/s; 20 readings, one per second over the last 20 s; the
  error of a configuration is its largest |reading - mass| over the 20 (the
  weighing paper does not say when its readings were taken: the first 20 s after
  power-up are reported too, where the Kalman filter has averaged less).
  Disturbances: vibration (white, proportional to the load: floor
  acceleration times mass) plus electrical impulses (0.1 per second, one
  polarity, 5..10 kg equivalent).  The vibration level is SOLVED for (brentq)
  so that the median over seeds of the raw error at 30 kg is the weighing paper's
  6.2 %; the impulse setting is chosen so that a plain Kalman filter errs by
  about the weighing paper's 1.8 % at the worst mass.
- Configurations: raw samples; plain Kalman (the weighing paper's Q 1e-7, R 0.05, x0
  1, P0 10); the weighing paper's chain (preset "paper"); "adaptive": the weighing paper's
  parameters with the lock-out fix (5 rejections) and the motion-aware mode
  (band 4 sigma of the window mean from the measured noise, 2 samples);
  "adaptive_preset" and "recommended": Chain(preset="adaptive") and the
  package default Chain(preset="recommended") as shipped, given the sensor's
  noise R (the variance of one reading, measured on a still record at the
  heaviest load, pysig.weigh._calibration.noise_sigma): their A0 / motion band are
  derived from R ("auto", pysig.weigh._presets.PRESETS);
  "recommended_hx711_R": the default left with the R of the HX711 recording
  it was tuned on (24x below this simulator's noise: what happens when R is
  not the sensor's); chain_fixed / adaptive_fixed: the same chains in the
  firmware's fixed-point form on integer codes.
- Settling ("the bench"): ADC noise 0.3 uV rms (2 g), the same impulses.
  The settle time is from the load change until the output is flagged
  stable and within 0.1 % of the new load, and stays within it up to the
  next change.  "paper" chain: 10 -> 30 kg at 30 s, 900 s to follow.
  adaptive/recommended: a staircase 10, 30, 10, 50, 20, 40 kg, 15 s per
  level, the worst step counts; without swing (the headline figure), and
  with a swing after each change (2 % and 5 % of the step, 1.5 Hz, 0.5 s
  decay), next to the time the swinging load itself needs to come within
  the band.
"""
import numpy as np
from scipy.optimize import brentq


import pysig.weigh as chain
from pysig.weigh import _calibration as weighing
from pysig.sim._loadcell import LoadCellParams, simulate

RATE = 10.0
CAL_MASSES = np.arange(10.0, 50.1, 5.0)
MASSES = np.arange(5.0, 50.1, 5.0)
RUN_S = 60.0
READ_IDX = (np.arange(41, 61) * RATE - 1).astype(int)        # one reading per second, last 20 s
EARLY_IDX = (np.arange(1, 21) * RATE - 1).astype(int)        # ... or the first 20 s after power-up
CELL = dict(rate_hz=RATE, nonlinearity_frac_fs=0.0002)
QUIET = dict(noise_uv_rms=0.02)
IMPULSES = dict(impulse_rate_hz=0.1, impulse_amp_uv=10.0 * 150.0, impulse_polarity="+")
BENCH = dict(noise_uv_rms=0.3, ringing_hz=1.5, ringing_tau_s=0.5, **IMPULSES)
SWINGS = (0.0, 0.02, 0.05)        # swing amplitude after a load change, fraction of the step
PAPER_TARGET_RAW_PCT = 6.2
SETTLE_FRAC = 0.001
# lockout_n 5, not 3: on the floor setting A0 = 2 kg is only 1.6 sigma at 50 kg, and 3
# successive same-side rejections then happen by chance in ~10 % of 60-s runs (each a
# spurious re-seed: up to 4 % error, measured); 5 never did over 20 seeds x 10 masses.
ADAPTIVE = dict(lockout_n=5, motion_count=2)     # + motion_band from the measured noise
BAND_SIGMAS = 4.0
STAIRS = (10.0, 30.0, 10.0, 50.0, 20.0, 40.0)   # within the calibrated 10-50 kg: the fit errs < 0.1 %
STAIR_S = 15.0
PAPER_STEP = ((0.0, 10.0), (30.0, 30.0))
PAPER_RUN_S = 930.0


def motion_band_for(kg_still, window=12):
    """The motion band a commissioning engineer would set: BAND_SIGMAS standard
    deviations of the anti-pulse mean, from the per-sample noise of a still
    record (robust, pysig.weigh._calibration.noise_sigma) over the window's N - 2 samples."""
    return BAND_SIGMAS * weighing.noise_sigma(kg_still) / np.sqrt(window - 2)


def noise_r_for(kg_still):
    """R, the variance of one reading (kg^2), from the same still record: what
    the shipped presets derive their thresholds from."""
    return float(weighing.noise_sigma(kg_still)) ** 2


def fixed_chain(kg, preset, **overrides):
    """The firmware's fixed-point chain on integer codes rint(kg * counts/kg):
    the ADC codes less the calibrated zero, as the MCU would filter them."""
    cpk = LoadCellParams().counts_per_kg
    out, stable = chain.Chain(preset, fixed=True, units_per_kg=cpk, **overrides).process(np.rint(kg * cpk))
    return out / cpk, stable


def configs(band, r_noise):
    """name -> function(kg array) -> (out kg, stable or None); fresh state per call.
    band: the adaptive configuration's motion band; r_noise: the sensor's R
    for the shipped presets."""
    return {
        "raw": lambda kg: (kg, None),
        "kalman": lambda kg: (chain.Kalman1(Q=1e-7, R=0.05, x0=1.0, P0=10.0).process(kg), None),
        "chain": lambda kg: chain.Chain("paper", units_per_kg=1.0).process(kg),
        "adaptive": lambda kg: chain.Chain("paper", units_per_kg=1.0, motion_band=band,
                                           **ADAPTIVE).process(kg),
        "adaptive_preset": lambda kg: chain.Chain("adaptive", units_per_kg=1.0, R=r_noise).process(kg),
        "chain_fixed": lambda kg: fixed_chain(kg, "paper"),
        "adaptive_fixed": lambda kg: fixed_chain(kg, "paper", motion_band=band, **ADAPTIVE),
        "recommended": lambda kg: chain.Chain("recommended", units_per_kg=1.0, R=r_noise).process(kg),
        "recommended_hx711_R": lambda kg: chain.Chain("recommended", units_per_kg=1.0).process(kg),
    }


def calibrate_seed(seed):
    p = LoadCellParams(**CELL, **QUIET)
    means = [np.mean(simulate(p, seed=seed * 1000 + i, load_steps=((0.0, float(m)),),
                              duration_s=5 / RATE)["counts"]) for i, m in enumerate(CAL_MASSES)]
    cal = weighing.calibrate(means, CAL_MASSES, unit="kg")
    return cal, cal.counts_per_unit * p.lsb_v * 1e3


def floor_params(vib_g):
    return LoadCellParams(**CELL, **IMPULSES, noise_uv_rms=0.02, vibration_g_rms=vib_g)


def static_run(mass, seed, vib_g, cal):
    run = simulate(floor_params(vib_g), seed=seed * 7919 + int(mass * 10),
                   load_steps=((0.0, float(mass)),), duration_s=RUN_S)
    return cal.to_mass(run["counts"])


def max_err_pct(out, mass, idx=READ_IDX):
    return float(np.max(np.abs(out[idx] - mass)) / mass * 100.0)


def solve_vibration(seeds, cals):
    def f(vib):
        errs = [max_err_pct(static_run(30.0, s, vib, cals[s]), 30.0) for s in seeds]
        return float(np.median(errs)) - PAPER_TARGET_RAW_PCT
    return brentq(f, 0.001, 0.2, xtol=1e-5)


def settle_time(out, stable, t_step, t_end, target):
    i0, i1 = int(round(t_step * RATE)), int(round(t_end * RATE))
    idx = weighing.settle_index(out, target, SETTLE_FRAC * abs(target), i0, i1, stable)
    return None if idx is None else (idx - i0) / RATE


def bench_still(cal):
    """60 s of the heaviest load held still on the bench setting (kg)."""
    p = LoadCellParams(**CELL, **BENCH, load_steps=((0.0, float(max(STAIRS))),), duration_s=60.0)
    return cal.to_mass(simulate(p, seed=99)["counts"])


def bench_band(cal):
    """Motion band for the bench setting: from 60 s of the heaviest load held still."""
    return motion_band_for(bench_still(cal))


def swing_bound(swing):
    """The load itself: worst time over the staircase after which the swing
    term of the simulator stays within the settle band (at sample instants).
    No filter can be settled before this."""
    t = np.arange(0.0, STAIR_S, 1.0 / RATE)
    worst = 0.0
    for prev, new in zip(STAIRS, STAIRS[1:]):
        term = np.abs((new - prev) * swing * np.exp(-t / BENCH["ringing_tau_s"])
                      * np.sin(2 * np.pi * BENCH["ringing_hz"] * t))
        out = np.flatnonzero(term > SETTLE_FRAC * new)
        worst = max(worst, 0.0 if out.size == 0 else (out[-1] + 1) / RATE)
    return worst


def settle_seed(seed, cal):
    still = bench_still(cal)
    cfgs = configs(motion_band_for(still), noise_r_for(still))
    res = {}
    p = LoadCellParams(**CELL, **BENCH, load_steps=PAPER_STEP, duration_s=PAPER_RUN_S)
    kg = cal.to_mass(simulate(p, seed=seed)["counts"])
    for name in ("chain", "chain_lockfix"):
        fn = cfgs["chain"] if name == "chain" else (
            lambda x: chain.Chain("paper", units_per_kg=1.0, lockout_n=ADAPTIVE["lockout_n"]).process(x))
        out, stable = fn(kg)
        res[name] = settle_time(out, stable, PAPER_STEP[1][0], PAPER_RUN_S, PAPER_STEP[1][1])
    steps = tuple((STAIR_S * i, m) for i, m in enumerate(STAIRS))
    for swing in SWINGS:
        p = LoadCellParams(**CELL, **BENCH, ringing_frac=swing, load_steps=steps,
                           duration_s=STAIR_S * len(STAIRS))
        kg = cal.to_mass(simulate(p, seed=seed + 500)["counts"])
        for name in ("adaptive", "adaptive_fixed", "adaptive_preset", "recommended"):
            out, stable = cfgs[name](kg)
            times = [settle_time(out, stable, STAIR_S * i, STAIR_S * (i + 1), m)
                     for i, m in enumerate(STAIRS) if i > 0]
            res[(name, swing)] = None if any(t is None for t in times) else max(times)
    return res


def stats(values):
    v = [x for x in values if x is not None]
    if len(v) < len(values):
        return {"median": None if len(v) <= len(values) / 2 else float(np.median(
                    v + [np.inf] * (len(values) - len(v)))),
                "worst": None, "never": len(values) - len(v)}
    return {"median": float(np.median(v)), "worst": float(np.max(v)), "never": 0}


def run(n_seeds):
    seeds = list(range(n_seeds))
    cals, sens = {}, []
    for s in seeds:
        cals[s], mv = calibrate_seed(s)
        sens.append(mv)
    vib = solve_vibration(seeds, cals)
    floor_still = static_run(50.0, 99, vib, cals[0])
    floor_band, floor_r = motion_band_for(floor_still), noise_r_for(floor_still)
    cfgs = configs(floor_band, floor_r)
    names = list(cfgs)
    err = {n: np.zeros((n_seeds, MASSES.size)) for n in names}     # % of the mass
    err_kg = {n: np.zeros((n_seeds, MASSES.size)) for n in names}
    early30 = {n: [] for n in names}
    for s in seeds:
        for j, m in enumerate(MASSES):
            kg = static_run(m, s, vib, cals[s])
            for n in names:
                out = cfgs[n](kg)[0]
                err[n][s, j] = max_err_pct(out, m)
                err_kg[n][s, j] = err[n][s, j] * m / 100.0
                if m == 30.0:
                    early30[n].append(max_err_pct(out, m, EARLY_IDX))
    j30 = int(np.flatnonzero(MASSES == 30.0)[0])
    settle = [settle_seed(s, cals[s]) for s in seeds]

    def med(n, j=None):
        a = err[n][:, j] if j is not None else err[n].max(axis=1)
        return float(np.median(a)), float(np.max(a))

    out = {
        "seeds": n_seeds,
        "calibration": {
            "masses_kg": CAL_MASSES.tolist(), "readings_per_mass": 5,
            "sensitivity_mv_per_kg_median": float(np.median(sens)),
            "linearity_err_pct_fs_median": float(np.median([c.linearity_err_pct_fs for c in cals.values()])),
            "linearity_err_pct_fs_worst": float(np.max([c.linearity_err_pct_fs for c in cals.values()])),
            "counts_per_kg_median": float(np.median([c.counts_per_unit for c in cals.values()])),
        },
        "noise_setting": {
            "vibration_g_rms": vib,
            "vibration_kg_rms_at_30kg": vib * 30.0,
            "how_chosen": "brentq on the vibration level until the median over seeds of the raw max "
                          f"error over 20 readings at 30 kg equals {PAPER_TARGET_RAW_PCT} %",
            **{k: v for k, v in IMPULSES.items()},
            "impulse_amp_kg": IMPULSES["impulse_amp_uv"] / 150.0,
            "adc_noise_uv_rms": 0.02,
        },
        "adaptive_motion_band_kg": {"floor": floor_band, "bench": bench_band(cals[0]),
                                    "rule": f"{BAND_SIGMAS:g} sigma of the anti-pulse mean, per-sample "
                                            "sigma measured on a still record at the heaviest load"},
        "preset_noise_r_kg2": {"floor": floor_r, "bench": noise_r_for(bench_still(cals[0])),
                               "rule": "R given to the shipped presets: variance of one reading, "
                                       "from the same still record"},
        "preset_thresholds_kg": {
            name: {setting: {k: chain.chain_params(preset, units_per_kg=1.0, R=r)[k]
                             for k in ("A0", "motion_band", "lockout_n")}
                   for setting, r in (("floor", floor_r), ("bench", noise_r_for(bench_still(cals[0]))))}
            for name, preset in (("adaptive_preset", "adaptive"), ("recommended", "recommended"))},
    }
    for n in names:
        m30, w30 = med(n, j30)
        ma, wa = med(n)
        out[f"{n}_max_err_pct_30kg"] = m30
        out[f"{n}_max_err_pct_30kg_worst"] = w30
        out[f"{n}_max_err_kg_30kg"] = float(np.median(err_kg[n][:, j30]))
        out[f"{n}_max_err_pct_all"] = ma
        out[f"{n}_max_err_pct_all_worst"] = wa
    in_range = (MASSES >= CAL_MASSES[0]) & (MASSES <= CAL_MASSES[-1])   # the calibrated 10-50 kg
    for n in names:
        a = err[n][:, in_range].max(axis=1)
        out[f"{n}_max_err_pct_10to50kg"] = float(np.median(a))
        out[f"{n}_max_err_pct_10to50kg_worst"] = float(np.max(a))
    for n in names:
        out[f"{n}_max_err_pct_30kg_first20s"] = float(np.median(early30[n]))
    out["improvement_raw_to_chain_30kg"] = out["raw_max_err_pct_30kg"] / out["chain_max_err_pct_30kg"]
    out["improvement_kalman_to_chain_all"] = out["kalman_max_err_pct_all"] / out["chain_max_err_pct_all"]
    out["per_mass"] = [
        {"mass_kg": float(m),
         **{f"{n}_max_err_pct_median": float(np.median(err[n][:, j])) for n in names},
         **{f"{n}_max_err_pct_worst": float(np.max(err[n][:, j])) for n in names}}
        for j, m in enumerate(MASSES)]
    st = {n: stats([r[n] for r in settle]) for n in ("chain", "chain_lockfix")}
    out["settle"] = {
        "criterion": f"from the load change until stable and within {SETTLE_FRAC * 100:g} % of the "
                     "new load, staying within it up to the next change",
        "paper_step": "10 -> 30 kg, no swing", **st,
        "staircase_kg": list(STAIRS),
        "by_swing": [{"swing_frac": sw, "load_itself_s": swing_bound(sw),
                      **{n: stats([r[(n, sw)] for r in settle])
                         for n in ("adaptive", "adaptive_fixed", "adaptive_preset", "recommended")}}
                     for sw in SWINGS]}
    no_swing = out["settle"]["by_swing"][0]
    out["paper_settle_s"] = st["chain"]["median"]
    out["paper_settle_never"] = st["chain"]["never"]
    out["paper_lockfix_settle_s"] = st["chain_lockfix"]["median"]
    out["adaptive_settle_s"] = no_swing["adaptive"]["median"]
    out["adaptive_settle_s_worst"] = no_swing["adaptive"]["worst"]
    out["adaptive_preset_settle_s"] = no_swing["adaptive_preset"]["median"]
    out["adaptive_preset_settle_s_worst"] = no_swing["adaptive_preset"]["worst"]
    out["recommended_settle_s"] = no_swing["recommended"]["median"]
    out["recommended_settle_s_worst"] = no_swing["recommended"]["worst"]
    return out
