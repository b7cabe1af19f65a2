"""The one blocked-fold implementation (pysig.folds) that refine's time
blocks and tcomp's temperature blocks both use: every held-out block is
contiguous, each sample is tested once, training never touches the test
block or its guard band, and the end blocks stay in training when asked."""
import numpy as np
from hypothesis import given, strategies as st

from pysig.folds import equal_count_blocks, equal_width_blocks, held_out_blocks


@given(st.integers(1, 500), st.integers(1, 30), st.integers(0, 40))
def test_time_blocks_test_each_sample_once_behind_a_guard_band(n, n_blocks, gap):
    labels = equal_count_blocks(n, n_blocks)
    sizes = np.bincount(labels, minlength=n_blocks)
    assert sizes.max() - sizes.min() <= 1 and np.all(np.diff(labels) >= 0)
    folds = held_out_blocks(labels, n_blocks, gap=gap)
    tested = np.zeros(n, dtype=int)
    for train, test in folds:
        idx = np.flatnonzero(test)
        assert idx.size and np.all(np.diff(idx) == 1)          # contiguous
        tested += test
        far = (np.arange(n) < idx[0] - gap) | (np.arange(n) > idx[-1] + gap)
        assert np.array_equal(train, far)
    assert np.all(tested == 1)


@given(st.lists(st.floats(-40, 85), min_size=2, max_size=200), st.integers(3, 12))
def test_temperature_blocks_keep_the_ends_in_training(temps, n_blocks):
    x = np.asarray(temps)
    if not x.max() > x.min():
        return
    labels = equal_width_blocks(x, n_blocks)
    assert labels[np.argmin(x)] == 0 and labels[np.argmax(x)] == n_blocks - 1
    for train, test in held_out_blocks(labels, n_blocks, keep_ends=True):
        assert np.array_equal(train, ~test)
        assert not test[np.argmin(x)] and not test[np.argmax(x)]
        lo, hi = x[test].min(), x[test].max()
        assert not np.any((x[train] > lo) & (x[train] < hi))    # a contiguous range of x
