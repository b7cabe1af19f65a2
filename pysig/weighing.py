"""Scale calibration and the figures of a weighing run.

- calibrate(): least-squares line counts -> mass from standard masses, with
  pysig.lsq.fit_poly (the same solver as the temperature fit), its linearity
  error and sensitivity.  The result applies itself in float and converts to
  the fixed-point image that csrc/sig_scale.c applies on the MCU.
- find_plateaus() / assign_nominal(): where a recording holds a load still,
  found from the data (no hand-picked indices), and which nominal level each
  plateau is.
- settle_index(), glitch_indices(): the measurements the benches report.
"""
from dataclasses import dataclass

import numpy as np
from scipy.ndimage import maximum_filter1d, median_filter, minimum_filter1d

from .errors import InsufficientDataError, RangeError
from .lsq import fit_poly
from .reference import scale as ref_scale


@dataclass(frozen=True)
class Calibration:
    """mass = (counts - offset_counts) * gain  (gain in unit per count)."""
    offset_counts: float
    gain: float
    unit: str
    linearity_err_pct_fs: float   # max |fit residual| / largest calibration mass, %
    residual_rms: float           # fit residual RMS, in `unit`
    full_scale: float             # largest calibration mass, in `unit`

    @property
    def counts_per_unit(self):
        """Sensitivity in ADC codes per unit of mass."""
        return 1.0 / self.gain

    def to_mass(self, counts):
        """Float path (the same formula as csrc sig_scale_apply_f)."""
        return ref_scale.apply_f(counts, self.offset_counts, self.gain)

    def fixed(self, out_frac=16):
        """The integer image for csrc/sig_scale.c (see reference.scale.quantize)."""
        return ref_scale.quantize(self.offset_counts, self.gain, out_frac)


def calibrate(counts, masses, unit="kg"):
    """Least-squares straight line mass(counts) through (counts[i], masses[i]).

    `counts` are the mean readings at each standard mass (the paper averages
    5 readings per mass).  Needs at least 2 distinct masses."""
    counts = np.asarray(counts, dtype=float).ravel()
    masses = np.asarray(masses, dtype=float).ravel()
    if counts.size != masses.size:
        raise RangeError(f"calibrate: {counts.size} readings for {masses.size} masses")
    if np.unique(masses).size < 2:
        raise InsufficientDataError(
            f"calibrate: a line needs at least 2 distinct masses, got {np.unique(masses).size}")
    fit = fit_poly(counts, masses, 1, what="scale calibration")
    gain = fit.coef[1] / fit.scale
    if gain == 0:
        raise InsufficientDataError("calibrate: the readings do not change with the mass")
    offset = fit.center - fit.coef[0] / gain
    resid = masses - fit(counts)
    full_scale = float(np.max(np.abs(masses)))
    return Calibration(offset_counts=float(offset), gain=float(gain), unit=unit,
                       linearity_err_pct_fs=float(100.0 * np.max(np.abs(resid)) / full_scale),
                       residual_rms=fit.rms, full_scale=full_scale)


# ---- plateaus -------------------------------------------------------------

@dataclass(frozen=True)
class Plateau:
    start: int        # first sample index
    stop: int         # one past the last sample
    level: float      # median of the raw samples in [start, stop)
    nominal: float = float("nan")


def noise_sigma(x):
    """Robust per-sample noise: MAD of first differences / sqrt(2).  Isolated
    glitches and load steps are a few differences out of many and do not move it."""
    d = np.diff(np.asarray(x, dtype=float))
    return float(1.4826 * np.median(np.abs(d - np.median(d))) / np.sqrt(2.0))


def find_plateaus(x, rate_hz, min_s=3.0, window_s=1.0, k_sigma=6.0, trim_s=0.0):
    """Intervals where the load is still, found from the data.

    A 5-sample running median removes isolated glitches; a sample is steady
    when the running median moves by no more than k_sigma * sigma (sigma from
    noise_sigma) over the centred window of window_s; steady runs of at least
    min_s seconds are plateaus, each trimmed by trim_s at both ends."""
    x = np.asarray(x, dtype=float)
    if x.size < 5:
        raise InsufficientDataError(f"find_plateaus: {x.size} samples, need at least 5")
    sigma = noise_sigma(x)
    med = median_filter(x, size=5, mode="nearest")
    w = max(int(round(window_s * rate_hz)), 2)
    hi = maximum_filter1d(med, size=w, mode="nearest")
    lo = minimum_filter1d(med, size=w, mode="nearest")
    steady = (hi - lo) <= k_sigma * sigma
    min_len = int(round(min_s * rate_hz))
    trim = int(round(trim_s * rate_hz))
    plateaus = []
    edges = np.flatnonzero(np.diff(np.concatenate(([0], steady.astype(np.int8), [0]))))
    for a, b in zip(edges[::2], edges[1::2]):
        a, b = a + trim, b - trim
        if b - a >= min_len:
            plateaus.append(Plateau(int(a), int(b), float(np.median(x[a:b]))))
    return plateaus


def assign_nominal(plateaus, step, tol_frac=0.25):
    """Nominal level of each plateau for loads put on in equal steps from zero.

    Plateau levels are grouped (levels closer than tol_frac of the smallest
    gap between groups belong together); the lowest group is 0, the next
    `step`, then 2*step, ...  Returns new Plateau objects with `nominal` set."""
    if not plateaus:
        raise InsufficientDataError("assign_nominal: no plateaus")
    levels = np.array([p.level for p in plateaus])
    order = np.sort(levels)
    gaps = np.diff(order)
    if gaps.size == 0:
        groups = np.zeros(1)
    else:
        big = gaps.max()
        split = gaps > tol_frac * big
        groups_sorted = np.concatenate(([0], np.cumsum(split)))
        groups = groups_sorted[np.searchsorted(order, levels)]
    return [Plateau(p.start, p.stop, p.level, float(g * step)) for p, g in zip(plateaus, groups)]


# ---- measurements ---------------------------------------------------------

def settle_index(out, target, band, start, stop, stable=None):
    """First index i in [start, stop) from which out stays within target +-
    band up to stop (and, when `stable` is given, stable[i] is set).
    Returns None when the output never settles in the interval."""
    seg = np.abs(np.asarray(out[start:stop], dtype=float) - target) > band
    if seg.size == 0:
        return None
    bad = np.flatnonzero(seg)
    first = 0 if bad.size == 0 else int(bad[-1]) + 1
    if first >= seg.size:
        return None
    if stable is not None:
        ok = np.flatnonzero(np.asarray(stable[start + first:stop], dtype=bool))
        if ok.size == 0:
            return None
        first += int(ok[0])
    return start + first


def glitch_indices(x, k_sigma=50.0):
    """Isolated read glitches: samples further than k_sigma * noise from the
    5-sample running median (real HX711 glitches are millions of codes off)."""
    x = np.asarray(x, dtype=float)
    med = median_filter(x, size=5, mode="nearest")
    return np.flatnonzero(np.abs(x - med) > k_sigma * noise_sigma(x))
