"""Impulses and practical significance for the refinement loop.

Impulses (read glitches) own a squared-error score: one 20 000-count glitch
outweighs an hour of a 7-count creep.  `impulse_mask` finds them on the
base model's residual with a Hampel rule (scipy.ndimage.median_filter): a
sample is an impulse when it sits more than `k` robust standard deviations
from the running median of its neighbours.  The running median follows
steps and slow structure, so a load change, a creep or a lag is not flagged;
an isolated spike is.  Impulses are left out of fitting and scoring, and the
report counts them.

Practical significance: an effect is worth adding for the error it removes
from a reported reading, which is an average over `report_s` seconds.  White
noise averages away in such a reading; a systematic error does not.
`averaged_rms` is the RMS of the residual averaged over consecutive blocks
of `report_s` (the error of a reported reading); `systematic_rms` is the
part of it that is not white noise: the mean square of the block means less
the white-noise share sigma^2 / (samples in the block), sigma from the first
differences of the residual (`white_sigma`, a MAD, so slow structure and the
odd outlier do not inflate it)."""
import numpy as np
from scipy import ndimage

MAD_TO_SIGMA = 1.4826
HAMPEL_HALF_WINDOW = 3
HAMPEL_K = 6.0


def white_sigma(e):
    """Standard deviation of the white part of `e` (NaNs skipped): the MAD
    of first differences of consecutive finite samples, / sqrt(2)."""
    e = np.asarray(e, dtype=float)
    e = e[np.isfinite(e)]
    if e.size < 3:
        return 0.0
    return float(MAD_TO_SIGMA * np.median(np.abs(np.diff(e))) / np.sqrt(2.0))


def impulse_mask(residual, mask, k=HAMPEL_K, half_window=HAMPEL_HALF_WINDOW):
    """Boolean array, True at the samples (within `mask`) that are impulses:
    |r - running median of 2*half_window+1 neighbours| > k * sigma, sigma
    the MAD of those deviations.  Masked-out samples are skipped (the
    neighbours are the nearest used samples)."""
    residual = np.asarray(residual, dtype=float)
    out = np.zeros(residual.size, dtype=bool)
    idx = np.flatnonzero(mask)
    if idx.size < 2 * half_window + 2:
        return out
    r = residual[idx]
    dev = r - ndimage.median_filter(r, size=2 * half_window + 1, mode="nearest")
    sigma = MAD_TO_SIGMA * float(np.median(np.abs(dev - np.median(dev))))
    if not sigma > 0:
        return out
    out[idx] = np.abs(dev) > k * sigma
    return out


def block_means(e, per_block):
    """Means of consecutive blocks of `per_block` samples (NaNs skipped) and
    the number of finite samples in each; blocks with none are dropped.
    The blocks are np.array_split's (sizes differ by at most one), summed
    at once (np.add.reduceat): the loop scores many residuals."""
    e = np.asarray(e, dtype=float)
    n_blocks = max(1, e.size // per_block)
    if e.size == 0:
        return np.zeros(0), np.zeros(0)
    size, extra = divmod(e.size, n_blocks)
    starts = np.concatenate([[0], np.cumsum([size + 1] * extra + [size] * (n_blocks - extra))[:-1]])
    ok = np.isfinite(e)
    sums = np.add.reduceat(np.where(ok, e, 0.0), starts)
    counts = np.add.reduceat(ok.astype(float), starts)
    has = counts > 0
    return sums[has] / counts[has], counts[has]


def samples_per_report(dt, report_s):
    """Samples in one reported reading (at least 1)."""
    return int(max(1, round(report_s / dt))) if dt > 0 else 1


def averaged_rms(e, per_block):
    """RMS of the residual averaged over blocks of `per_block` samples: the
    error of a reading reported as such an average."""
    m, _ = block_means(e, per_block)
    return float(np.sqrt(np.mean(m ** 2))) if m.size else float("nan")


def systematic_rms(e, per_block, sigma=None):
    """The part of averaged_rms that is not white noise:
    sqrt(max(0, mean(block_mean^2 - sigma^2 / count)))."""
    m, c = block_means(e, per_block)
    if not m.size:
        return float("nan")
    sigma = white_sigma(e) if sigma is None else sigma
    return float(np.sqrt(max(0.0, float(np.mean(m ** 2 - sigma ** 2 / c)))))


def figures(e, per_block):
    """Per-sample and reported-reading figures of one residual (NaN = not
    used): rms, averaged_rms, systematic_rms, white_sigma."""
    e = np.asarray(e, dtype=float)
    f = e[np.isfinite(e)]
    sigma = white_sigma(e)
    return {"rms": float(np.sqrt(np.mean(f ** 2))) if f.size else float("nan"),
            "averaged_rms": averaged_rms(e, per_block),
            "systematic_rms": systematic_rms(e, per_block, sigma),
            "white_sigma": sigma}
