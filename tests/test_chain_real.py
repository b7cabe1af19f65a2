"""The chain on a real HX711 recording (../shared/data/hx711_steps_10hz:
two load cells, 10-lb steps 0 -> 40 -> 0 lb put on by hand, ~1000 counts/lb,
read glitches near -2^23).  Behaviour with margins, not exact numbers:
the recommended preset and the default (auto) let no glitch through, reaches every
plateau and settles; the weighing paper's parameters lock out on the first step.

Measured (default chain, float and fixed): the output settles, from the
first sample that leaves the previous level by 300 counts to within 50
counts (0.05 lb) for good, in lc1 1.2-6.2 s (median 2.0 s), lc2 0.9-2.8 s
(median 1.7 s); the 6.2 s plateau is one whose raw level itself wanders by
~60 counts.  The stable flag is never raised on a plateau sample more than
3 sigma (210 counts) off the load and is up on 87-100 % of the samples of
each plateau; it drops while the load still creeps (the output moves by
more than sigma over a window), so "stable and within 0.05 lb for good"
comes later, up to 14.3 s on lc1, and on the first plateau of lc2 a late
creep drops it again before the plateau ends.  The bounds sit just above
these figures."""
import numpy as np
import pytest
from scipy.ndimage import median_filter

from conftest import require_shared_data
from pysig.weigh import Chain
from pysig.io import read_csv

FS = 10.0
COUNTS_PER_LB = 1000.0
TOL = 50.0                                   # 0.05 lb
SETTLE_MAX_S = {"lc1_counts": 6.5, "lc2_counts": 3.5}   # measured 6.2 s and 2.8 s (docstring)
SIGMA = 70.0                                 # plateau noise, counts (PROVENANCE.md)
MIN_STABLE_SHARE = 0.8                       # measured 0.87 at least


@pytest.fixture(scope="module")
def rec():
    return read_csv(require_shared_data("hx711_steps_10hz/hx711_steps_10hz.csv"))


def plateaus(x):
    """(start, end) of each plateau: runs of >= 6 s where a 15-sample median
    sits on one 10-lb level above the starting level."""
    m = median_filter(x, 15, mode="nearest")
    level = np.round((m - np.median(m[:100])) / (10 * COUNTS_PER_LB)).astype(int)
    edges = np.flatnonzero(np.diff(level)) + 1
    bounds = zip(np.r_[0, edges], np.r_[edges, x.size])
    return [(a, b) for a, b in bounds if b - a >= 60]


def settle_times(x, out):
    segs = plateaus(x)
    times = []
    for k in range(1, len(segs)):
        (pa, pb), (a, b) = segs[k - 1], segs[k]
        prev, target = np.median(x[pa + 30:pb - 25]), np.median(x[a + 30:b - 25])
        start = pb - 10 + int(np.flatnonzero(np.abs(x[pb - 10:b] - prev) > 300)[0])
        ok = np.abs(out[start:b - 25] - target) <= TOL
        bad = np.flatnonzero(~ok)
        times.append(np.inf if bad.size and bad[-1] == ok.size - 1 else (bad[-1] + 1) / FS if bad.size else 0.0)
    return np.array(times)


@pytest.mark.parametrize("fixed", [False, True])
@pytest.mark.parametrize("channel", ["lc1_counts", "lc2_counts"])
def test_recommended_on_loaded_cells(rec, channel, fixed):
    x = rec[channel]
    out, stable, status = Chain(fixed=fixed).process(x, flags=True)
    glitches = np.flatnonzero(x < -1e6)
    assert glitches.size == 4
    good = np.delete(x, glitches)
    # no glitch reaches the output
    assert out.min() > good.min() - 500
    assert np.all(np.abs(out[glitches] - out[glitches - 1]) < 500)
    assert np.all(status[glitches] & 4)
    segs = plateaus(x)
    assert len(segs) == 9                     # 0, 10, 20, 30, 40, 30, 20, 10, 0 lb
    for a, b in segs:                         # every plateau reached: no lock-out
        target = np.median(x[a + 30:b - 25])
        assert abs(np.mean(out[b - 45:b - 15]) - target) < TOL
        assert np.std(out[a + 40:b - 25]) < np.std(x[a + 40:b - 25]) / 1.4
        held = slice(a, b - 25)
        # stable only when right, and up on most of the plateau
        assert not np.any(stable[held] & (np.abs(out[held] - target) > 3 * SIGMA))
        assert stable[a + 30:b - 25].mean() >= MIN_STABLE_SHARE
    t = settle_times(x, out)
    assert np.all(t <= SETTLE_MAX_S[channel]) and np.median(t) <= 2.3, t


@pytest.mark.parametrize("channel", ["lc1_counts", "lc2_counts"])
def test_paper_parameters_lock_out_on_the_first_step(rec, channel):
    x = rec[channel]
    out, _ = Chain(preset="paper", units_per_kg=COUNTS_PER_LB / 0.45359237).process(x)
    base = np.median(x[:100])
    # the load goes up to 40 lb; the weighing paper's chain never gets near even 20 lb
    assert np.max(out) < base + 15 * COUNTS_PER_LB


@pytest.mark.parametrize("channel", ["lc3_counts", "lc4_counts", "lc5_counts", "lc6_counts"])
def test_unloaded_cells_quiet_and_glitch_free(rec, channel):
    x = rec[channel]
    out, stable = Chain().process(x)
    good = x[x > -1e6]
    assert out.min() > good.min() - 500 and out.max() < good.max() + 500
    assert np.std(out[50:]) < np.std(good)
    assert stable[50:].mean() > 0.5


@pytest.mark.parametrize("channel", ["lc1_counts", "lc2_counts", "lc3_counts"])
def test_fixed_form_tracks_the_float_form(rec, channel):
    """Integer codes, rounded window means and a Q24.7 state cost less than
    one count against the double chain on this recording (measured: at most
    0.87 counts; stability flags differ on at most 1 of 1324 samples)."""
    x = rec[channel]
    a, sa = Chain("recommended").process(x)
    b, sb = Chain("recommended", fixed=True).process(x)
    assert np.max(np.abs(a - b)) < 1.5
    assert np.count_nonzero(sa != sb) <= 3


@pytest.mark.parametrize("channel", ["lc1_counts", "lc2_counts", "lc3_counts"])
def test_fixed_auto_follows_the_float_auto(rec, channel):
    """The default (auto): the fixed form measures its own noise (Q24.7,
    truncating steps, a quarter-code floor), so its thresholds differ a
    little and a restart or the end of settling can fall a sample apart;
    on most samples the two agree within a fraction of a count, and within
    a tenth of the noise (~100 counts here) on 95 % (measured: median
    0.04-0.06 counts, 95th percentile at most 7.5 counts, stability flags
    differ on at most 12 of 1324)."""
    x = rec[channel]
    a, sa = Chain().process(x)
    b, sb = Chain(fixed=True).process(x)
    d = np.abs(a - b)
    assert np.median(d) < 0.25 and np.percentile(d, 95) < 10.0
    assert np.count_nonzero(sa != sb) <= 20
