"""What a fleet fit leaves in its output directory: per device the model
(``<device>.json``) and its NVM image carrying the device's serial
(``<device>.bin``), ``fleet_summary.csv`` with one row per device, and the
fleet plots.  The directory appears whole or not at all: everything is
written into a temporary directory beside it, then renamed into place.

Screening.  A device is flagged when any of its fit errors (held-out RMS per
axis, in-sample RMS where cross-validation was impossible) or drifts (mean
slope of the correction, reading units per °C, per axis) lies outside the
fleet's robust spread, median +- k * MAD (MAD = median absolute deviation
from the median, over the fitted devices), or when it could not be fitted
(too few temperatures and the other reasons of pysig.fleet._fit)."""
import hashlib
import json
import os
import re
import shutil
import tempfile

import numpy as np

from ..errors import OutputFileError
from ..io import write_csv
from ..store._device import device_section
from ..store._image import model_image
from ..tcomp import _poly_model as tmodel

DEFAULT_K = 5.0
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


def robust_outliers(values, ok, k):
    """(outside, median, mad) of one metric: outside median +- k * MAD,
    judged over the fitted devices; NaN never counts as outside."""
    v = values[ok & np.isfinite(values)]
    if v.size == 0:
        return np.zeros(values.shape, dtype=bool), np.nan, np.nan
    med = float(np.median(v))
    mad = float(np.median(np.abs(v - med)))
    floor = 1e-12 * max(abs(med), 1.0)                   # identical devices: nobody is an outlier
    with np.errstate(invalid="ignore"):
        outside = np.abs(values - med) > k * max(mad, floor)
    return outside & ok & np.isfinite(values), med, mad


def screen(fit, k=DEFAULT_K):
    """Per device (flagged, reason), and per metric (median, MAD, outside mask)."""
    D = len(fit.devices)
    flagged = ~fit.ok.copy()
    reason = np.array([f"not fitted: {r}" if r else "" for r in fit.reason], dtype=object)
    spread = {}
    err = np.where(np.isnan(fit.cv_rms), fit.rms, fit.cv_rms)
    for i, axis in enumerate(fit.axes):
        for name, values, unit in ((f"fit error {axis}", err[:, i], ""), (f"drift {axis}", fit.drift[:, i], "/°C")):
            out, med, mad = robust_outliers(values, fit.ok, k)
            spread[name] = (med, mad, out)
            for d in np.flatnonzero(out):
                text = f"{name} {values[d]:.4g}{unit} outside {med:.4g} +- {k:g}*{mad:.3g}"
                reason[d] = f"{reason[d]}; {text}" if reason[d] else text
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


def fleet_plots(fit, flagged, spread, k, directory, worst=5):
    """fleet_coefficients.png (distribution of each axis' drift and fit
    error, the median +- k*MAD limits, the devices outside them marked) and
    fleet_worst.png (the correction delta(T) of the fleet, median and 5-95 %
    band, against the devices furthest from it)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    ok = fit.ok
    err = np.where(np.isnan(fit.cv_rms), fit.rms, fit.cv_rms)
    A = len(fit.axes)
    fig, ax = plt.subplots(2, A, figsize=(4 * A, 6), squeeze=False)
    for i, a in enumerate(fit.axes):
        for row, (values, name, label) in enumerate(
                ((fit.drift[:, i], f"drift {a}", f"drift {a} (units/°C)"),
                 (err[:, i], f"fit error {a}", f"fit error {a} (RMS, units)"))):
            ax[row, i].hist(values[ok], bins=60, color="0.6")
            med, mad, outside = spread[name]
            if np.isfinite(med):
                for edge in (med - k * mad, med + k * mad):
                    ax[row, i].axvline(edge, color="b", lw=0.8, ls="--")
            bad = values[outside]
            ax[row, i].plot(bad, np.zeros_like(bad), "r|", ms=14, label=f"outside median +- {k:g} MAD ({bad.size})")
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


def write_fleet(fit, directory, k=DEFAULT_K, temp_column="temp", plots=True):
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
        flagged, reason, spread = screen(fit, k)
        write_models(fit, staging, temp_column)
        write_csv(os.path.join(staging, SUMMARY), summary_columns(fit, flagged, reason))
        if plots:
            fleet_plots(fit, flagged, spread, k, staging)
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
