"""The weighing chain on a real recording: hx711_steps_10hz.

Two load cells (lc1, lc2) read by an HX711 at 10 Hz while 10-lb weights are
put on and taken off by hand (0 -> 40 -> 0 lb), with real read glitches;
lc3..lc6 carry no load.  Source: GitHub mvsivaselvan/CIE324-Swing-Project
(MIT); the copy bundled in pysig/data has its LICENSE and provenance.

analyse_loaded() calibrates counts -> lb on the plateaus it finds itself
(pysig.weigh._calibration), converts to kg (the chain's presets are in kg, as in the
weighing paper) and runs each configuration:

  raw          the calibrated samples themselves
  paper_chain  Chain(preset="paper"): the weighing paper's published parameters
  kalman       the weighing paper's plain Kalman filter (Q 1e-7, R 0.05, x0 1, P0 10)
  recommended  Chain(preset="recommended"): lock-out fix, motion-aware
               settling, zero tracking, thresholds from a fixed R
  auto         Chain(), the default: the same with every threshold
               following the noise measured on the fly

and measures, per configuration (definitions in METRICS):
glitches_passed, plateaus_missed, settle_s_max, plateau_err_lb_max,
plateau_noise_lb.  analyse_zero() does the no-load channels: zero noise and
zero drift before and after filtering.
"""
import contextlib
import importlib
import importlib.resources

import numpy as np
from scipy.ndimage import median_filter

from ..errors import InputFileError, InsufficientDataError
from ..io import atomic_output, check_time_column, read_csv
from ..lsq import fit_poly
from ._calibration import assign_nominal, calibrate, find_plateaus, glitch_indices, settle_index

KG_PER_LB = 0.45359237
RATE_HZ = 10.0
STEP_LB = 10.0
LOADED = ("lc1", "lc2")
UNLOADED = ("lc3", "lc4", "lc5", "lc6")
CONFIGS = ("raw", "paper_chain", "kalman", "recommended", "auto")
SETTLE_BAND_LB = 0.05
MISSED_BAND_LB = 1.0
GLITCH_BAND_LB = 0.05
END_GUARD = 5              # samples: plateau ends are found to within half the 1-s steadiness window
GLITCH_WINDOW = 24          # samples after a glitch in which its effect is looked for
ZERO_WARMUP_S = 10.0        # no-load channels: skip this much of the still segment (recovery after the
                            # rig was touched) ...
ZERO_TAIL_S = 3.0           # ... and this much before its end

METRICS = {
    "glitches_passed": "read glitches (samples > 50 noise sigma from the 5-sample running median) after "
                       f"which, within {GLITCH_WINDOW} samples, the output leaves towards the glitch by "
                       f"more than {GLITCH_BAND_LB} lb the range that the same configuration outputs "
                       f"within +-{GLITCH_WINDOW} samples when each glitch is replaced by the running median",
    "plateaus_missed": f"plateaus at whose end (median of the last 1 s) the output is more than "
                       f"{MISSED_BAND_LB} lb (a tenth of a step) from the plateau's level: locked out or "
                       "too slow to follow",
    "settle_s_max": f"largest time over the 8 steps from the end of the previous plateau until the output "
                    f"stays within +-{SETTLE_BAND_LB} lb of the new plateau's level (median of its raw "
                    "samples) to the plateau's end (less 0.5 s: the plateau finder's resolution), at "
                    "least 1 s before that end; null when some step never settles.  The hand and the swing take motion_s of it (end of the previous "
                    "plateau to the start of this one)",
    "plateau_err_lb_max": "largest |median of the output over the second half of a plateau - nominal "
                          "level| (glitch samples excluded)",
    "plateau_noise_lb": "largest standard deviation of the output over the second half of a plateau "
                        "(glitch samples excluded: they are counted by glitches_passed)",
    "zero_noise_lb": "no-load channels, longest still segment without its first "
                     f"{ZERO_WARMUP_S} s and last {ZERO_TAIL_S} s, glitch samples excluded: standard deviation of the output "
                     "about its least-squares line, in lb of lc1's calibration",
    "zero_drift_lb": "change of that least-squares line over the segment (end minus start), lb",
}


@contextlib.contextmanager
def bundled_csv():
    """Path of the recording bundled in the installed package."""
    res = importlib.resources.files("pysig.data") / "hx711_steps_10hz.csv"
    with importlib.resources.as_file(res) as path:
        yield path


