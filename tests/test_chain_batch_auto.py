"""The default chain (auto: noise measured on the fly, thresholds following
it) on the batch entry point (sig_chain_process_f: process() without flags)
gives the same bits as the step loop (process(flags=True)): outputs, stable
flags, the last status and the whole state, over signals with plateaus,
steps, ramps, glitches and non-finite samples, split at random points, with
a tare in between.  The batch path runs its fast path in the steady state
here too (the noise estimator, its gate and the thresholds inside it)."""
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from pysig.weigh import Chain

from test_chain import _state, split
from test_chain_noise import auto_kwargs

SETTINGS = settings(max_examples=150, deadline=None)


@st.composite
def dynamic_signals(draw):
    """Plateaus, steps and ramps of several slopes, impulses, NaN/inf, in any
    unit (scale 1e-3 .. 1e6), plus split points."""
    n = draw(st.integers(1, 700))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    scale = draw(st.sampled_from([1e-3, 1.0, 70.0, 1e6]))
    x = np.zeros(n)
    for _ in range(draw(st.integers(0, 4))):                     # steps
        x[int(rng.integers(0, n)):] += draw(st.sampled_from([5.0, 30.0, 300.0, -200.0]))
    for _ in range(draw(st.integers(0, 3))):                     # ramps (pours)
        a = int(rng.integers(0, n))
        b = min(n, a + int(rng.integers(2, 60)))
        slope = draw(st.sampled_from([0.2, 1.0, 5.0, 40.0]))
        x[a:b] += slope * np.arange(1, b - a + 1)
        x[b:] += slope * (b - a)
    x = (x + rng.normal(0, 1.0, n)) * scale
    for _ in range(draw(st.integers(0, 4))):                     # glitches
        x[int(rng.integers(0, n))] += draw(st.sampled_from([-1e3, 50.0, 4e4])) * scale
    for _ in range(draw(st.integers(0, 2))):
        x[int(rng.integers(0, n))] = draw(st.sampled_from([math.nan, math.inf, -math.inf]))
    x = np.round(x) if draw(st.booleans()) else x
    return x, sorted(draw(st.lists(st.integers(0, n), max_size=5)))


@SETTINGS
@given(dynamic_signals(), auto_kwargs(), st.booleans())
def test_auto_batch_equals_the_step_loop_split(sig, kw, tare):
    x, cuts = sig
    assert_batch_is_the_step_loop(x, cuts, tare, kw)


def assert_batch_is_the_step_loop(x, cuts, tare, kw):
    """Batch and step loop on x split at cuts (a tare between pieces):
    outputs, flags, last status, state and sigma, bit for bit."""
    stepped, batch = Chain(**kw), Chain(**kw)
    for part in split(x, cuts):
        o1, s1, st1 = stepped.process(part, flags=True)
        o2, s2 = batch.process(part)
        np.testing.assert_array_equal(o1, o2)
        np.testing.assert_array_equal(s1, s2)
        if len(part):
            assert batch.status == st1[-1]
        assert _state(batch) == pytest.approx(_state(stepped), rel=0, abs=0, nan_ok=True)
        assert batch.sigma == stepped.sigma
        if tare:
            assert batch.tare() == stepped.tare()


