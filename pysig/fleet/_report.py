"""What a fleet fit leaves in its output directory: per device the model
(``<device>.json``) and its NVM image carrying the device's serial
(``<device>.bin``), ``fleet_summary.csv`` with one row per device, and the
fleet plots.  The directory appears whole or not at all: everything is
written into a temporary directory beside it, then renamed into place.

Screening.  Every statistic is tested against its distribution for a good
unit, so the share of good units flagged is what the screening is built
for: `false_flag_rate` (default 0.5 %).  Per device and axis:

* noise: the variance of the residual within the temperature groups, s^2 on
  nu = samples - groups degrees of freedom; a good unit has the fleet's
  noise sigma^2 (estimated as the median of s^2 / (median of chi2_nu / nu)
  over the fitted devices), so nu s^2 / sigma^2 ~ chi2_nu; two-sided (a
  noisy channel, or a stuck one);
* lack of fit: F = (lack-of-fit variance) / s^2 ~ F(groups - order - 1, nu)
  when a polynomial of the order most of the fleet chose follows the unit
  (the classic lack-of-fit test); with one sample per temperature (plateau
  means, nu = 0) the lack-of-fit variance against the fleet's, as chi2
  above; not tested on an axis where the fleet's median p is below 0.01
  (the typical unit is not followed: too few temperatures for its shape);
* drift (mean slope of the correction) and curvature (u^2 coefficient of an
  order-2 fit): a robust z against the fleet, (v - median) / (1.4826 MAD),
  ~ N(0, 1) for a fleet whose good units' coefficients spread normally.

A device is flagged when the smallest p-value of its tests is below
false_flag_rate / (number of its tests) (Bonferroni: a good unit is
flagged with probability at most false_flag_rate), or when it could not be
fitted (too few temperatures and the other reasons of pysig.fleet._fit).
Where it stops working: readings quantised coarser than their noise (noise
below ~0.5 LSB, where s^2 is no longer chi-square), noise that differs
between good units, and coefficients whose fleet spread is far from
normal (heavy tails are flagged)."""
import hashlib
import json
import os
import re
import shutil
import tempfile

import numpy as np
from scipy import stats

from ..errors import OutputFileError
from ..io import write_csv
from ..store._device import device_section
from ..tcomp._sections import model_image
from ..tcomp import _poly_model as tmodel

DEFAULT_FALSE_FLAG_RATE = 0.005       # the share of good units the screening is built to flag
MAD_TO_SIGMA = 1.4826                 # sigma of a normal distribution / its MAD
FLEET_LACK_OF_FIT_P = 0.01            # a median lack-of-fit p below this: the fleet's shape, untested
SUMMARY = "fleet_summary.csv"
_SAFE = re.compile(r"[^A-Za-z0-9._-]")


def file_stem(serial):
    """A file name for a serial: itself when it is made of [A-Za-z0-9._-]
    (and not '.' or '..'), else the safe characters plus a short hash, so two
    serials never share a file."""
    s = str(serial)
    safe = _SAFE.sub("_", s)
    if safe == s and s not in (".", "..") and not s.startswith("."):
        return s
    return f"{safe.lstrip('.')[:40]}-{hashlib.sha256(s.encode()).hexdigest()[:10]}"


def robust_z(values, ok):
    """(z, median, MAD) of one coefficient against the fitted devices:
    z = (v - median) / (1.4826 MAD); NaN stays NaN."""
    v = values[ok & np.isfinite(values)]
    if v.size == 0:
        return np.full(values.shape, np.nan), np.nan, np.nan
    med = float(np.median(v))
    mad = float(np.median(np.abs(v - med)))
    floor = 1e-12 * max(abs(med), 1.0)                   # identical devices: nobody is an outlier
    return (values - med) / (MAD_TO_SIGMA * max(mad, floor)), med, mad


def fleet_variance(var, dof, ok):
    """The fleet's variance behind per-device variances var ~ sigma^2 chi2_dof / dof:
    the median of var / (median of chi2_dof / dof) over the devices with dof > 0."""
    use = ok & (dof > 0) & np.isfinite(var)
    if not np.any(use):
        return np.nan
    return float(np.median(var[use] / (stats.chi2.median(dof[use]) / dof[use])))