def load(path):
    """Columns of the recording: t_s and lc1..lc6 counts (float64)."""
    cols = ["t_s"] + [f"{c}_counts" for c in LOADED + UNLOADED]
    d = read_csv(path, cols)
    check_time_column(path, "t_s", d["t_s"])
    if d["t_s"].size < 100:
        raise InputFileError(f"{path}: {d['t_s'].size} rows, the step analysis needs at least 100")
    return d


def default_backend():
    """The C chain through Cython (pysig.weigh)."""
    return importlib.import_module("pysig.weigh")


def run_config(config, kg, backend=None, counts_per_kg=None):
    """One configuration over a kg signal -> (output kg, stable flags or None).

    "recommended_fixed" and "auto_fixed" run the firmware's fixed-point
    chain on integer codes, rint(kg * counts_per_kg): the ADC codes minus the calibrated zero,
    as firmware that subtracts the stored offset first would see them."""
    backend = backend or default_backend()
    if config == "raw":
        return np.array(kg, dtype=float), None
    if config == "paper_chain":
        return backend.Chain(preset="paper", units_per_kg=1.0).process(kg)
    if config == "kalman":
        return backend.Kalman1(Q=1e-7, R=0.05, x0=1.0, P0=10.0).process(kg), None
    if config == "recommended":
        return backend.Chain(preset="recommended", units_per_kg=1.0).process(kg)
    if config == "auto":
        return backend.Chain(preset="auto").process(kg)
    if config == "auto_fixed":
        codes = np.rint(np.asarray(kg) * counts_per_kg)
        out, stable = backend.Chain(preset="auto", fixed=True).process(codes)
        return out / counts_per_kg, stable
    if config == "recommended_fixed":
        codes = np.rint(np.asarray(kg) * counts_per_kg)
        out, stable = backend.Chain(preset="recommended", fixed=True,
                                    units_per_kg=counts_per_kg).process(codes)
        return out / counts_per_kg, stable
    raise ValueError(f"unknown configuration {config!r} (choose from {', '.join(CONFIGS)})")


def deglitched(x, glitches):
    """x with each glitch sample replaced by the 5-sample running median."""
    clean = np.array(x, dtype=float)
    clean[glitches] = median_filter(clean, size=5, mode="nearest")[glitches]
    return clean


def glitches_passed(out, out_clean, glitches, band, x=None, x_clean=None):
    """Glitches whose value leaks into the output: after the glitch the
    output leaves, towards the glitch (x[g] vs x_clean[g]; both ways when not
    given), the envelope (+-band) of the glitch-free run's output around it.
    A glitch that only delays the following of a step (it restarts the
    lock-out count) stays inside the envelope; a motion restart on noise that
    happens to coincide with a glitch moves the output the other way."""
    n = 0
    for g in glitches:
        env = out_clean[max(g - GLITCH_WINDOW, 0):g + GLITCH_WINDOW]
        seg = out[g:g + GLITCH_WINDOW]
        up, down = np.any(seg > env.max() + band), np.any(seg < env.min() - band)
        if x is not None:
            n += bool(up if x[g] > x_clean[g] else down)
        else:
            n += bool(up or down)
    return n


