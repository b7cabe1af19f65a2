"""The default chain ("auto"): the noise measured on the fly and the
thresholds that follow it.  C (through Cython) against the pure-Python spec
(fixed: bit for bit; float: the same operations, equal within 1e-9), scale invariance of the float form,
glitch / step / settle / steady behaviour, and bad input (stuck sensor,
noise bursts, saturated codes, NaN/inf)."""
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from pysig.errors import RangeError
from spec import chain as R
import pysig.weigh as C
from pysig.weigh import _presets as P

from test_chain import RTOL, both, run_split, signals

SETTINGS = settings(max_examples=80, deadline=None)


@st.composite
def auto_kwargs(draw):
    kw = {}
    if draw(st.booleans()):
        kw.update(window=draw(st.integers(3, 32)), lockout_n=draw(st.integers(0, 6)),
                  motion_count=draw(st.integers(1, 3)), stable_count=draw(st.integers(1, 6)),
                  seed_first=draw(st.booleans()), Q=draw(st.sampled_from([0.0, 1e-4, 1e-3, 1.0])))
    if draw(st.integers(0, 4)) == 0:
        kw["R"] = draw(st.sampled_from([1e-4, 1.0, 4900.0]))      # sigma fixed at sqrt(R)
    return kw


# ---- C == spec ------------------------------------------------------------------

@SETTINGS
@given(signals(extreme=True), st.booleans())
def test_noise_estimator_fixed_and_float_equal_the_spec(sig, fixed):
    x, cuts = sig
    update = np.random.default_rng(len(x)).random(len(x)) < 0.8
    c = C.NoiseEstimator(fixed)
    got = np.concatenate([c.process(x[a:b], update[a:b])
                          for a, b in zip([0] + cuts, cuts + [len(x)])])
    want = R.NoiseEstimator(fixed).process(x, update)
    np.testing.assert_array_equal(got, want)


@SETTINGS
@given(signals(extreme=True), auto_kwargs())
def test_auto_chain_fixed_equals_the_spec_bit_for_bit(sig, kw):
    x, cuts = sig
    c, r = both("Chain", preset="auto", fixed=True, **kw)
    for a, b in zip(run_split(c, x, cuts, flags=True), r.process(x, flags=True)):
        np.testing.assert_array_equal(a, b)
    assert c.sigma == r.sigma


@SETTINGS
@given(signals(allow_nonfinite=True, extreme=True), auto_kwargs())
def test_auto_chain_float_equals_the_spec(sig, kw):
    x, cuts = sig
    c_out, c_stable, c_status = run_split(C.Chain(**kw), x, cuts, flags=True)
    r_out, r_stable, r_status = R.Chain("auto", **kw).process(x, flags=True)
    np.testing.assert_allclose(c_out, r_out, rtol=RTOL, atol=RTOL * (1 + np.nanmax(np.abs(r_out), initial=0)))
    np.testing.assert_array_equal(c_stable, r_stable)
    np.testing.assert_array_equal(c_status, r_status)
    # the batch path (no flags) is the step path
    b_out, b_stable = run_split(C.Chain(**kw), x, cuts)
    np.testing.assert_array_equal(b_out, c_out)
    np.testing.assert_array_equal(b_stable, c_stable)


def test_auto_preset_refuses_a_fixed_threshold():
    with pytest.raises(RangeError, match="A0"):
        C.Chain(A0=2.0)
    with pytest.raises(RangeError, match="zero_band"):
        C.Chain(zero_band=0.1)


def test_explicit_R_fixes_sigma():
    c = C.Chain(R=49.0)
    assert c.sigma == 7.0 and c.params["A0"] == 42.0 and not c.params["noise_auto"]
    x = 1000 + np.random.default_rng(3).normal(0, 400.0, 300)
    c.process(x)
    assert c.sigma == 7.0                 # not measured


# ---- scale invariance -----------------------------------------------------------

def _load_signal(rng, n, sigma):
    x = np.full(n, 1000.0)
    for i in rng.integers(0, n, 3):
        x[i:] += rng.choice([-1, 1]) * rng.uniform(20, 200) * sigma
    x += rng.normal(0, sigma, n)
    for i in rng.integers(0, n, 2):
        x[i] += 80 * sigma
    return x


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.floats(1e-6, 1e6), st.floats(0.01, 100.0))
def test_float_form_is_scale_invariant(seed, c, sigma):
    """input * c -> output * c (to rounding) and the same stable flags."""
    x = _load_signal(np.random.default_rng(seed), 400, sigma)
    out, stable = C.Chain().process(x)
    out_c, stable_c = C.Chain().process(x * c)
    np.testing.assert_allclose(out_c, out * c, rtol=1e-9, atol=1e-9 * c * np.abs(x).max())
    np.testing.assert_array_equal(stable_c, stable)


# ---- behaviour ------------------------------------------------------------------

def _steps(sigma, seed, step=10000.0, hold=150, n=8):
    rng = np.random.default_rng(seed)
    level = np.repeat([step * (k % 2) for k in range(n)], hold).astype(float)
    return level + rng.normal(0, sigma, level.size), level, hold