def chi2_two_sided(var, sigma2, dof):
    """p of var ~ sigma2 chi2_dof / dof, two-sided; NaN where not testable."""
    with np.errstate(invalid="ignore", divide="ignore"):
        x = dof * var / sigma2
        p = 2 * np.minimum(stats.chi2.sf(x, dof), stats.chi2.cdf(x, dof))
    return np.where((dof > 0) & np.isfinite(var) & (sigma2 > 0), np.minimum(p, 1.0), np.nan)


def screen_tests(fit):
    """{test name: (p-values per device, statistic per device, text(d))} for every axis."""
    ok = fit.ok
    out = {}
    noise_var, noise_dof, lof_var, lof_dof = fit.at_screening_order()
    for i, axis in enumerate(fit.axes):
        sigma2 = fleet_variance(noise_var[:, i], noise_dof, ok)
        p = chi2_two_sided(noise_var[:, i], sigma2, noise_dof)
        rms = np.sqrt(noise_var[:, i])
        out[f"noise {axis}"] = (p, rms, lambda d, rms=rms, s=sigma2, axis=axis: (
            f"noise {axis}: within-plateau RMS {rms[d]:.4g} vs the fleet's {np.sqrt(s):.4g}"))
        with np.errstate(invalid="ignore", divide="ignore"):
            F = lof_var[:, i] / noise_var[:, i]
            p_f = stats.f.sf(F, lof_dof, noise_dof)
        p_f = np.where((lof_dof > 0) & (noise_dof > 0) & np.isfinite(F), p_f, np.nan)
        means_only = (noise_dof == 0) & (lof_dof > 0)
        if np.any(means_only & ok):          # plateau means: the lack of fit against the fleet's
            s_lof = fleet_variance(lof_var[:, i], np.where(means_only, lof_dof, 0), ok)
            p_f = np.where(means_only, chi2_two_sided(lof_var[:, i], s_lof, lof_dof), p_f)
        tested = ok & np.isfinite(p_f) & ~means_only
        if np.any(tested) and np.median(p_f[tested]) < FLEET_LACK_OF_FIT_P:
            # the typical unit is not followed: the model's order (too few
            # temperatures for the fleet's shape), not the unit, is the cause
            p_f = np.where(means_only, p_f, np.nan)
        out[f"lack of fit {axis}"] = (p_f, F, lambda d, F=F, axis=axis, i=i: (
            f"lack of fit {axis}: the model leaves F = {F[d]:.3g} x the noise between temperatures "
            f"(F({lof_dof[d]}, {noise_dof[d]}))" if noise_dof[d] else
            f"lack of fit {axis}: residual of the plateau means {np.sqrt(lof_var[d, i]):.4g}"))
        for name, values, unit in (("drift", fit.drift[:, i], "/°C"), ("curvature", fit.curvature[:, i], "")):
            z, med, mad = robust_z(values, ok)
            p_z = np.where(np.isfinite(z), 2 * stats.norm.sf(np.abs(z)), np.nan)
            out[f"{name} {axis}"] = (p_z, values, lambda d, v=values, z=z, med=med, mad=mad, n=name, u=unit,
                                     axis=axis: (
                f"{n} {axis} {v[d]:.4g}{u}: z = {z[d]:.1f} against the fleet's {med:.4g} +- "
                f"{MAD_TO_SIGMA * mad:.3g}"))
    return out


