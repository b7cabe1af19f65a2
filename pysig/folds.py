"""Blocked cross-validation folds: contiguous blocks of samples held out in
turn, so a score measures prediction across a gap, not memory of the
neighbouring samples.  One implementation for both of its users:

* refine cuts the record in time into blocks of equal sample count, and
  leaves a guard band of `gap` samples on each side of the held-out block
  out of training (a lag or a drift cannot leak into the test block);
* tcomp's model choice cuts the temperature range into blocks of equal
  width and never holds out the two end blocks (no fold extrapolates: the
  firmware clamps outside its calibrated range).

==================  ========================================================
equal_count_blocks  block label of each of n ordered samples (equal counts)
equal_width_blocks  block label of each value (equal-width bins of its range)
held_out_blocks     (train, test) masks, each non-empty block held out in turn
==================  ========================================================
"""
import numpy as np

__all__ = ["equal_count_blocks", "equal_width_blocks", "held_out_blocks"]


def equal_count_blocks(n, n_blocks):
    """Block label (0 .. n_blocks-1) of each of `n` ordered samples: contiguous
    runs whose sizes differ by at most one (edges at round(k n / n_blocks))."""
    edges = np.linspace(0, n, n_blocks + 1).round().astype(int)
    return np.searchsorted(edges, np.arange(n), side="right") - 1


def equal_width_blocks(x, n_blocks):
    """Block label of each value of `x`: `n_blocks` equal-width bins from its
    minimum to its maximum (the maximum falls in the last bin).  The caller
    makes sure the range is not empty."""
    x = np.asarray(x, dtype=float)
    lo, hi = float(x.min()), float(x.max())
    return np.minimum(((x - lo) / (hi - lo) * n_blocks).astype(int), n_blocks - 1)


def held_out_blocks(labels, n_blocks, gap=0, keep_ends=False):
    """(train, test) boolean masks, each non-empty block of `labels` held out
    in turn.  Training leaves out the test block and every sample within
    `gap` positions of it; with `keep_ends` the first and last block are
    never held out."""
    labels = np.asarray(labels)
    n = labels.size
    blocks = range(1, n_blocks - 1) if keep_ends else range(n_blocks)
    out = []
    for b in blocks:
        test = labels == b
        if not test.any():
            continue
        if gap > 0:
            # samples within `gap` positions of a test sample (a moving
            # window count over the test mask)
            count = np.concatenate([[0], np.cumsum(test)])
            idx = np.arange(n)
            near = count[np.minimum(n, idx + gap + 1)] - count[np.maximum(0, idx - gap)] > 0
        else:
            near = test
        out.append((~near, test))
    return out