def analyse_loaded(t, counts, configs=CONFIGS, backend=None):
    """Calibrate on the plateaus and measure every configuration.

    Returns dict: calibration, plateaus, glitches, lb (calibrated raw),
    outputs {config: (out_lb, stable)}, rows {config: metrics}."""
    counts = np.asarray(counts, dtype=float)
    plateaus = assign_nominal(find_plateaus(counts, RATE_HZ), STEP_LB)
    cal = calibrate([p.level for p in plateaus], [p.nominal for p in plateaus], unit="lb")
    lb = cal.to_mass(counts)
    glitches = glitch_indices(counts)
    clean_kg = deglitched(lb, glitches) * KG_PER_LB
    levels = [float(cal.to_mass(p.level)) for p in plateaus]
    outputs, rows = {}, {}
    for config in configs:
        cpk = cal.counts_per_unit / KG_PER_LB
        out_kg, stable = run_config(config, lb * KG_PER_LB, backend, cpk)
        out = out_kg / KG_PER_LB
        out_clean = run_config(config, clean_kg, backend, cpk)[0] / KG_PER_LB
        outputs[config] = (out, stable)
        settle, motion, missed, errs, noise = [], [], 0, [], []
        for k, p in enumerate(plateaus):
            half = np.arange(p.start + (p.stop - p.start) // 2, p.stop)
            half = half[~np.isin(half, glitches)]
            tail = out[max(p.stop - int(RATE_HZ), p.start):p.stop]
            if abs(np.median(tail) - levels[k]) > MISSED_BAND_LB:
                missed += 1
            errs.append(abs(float(np.median(out[half])) - p.nominal))
            noise.append(float(np.std(out[half])))
            if k > 0:
                start = plateaus[k - 1].stop
                end = p.stop - END_GUARD
                idx = settle_index(out, levels[k], SETTLE_BAND_LB, start, end)
                if idx is not None and end - idx < RATE_HZ:
                    idx = None
                settle.append(None if idx is None else (idx - start) / RATE_HZ)
                motion.append((p.start - start) / RATE_HZ)
        rows[config] = {
            "glitches_passed": glitches_passed(out, out_clean, glitches, GLITCH_BAND_LB,
                                               lb, clean_kg / KG_PER_LB),
            "glitches": int(glitches.size),
            "plateaus_missed": missed,
            "plateaus": len(plateaus),
            "settle_s": settle,
            "motion_s": motion,
            "settle_s_max": None if any(s is None for s in settle) else max(settle),
            "steps_settled": sum(s is not None for s in settle),
            "plateau_err_lb_max": max(errs),
            "plateau_noise_lb": max(noise),
        }
    return {"calibration": cal, "plateaus": plateaus, "levels_lb": levels, "glitches": glitches,
            "lb": lb, "outputs": outputs, "rows": rows}


def analyse_zero(t, counts, lb_per_count, configs=CONFIGS, backend=None):
    """A no-load channel: zero noise and drift before and after filtering.

    These cells have no calibration of their own: counts become lb with
    another channel's sensitivity (`lb_per_count`) about the level of the
    first still segment (the zero set at power-up).  They are not still all
    the time (the rig is touched at the start and near the end), so noise and
    drift are measured on the longest still segment that find_plateaus
    finds, without its first ZERO_WARMUP_S and last ZERO_TAIL_S."""
    t = np.asarray(t, dtype=float)
    counts = np.asarray(counts, dtype=float)
    glitches = glitch_indices(counts)
    still = find_plateaus(counts, RATE_HZ)
    if not still:
        raise InsufficientDataError("analyse_zero: no still segment in the channel")
    seg = max(still, key=lambda p: p.stop - p.start)
    lb = (counts - still[0].level) * lb_per_count
    clean_kg = deglitched(lb, glitches) * KG_PER_LB
    idx = np.arange(seg.start + int(ZERO_WARMUP_S * RATE_HZ), seg.stop - int(ZERO_TAIL_S * RATE_HZ))
    idx = idx[~np.isin(idx, glitches)]
    outputs, rows = {}, {}
    for config in configs:
        cpk = 1.0 / (lb_per_count * KG_PER_LB)
        out_kg, stable = run_config(config, lb * KG_PER_LB, backend, cpk)
        out = out_kg / KG_PER_LB
        out_clean = run_config(config, clean_kg, backend, cpk)[0] / KG_PER_LB
        outputs[config] = (out, stable)
        line = fit_poly(t[idx], out[idx], 1, what=f"zero drift ({config})")
        rows[config] = {
            "glitches_passed": glitches_passed(out, out_clean, glitches, GLITCH_BAND_LB,
                                               lb, clean_kg / KG_PER_LB),
            "glitches": int(glitches.size),
            "still_from_s": float(t[idx[0]]), "still_to_s": float(t[idx[-1]]),
            "zero_noise_lb": float(np.std(out[idx] - line(t[idx]))),
            "zero_drift_lb": float(line(t[idx[-1]]) - line(t[idx[0]])),
        }
    return {"glitches": glitches, "lb": lb, "outputs": outputs, "rows": rows, "still": seg}


def plot_channel(path, t, result, title, configs=CONFIGS, nominal=True):
    """PNG: raw, each configuration, nominal levels, stability flags; for a
    loaded channel also a close-up of the step the default (auto) chain
    takes longest to settle on, with the +-SETTLE_BAND_LB band."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = np.asarray(t, dtype=float)
    lb = result["lb"]
    glitches = result["glitches"]
    zoom = nominal and "plateaus" in result and "auto" in result["rows"]
    fig = plt.figure(figsize=(13 if zoom else 11, 6))
    grid = fig.add_gridspec(2, 2 if zoom else 1, height_ratios=[5, 1],
                            width_ratios=[3, 1] if zoom else None)
    ax = fig.add_subplot(grid[0, 0])
    axs = fig.add_subplot(grid[1, 0], sharex=ax)
    colors = {"raw": "0.7", "paper_chain": "tab:red", "kalman": "tab:orange", "recommended": "tab:purple",
              "auto": "tab:blue", "recommended_fixed": "tab:pink", "auto_fixed": "tab:cyan"}
    ok = np.ones(lb.size, dtype=bool)
    ok[glitches] = False
    lo, hi = np.min(lb[ok]), np.max(lb[ok])
    pad = 0.08 * (hi - lo) + 0.5
    for config in configs:
        out, _ = result["outputs"][config]
        off = config != "raw" and (np.min(out) < lo - pad or np.max(out) > hi + pad)
        ax.plot(t, out, color=colors[config], lw=0.8 if config == "raw" else 1.4,
                label=config + (" (leaves the plot: glitches)" if off else ""))
    ax.set_ylim(lo - pad, hi + pad)
    for g in glitches:
        ax.annotate("glitch", (t[g], lo - pad), xytext=(t[g], lo - 0.5 * pad), fontsize=7,
                    color="0.4", ha="center", arrowprops=dict(arrowstyle="->", color="0.5"))
    if nominal and "plateaus" in result:
        for p in result["plateaus"]:
            ax.hlines(p.nominal, t[p.start], t[p.stop - 1], colors="k", linestyles="--", lw=0.8)
        ax.plot([], [], "k--", lw=0.8, label="nominal level (found plateaus)")
    ax.set_ylabel("lb")
    ax.set_title(title, fontsize=10)
    ax.legend(loc="upper right", fontsize=8)
    ax.grid(alpha=0.3)
    rows = [c for c in configs if result["outputs"][c][1] is not None]
    for i, config in enumerate(rows):
        stable = result["outputs"][config][1]
        axs.fill_between(t, i, i + 0.8 * stable, step="post", color=colors[config], alpha=0.7)
    axs.set_yticks([i + 0.4 for i in range(len(rows))], [f"{c} stable" for c in rows], fontsize=7)
    axs.set_xlabel("t (s)")
    if zoom:
        _plot_zoom(fig.add_subplot(grid[:, 1]), t, result, colors)
    fig.tight_layout()
    try:
        with atomic_output(path, "wb") as fh:
            fig.savefig(fh, format="png", dpi=110)
    finally:
        plt.close(fig)


def _plot_zoom(ax, t, result, colors):
    settle = result["rows"]["auto"]["settle_s"]
    known = [(s, k) for k, s in enumerate(settle) if s is not None]
    k = (max(known)[1] if known else 0) + 1          # plateau index after the slowest step
    plateaus, level = result["plateaus"], result["levels_lb"][k]
    a = plateaus[k - 1].stop - int(2 * RATE_HZ)
    b = min(plateaus[k].stop, plateaus[k - 1].stop + int(12 * RATE_HZ))
    sl = slice(max(a, 0), b)
    for config in ("raw", "paper_chain", "recommended", "auto"):
        if config in result["outputs"]:
            ax.plot(t[sl], result["outputs"][config][0][sl], color=colors[config],
                    lw=0.8 if config == "raw" else 1.4)
    ax.axhspan(level - SETTLE_BAND_LB, level + SETTLE_BAND_LB, color="tab:green", alpha=0.25,
               label=f"level +-{SETTLE_BAND_LB} lb")
    t0 = t[plateaus[k - 1].stop]
    ax.axvline(t0, color="k", lw=0.8, ls=":", label="previous plateau ends")
    if settle[k - 1] is not None:
        ax.axvline(t0 + settle[k - 1], color="tab:blue", lw=0.8, ls=":",
                   label=f"default (auto) settled: {settle[k - 1]:.1f} s")
    ax.set_ylim(level - 0.6, level + 0.6)
    ax.set_title(f"close-up: step to {plateaus[k].nominal:g} lb", fontsize=9)
    ax.set_xlabel("t (s)")
    ax.legend(loc="lower right", fontsize=7)
    ax.grid(alpha=0.3)