def screen(fit, false_flag_rate=DEFAULT_FALSE_FLAG_RATE):
    """Per device (flagged, reason), and per test {name: (p-values, statistic, flagged by it)}."""
    flagged = ~fit.ok.copy()
    reason = np.array([f"not fitted: {r}" if r else "" for r in fit.reason], dtype=object)
    tests = screen_tests(fit)
    P = np.column_stack([p for p, _, _ in tests.values()]) if tests else np.zeros((len(fit.devices), 0))
    n_tests = np.sum(np.isfinite(P), axis=1)
    limit = false_flag_rate / np.maximum(n_tests, 1)
    spread = {}
    for j, (name, (p, stat, text)) in enumerate(tests.items()):
        out = fit.ok & np.isfinite(p) & (p < limit)
        spread[name] = (p, stat, out)
        for d in np.flatnonzero(out):
            t = f"{text(d)} (p = {p[d]:.2g} < {limit[d]:.2g})"
            reason[d] = f"{reason[d]}; {t}" if reason[d] else t
        flagged |= out
    return flagged, reason, spread


def summary_columns(fit, flagged, reason):
    """fleet_summary.csv's columns (a dict of arrays)."""
    model = np.array([f"poly:{n}" if ok else "" for n, ok in zip(fit.order, fit.ok)], dtype=object)
    cols = {"device": np.asarray([str(d) for d in fit.devices], dtype=object), "model": model,
            "n_temps": fit.n_temps.astype(np.int64), "samples": fit.samples.astype(np.int64)}
    for i, a in enumerate(fit.axes):
        cols[f"cv_rms_{a}"] = fit.cv_rms[:, i]
    for i, a in enumerate(fit.axes):
        cols[f"rms_{a}"] = fit.rms[:, i]
    for i, a in enumerate(fit.axes):
        cols[f"drift_{a}"] = fit.drift[:, i]
    noise_var = fit.at_screening_order()[0]
    for i, a in enumerate(fit.axes):
        cols[f"noise_rms_{a}"] = np.sqrt(noise_var[:, i])
    for i, a in enumerate(fit.axes):
        cols[f"curvature_{a}"] = fit.curvature[:, i]
    cols["flagged"] = flagged.astype(np.int64)
    cols["reason"] = reason
    cols["file"] = np.array([file_stem(d) if ok else "" for d, ok in zip(fit.devices, fit.ok)], dtype=object)
    return cols


def model_text(model):
    """The text TcompModel.save writes (checksummed JSON), without its
    per-file temporary file: the fleet's staging directory already makes
    the whole output appear at once."""
    d = model.to_dict()
    d[tmodel.CHECKSUM_KEY] = tmodel.checksum(d)
    return json.dumps(d, indent=2, allow_nan=False) + "\n"


def write_models(fit, directory, temp_column="temp"):
    """<stem>.json and <stem>.bin (model image + device-id section) per
    fitted device; returns the number written."""
    n = 0
    todo = np.flatnonzero(fit.ok)
    for d in _progress(todo, "devices written"):
        model = fit.model(d, temp_column)
        stem = os.path.join(directory, file_stem(fit.devices[d]))
        with open(stem + ".json", "w") as fh:       # the staging directory is what makes it atomic
            fh.write(model_text(model))
        with open(stem + ".bin", "wb") as fh:
            fh.write(model_image(model, extra_sections=[device_section(str(fit.devices[d]))]))
        n += 1
    return n


def _progress(items, what):
    """`items`, with a tqdm bar on stderr while stderr is a terminal."""
    import sys
    if not sys.stderr.isatty():
        return items
    from tqdm import tqdm
    return tqdm(items, desc=what, unit="dev", unit_scale=True, file=sys.stderr, leave=False)