def test_auto_batch_runs_long_hx711_like_runs():
    """10^5 samples of steps, noise and read glitches (the throughput bench's
    kind of signal): batch and step loop agree on every sample."""
    rng = np.random.default_rng(7)
    n = 100_000
    x = np.repeat(5800 + 10000 * rng.integers(0, 5, n // 150 + 1), 150)[:n] + rng.normal(0, 70, n)
    x[rng.integers(0, n, n // 300)] = -8387000.0
    o1, s1, _ = Chain().process(np.round(x), flags=True)
    o2, s2 = Chain().process(np.round(x))
    np.testing.assert_array_equal(o1, o2)
    np.testing.assert_array_equal(s1, s2)
    assert s2.mean() > 0.5                       # mostly settled: the fast path's steady state


@st.composite
def settled_signals(draw):
    """Long stretches of steady noise (the estimator saturates after 255
    updates, the window is full and settled: the batch path's steady-state
    loop), broken by what that loop hands back: single and paired glitches,
    NaN/inf, a step (the motion test trips inside it), a slow drift, a ramp;
    any scale, rounded or not; plus split points."""
    n = draw(st.integers(1500, 6000))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    scale = draw(st.sampled_from([1e-3, 1.0, 70.0, 1e6]))
    x = rng.normal(0, 1.0, n)
    for _ in range(draw(st.integers(0, 3))):                     # steps
        x[int(rng.integers(600, n)):] += draw(st.sampled_from([4.0, 12.0, 300.0, -50.0]))
    if draw(st.booleans()):                                      # a slow drift
        a = int(rng.integers(600, n))
        x[a:] += draw(st.sampled_from([0.02, 0.3])) * np.arange(n - a)
    if draw(st.booleans()):                                      # a ramp (a pour)
        a = int(rng.integers(600, n))
        b = min(n, a + int(rng.integers(5, 80)))
        x[a:b] += 5.0 * np.arange(1, b - a + 1)
        x[b:] += 5.0 * (b - a)
    x = x * scale
    for _ in range(draw(st.integers(0, 8))):                     # glitches, some in pairs
        i = int(rng.integers(400, n - 1))
        x[i:i + draw(st.integers(1, 2))] += draw(st.sampled_from([-1e3, 20.0, 4e4])) * scale
    for _ in range(draw(st.integers(0, 3))):
        x[int(rng.integers(400, n))] = draw(st.sampled_from([math.nan, math.inf, -math.inf]))
    x = np.round(x) if draw(st.booleans()) else x
    return x, sorted(draw(st.lists(st.integers(0, n), max_size=4)))


@settings(max_examples=60, deadline=None)
@given(settled_signals(), st.booleans())
def test_auto_batch_steady_state_loop_equals_the_step_loop(sig, tare):
    """The steady-state loop of the batch path and its hand-offs to the
    general path (a sample the limit rejects, a non-finite one, a motion test
    that trips) give the step loop's bits: outputs, flags, status, state."""
    x, cuts = sig
    assert_batch_is_the_step_loop(x, cuts, tare, {})


def assert_same_bits(x, cuts, kw):
    """Batch and step loop on x split at cuts: the outputs' bits (a -0.0
    where the step loop gives +0.0 is a difference here), flags, state."""
    stepped, batch = Chain(**kw), Chain(**kw)
    for part in split(x, cuts):
        o1, s1, st1 = stepped.process(part, flags=True)
        o2, s2 = batch.process(part)
        np.testing.assert_array_equal(o1.view(np.int64), o2.view(np.int64))
        np.testing.assert_array_equal(s1, s2)
        if len(part):
            assert batch.status == st1[-1]
        assert _state(batch) == pytest.approx(_state(stepped), rel=0, abs=0, nan_ok=True)


@st.composite
def tied_signals(draw):
    """Samples on a coarse grid (a few codes, so a full window holds its
    extremes several times over), +0.0 and -0.0 among them, any window:
    the batch path finds a full window's extremes its own way when one
    leaves, and must give the step loop's bits, a zero's sign included."""
    n = draw(st.integers(300, 3000))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    grid = draw(st.sampled_from([[-1.0, -0.0, 0.0, 1.0], [-0.0, 0.0], [0.0, 1.0, 2.0], [-0.0, -1.0, -2.0],
                                 [3.0, 4.0, 5.0]]))
    x = rng.choice(grid, n)
    for _ in range(draw(st.integers(0, 2))):                     # steps, glitches
        x[int(rng.integers(0, n)):] += draw(st.sampled_from([0.0, 40.0]))
        x[int(rng.integers(0, n))] = draw(st.sampled_from([-1e3, 4e4]))
    kw = {}
    if draw(st.booleans()):
        kw.update(window=draw(st.integers(3, 32)), stable_count=draw(st.integers(1, 6)))
    return x, sorted(draw(st.lists(st.integers(0, n), max_size=3))), kw


@settings(max_examples=80, deadline=None)
@given(tied_signals())
def test_auto_batch_window_extremes_with_ties_and_signed_zeros(sig):
    x, cuts, kw = sig
    assert_same_bits(x, cuts, kw)


@st.composite
def long_plateaus(draw):
    """Plateaus of 300..1500 samples (longer than the gains the batch path
    keeps, and than P's way from P0 to its fixed point, 548 updates for the
    default's Q/R) with steps between them (each a Kalman restart: the kept
    gains read back), any Q/R and P0 the default allows; split points."""
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    parts = [np.full(draw(st.integers(300, 1500)), draw(st.sampled_from([0.0, 500.0, -300.0, 2e4])))
             for _ in range(draw(st.integers(1, 4)))]
    x = np.concatenate(parts)
    x = x + rng.normal(0, draw(st.sampled_from([0.5, 1.0, 70.0])), x.size)
    x = np.round(x) if draw(st.booleans()) else x
    kw = {"Q": draw(st.sampled_from([1e-3, 1e-2, 1e-4, 0.0]))} if draw(st.booleans()) else {}
    return x, sorted(draw(st.lists(st.integers(0, x.size), max_size=3))), kw


@settings(max_examples=40, deadline=None)
@given(long_plateaus())
def test_auto_batch_kalman_gains_kept_across_restarts(sig):
    x, cuts, kw = sig
    assert_same_bits(x, cuts, kw)