@pytest.mark.parametrize("unit", [1.0, 1e-4, 3.7e3])
@pytest.mark.parametrize("rel", [1 / 5000, 1 / 200, 1 / 20])
def test_settles_within_sigma_in_1_2_s_and_is_steady(unit, rel):
    """Steps of 20 sigma or more: within +-sigma of the new level, for good,
    within 12 samples (1.2 s at 10 SPS), median over steps; steady std
    <= 0.3 sigma; the measured sigma within 20 %."""
    sigma = 10000.0 * rel
    x, level, hold = _steps(sigma, seed=int(1 / rel))
    c = C.Chain()
    out, _ = c.process(x * unit)
    out /= unit
    settle = []
    for k in range(1, len(level) // hold):
        seg = slice(k * hold, (k + 1) * hold)
        bad = np.flatnonzero(np.abs(out[seg] - level[seg]) > sigma)
        settle.append(0 if bad.size == 0 else bad[-1] + 1)
        assert bad.size == 0 or bad[-1] < hold // 2            # settled for good
    assert np.median(settle) <= 12
    still = np.concatenate([out[k * hold + hold // 2:(k + 1) * hold] - level[k * hold + hold // 2:(k + 1) * hold]
                            for k in range(len(level) // hold)])
    assert np.std(still) <= 0.3 * sigma
    assert abs(c.sigma / unit / sigma - 1) < 0.2 or abs(np.median(
        C.NoiseEstimator().process(x[:hold])[hold // 2:]) / sigma - 1) < 0.2


@pytest.mark.parametrize("fixed", [False, True])
def test_isolated_glitch_moves_output_less_than_sigma_and_a_run_is_a_load(fixed):
    sigma = 50.0
    rng = np.random.default_rng(7)
    x = np.rint(2000 + rng.normal(0, sigma, 400))
    clean = C.Chain(fixed=fixed).process(x)[0]
    for at, size in ((200, 5000.0), (250, -8e5), (300, 12 * sigma)):
        g = x.copy()
        g[at] += size
        out = C.Chain(fixed=fixed).process(g)[0]
        assert np.max(np.abs(out - clean)) <= sigma
    run = x.copy()
    run[200:] += 5000.0                                    # a run of out-of-band samples: the load changed
    out = C.Chain(fixed=fixed).process(run)[0]
    assert abs(np.median(out[220:]) - np.median(x[220:]) - 5000.0) < sigma


# ---- bad input ------------------------------------------------------------------

@pytest.mark.parametrize("fixed", [False, True])
def test_stuck_sensor_gives_the_floor_and_a_flag(fixed):
    x = np.full(200, 123456.0)
    c = C.Chain(fixed=fixed)
    out, stable, status = c.process(x, flags=True)
    assert np.all(out == 123456.0) and stable[-1]
    assert status[-1] & C.CHAIN_NOISE_FLOOR and c.noise_at_floor
    floor = 0.25 if fixed else 123456.0 * 2.0 ** -24
    assert c.sigma == floor and c.params["noise_auto"]
    # it moves: the next level is followed, the flag goes once noise is seen
    y = 123456.0 + 300.0 + np.random.default_rng(1).normal(0, 3.0, 200)
    out, _, status = c.process(y, flags=True)
    assert abs(out[-1] - 123756.0) < 4.5 and not status[-1] & C.CHAIN_NOISE_FLOOR


@pytest.mark.parametrize("fixed", [False, True])
def test_noise_burst_is_followed_up_and_back(fixed):
    rng = np.random.default_rng(11)
    x = 5000 + np.r_[rng.normal(0, 5, 300), rng.normal(0, 500, 300), rng.normal(0, 5, 400)]
    c = C.Chain(fixed=fixed)
    sig = []
    for v in x:
        c.step(v)
        sig.append(c.sigma)
    assert 400 < np.median(sig[450:600]) < 600     # the burst measured (not frozen as motion)
    assert 4 < np.median(sig[900:]) < 6            # and forgotten after it


def test_non_finite_samples_lose_nothing():
    rng = np.random.default_rng(5)
    x = 100 + rng.normal(0, 1.0, 300)
    bad = x.copy()
    bad[[50, 120, 121, 200]] = [math.nan, math.inf, -math.inf, math.nan]
    c = C.Chain()
    out, stable, status = c.process(bad, flags=True)
    assert np.all(np.isfinite(out)) and np.all(status[[50, 120, 121, 200]] & C.WARN_REJECTED)
    assert 0.7 < c.sigma < 1.3
    assert abs(out[-1] - 100) < 1.0


def test_saturated_codes_are_clamped_and_flagged():
    x = np.r_[np.full(50, 1000.0), np.full(50, 2.0**31)]
    c = C.Chain(fixed=True)
    out, _, status = c.process(x, flags=True)
    assert np.all(status[50:] & C.WARN_CLAMPED)
    assert out[-1] == P.CODE_MAX and c.sigma >= 0.25