def fleet_plots(fit, flagged, spread, directory, worst=5):
    """fleet_coefficients.png (per axis the drift and the within-plateau
    noise of the fleet, the devices a test flagged marked) and
    fleet_worst.png (the correction delta(T) of the fleet, median and 5-95 %
    band, against the devices furthest from it)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    ok = fit.ok
    A = len(fit.axes)
    noise_var = fit.at_screening_order()[0]
    fig, ax = plt.subplots(2, A, figsize=(4 * A, 6), squeeze=False)
    for i, a in enumerate(fit.axes):
        for row, (values, name, label) in enumerate(
                ((fit.drift[:, i], f"drift {a}", f"drift {a} (units/°C)"),
                 (np.sqrt(noise_var[:, i]), f"noise {a}", f"within-plateau noise {a} (RMS, units)"))):
            finite = values[ok & np.isfinite(values)]
            if finite.size:
                ax[row, i].hist(finite, bins=60, color="0.6")
            bad = values[spread[name][2]]
            ax[row, i].plot(bad, np.zeros_like(bad), "r|", ms=14, label=f"flagged by this test ({bad.size})")
            ax[row, i].legend(fontsize=7)
            ax[row, i].set_xlabel(label, fontsize=8)
    fig.suptitle(f"{int(ok.sum())} devices fitted, {int(flagged.sum())} flagged")
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "fleet_coefficients.png"), dpi=80)
    plt.close(fig)

    if not np.any(ok):
        return
    lo = float(np.median(fit.t_lo[ok])) / 100
    hi = float(np.median(fit.t_hi[ok])) / 100
    grid = np.linspace(lo, hi, 41)
    center = fit.t_center / 100.0
    scale = (2.0 ** (fit.u_shift + 15)) / np.maximum(fit.u_mul, 1) / 100.0
    t = np.clip(grid[None, :], (fit.t_lo / 100.0)[:, None], (fit.t_hi / 100.0)[:, None])
    u = (t - center[:, None]) / scale[:, None]
    fig, ax = plt.subplots(1, A, figsize=(4 * A, 3.5), squeeze=False)
    for i, a in enumerate(fit.axes):
        curves = np.zeros((len(fit.devices), grid.size))
        for k in range(fit.coef.shape[2] - 1, -1, -1):
            curves = curves * u + fit.coef[:, i, k][:, None]
        c_ok = curves[ok]
        med = np.median(c_ok, axis=0)
        p5, p95 = np.percentile(c_ok, [5, 95], axis=0)
        ax[0, i].fill_between(grid, p5, p95, color="0.85", label="fleet 5-95 %")
        ax[0, i].plot(grid, med, "k", label="fleet median")
        dist = np.where(ok, np.max(np.abs(curves - med[None, :]), axis=1), -1)
        for d in np.argsort(dist)[::-1][:worst]:
            if dist[d] >= 0:
                ax[0, i].plot(grid, curves[d], lw=1, label=str(fit.devices[d])[:16])
        ax[0, i].set_xlabel("temperature (°C)")
        ax[0, i].set_ylabel(f"correction delta {a}")
        ax[0, i].legend(fontsize=6)
    fig.suptitle("the devices furthest from the fleet")
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "fleet_worst.png"), dpi=80)
    plt.close(fig)


def write_fleet(fit, directory, false_flag_rate=DEFAULT_FALSE_FLAG_RATE, temp_column="temp", plots=True):
    """Write the whole output directory atomically; returns (flagged, reason, spread)."""
    directory = os.path.abspath(str(directory))
    if os.path.exists(directory) and not os.path.isdir(directory):
        raise OutputFileError(f"{directory}: exists and is not a directory")
    if os.path.isdir(directory) and os.listdir(directory) and \
            not os.path.exists(os.path.join(directory, SUMMARY)):
        raise OutputFileError(f"{directory}: not empty and not a previous fleet output "
                              f"(no {SUMMARY}): refusing to replace it")
    parent = os.path.dirname(directory)
    try:
        staging = tempfile.mkdtemp(prefix=".pysig-fleet-", dir=parent)
    except OSError as exc:
        raise OutputFileError(f"{directory}: cannot write: {exc.strerror}") from exc
    try:
        flagged, reason, spread = screen(fit, false_flag_rate)
        write_models(fit, staging, temp_column)
        write_csv(os.path.join(staging, SUMMARY), summary_columns(fit, flagged, reason))
        if plots:
            fleet_plots(fit, flagged, spread, staging)
        os.chmod(staging, 0o777 & ~_umask())
        old = None
        if os.path.isdir(directory):
            old = tempfile.mkdtemp(prefix=".pysig-old-", dir=parent)
            os.replace(directory, os.path.join(old, "previous"))
        os.replace(staging, directory)
        if old:
            shutil.rmtree(old, ignore_errors=True)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    return flagged, reason, spread


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask
