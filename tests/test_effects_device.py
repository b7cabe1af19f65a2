"""csrc/refine/sig_effects.c against its Python reference: fixed point bit for bit
(hypothesis-generated inputs, state carried across calls split at random
points), float forms within 1e-12 relative of the reference and of the
float model refine fits with (pysig.refine._effect_models)."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from conftest import I16, I32
from pysig.refine import _effects as C
from pysig.refine import _effect_models as fx
from pysig.errors import NonFiniteError, RangeError
from spec import effects as R

SETTINGS = settings(max_examples=150, deadline=None)


def assert_columns_equal_reference(c_result, ref_steps):
    """The C call's output arrays (its trailing state left out) equal the
    reference's per-step tuples, column by column; returns the first."""
    columns = c_result[:-1]
    for k, column in enumerate(columns):
        assert column.tolist() == [r[k] for r in ref_steps], f"column {k}"
    return columns[0]


def assert_split_carries_state(run, xs, cut):
    """run(xs[:cut]) then run(xs[cut:], its state) gives the one-call
    outputs (every column but the state)."""
    whole = run(xs)
    cut = min(cut, len(xs))
    first = run(xs[:cut])
    second = run(xs[cut:], first[-1])
    for k in range(len(whole) - 1):
        assert first[k].tolist() + second[k].tolist() == whole[k].tolist(), f"column {k}"


def _ref_lag(xs, alpha_q16, frac):
    lag = R.LagQ(alpha_q16, frac)
    out = [lag.step(int(x)) for x in xs]
    return [o for o, _ in out], [s for _, s in out]


@SETTINGS
@given(xs=st.lists(I32, min_size=1, max_size=60), alpha=st.integers(1, 65536),
       frac=st.integers(0, 16), cut=st.integers(0, 60))
def test_lag_q_bit_exact_and_split(xs, alpha, frac, cut):
    out, status = _ref_lag(xs, alpha, frac)
    c_out, c_st, _ = C.lag_q(xs, alpha, frac)
    assert c_out.tolist() == out and c_st.tolist() == status
    cut = min(cut, len(xs))
    a, sa, state = C.lag_q(xs[:cut], alpha, frac)
    b, sb, _ = C.lag_q(xs[cut:], alpha, frac, state)
    assert a.tolist() + b.tolist() == out


@SETTINGS
@given(ts=st.lists(I16, min_size=1, max_size=60), width=st.integers(1, 32767), k=I32,
       start=st.sampled_from([-1, 0, 1]), cut=st.integers(0, 60))
def test_hysteresis_q_bit_exact_and_split(ts, width, k, start, cut):
    h = R.HystQ(width, k, start)
    br = assert_columns_equal_reference(C.hyst_q(ts, width, k, start), [h.step(int(t)) for t in ts])
    assert np.all(np.abs(br) <= width)
    assert_split_carries_state(lambda xs, *state: C.hyst_q(xs, width, k, start, *state), ts, cut)


@SETTINGS
@given(xs=st.lists(I32, min_size=1, max_size=60), alpha=st.integers(1, 65536),
       frac=st.integers(0, 16), k=I32, cut=st.integers(0, 60))
def test_creep_q_bit_exact_and_split(xs, alpha, frac, k, cut):
    cr = R.CreepQ(alpha, frac, k)
    assert_columns_equal_reference(C.creep_q(xs, alpha, frac, k), [cr.step(int(x)) for x in xs])
    assert_split_carries_state(lambda ys, *state: C.creep_q(ys, alpha, frac, k, *state), xs, cut)


@SETTINGS
@given(coef=st.lists(I32, min_size=1, max_size=9), data=st.data())
def test_gain_q_bit_exact(coef, data):
    n = data.draw(st.integers(1, 30))
    u = data.draw(st.lists(I16, min_size=n, max_size=n))
    x = data.draw(st.lists(I32, min_size=n, max_size=n))
    out, s = C.gain_q(coef, u, x)
    ref = [R.gain_apply_q(coef, ui, xi) for ui, xi in zip(u, x)]
    assert out.tolist() == [r[0] for r in ref] and s.tolist() == [r[1] for r in ref]


@SETTINGS
@given(coef=st.lists(I32, min_size=1, max_size=9), center=I32, k=st.integers(1, (1 << 31) - 1),
       shift=st.integers(0, 30), x=st.lists(I32, min_size=1, max_size=30))
def test_nonlin_q_bit_exact(coef, center, k, shift, x):
    out, s = C.nonlin_q(coef, center, k, shift, x)
    ref = [R.nonlin_apply_q(coef, center, k, shift, xi) for xi in x]
    assert out.tolist() == [r[0] for r in ref] and s.tolist() == [r[1] for r in ref]


@SETTINGS
@given(k=st.lists(I32, min_size=1, max_size=3), data=st.data())
def test_cross_q_bit_exact(k, data):
    n = data.draw(st.integers(1, 20))
    x = data.draw(st.lists(I32, min_size=n, max_size=n))
    others = data.draw(st.lists(st.lists(I32, min_size=len(k), max_size=len(k)), min_size=n, max_size=n))
    out, s = C.cross_q(k, x, np.array(others, dtype=np.int64))
    ref = [R.cross_apply_q(k, xi, oi) for xi, oi in zip(x, others)]
    assert out.tolist() == [r[0] for r in ref] and s.tolist() == [r[1] for r in ref]


FLOATS = st.floats(-1e4, 1e4, allow_nan=False)


@SETTINGS
@given(xs=st.lists(FLOATS, min_size=1, max_size=50), alpha=st.floats(1e-4, 1.0))
def test_lag_f_matches_reference_and_fit_model(xs, alpha):
    out, _ = C.lag_f(xs, alpha)
    lag = R.LagF(alpha)
    ref = [lag.step(x) for x in xs]
    np.testing.assert_allclose(out, ref, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(out, fx.first_order_lag(xs, alpha), rtol=1e-9, atol=1e-7)


@SETTINGS
@given(ts=st.lists(FLOATS, min_size=1, max_size=50), width=st.floats(0.01, 100.0),
       k=st.floats(-10, 10), start=st.sampled_from([-1, 0, 1]))
def test_hyst_f_matches_reference_and_fit_model(ts, width, k, start):
    br, c, _ = C.hyst_f(ts, width, k, start)
    h = R.HystF(width, k, start)
    ref = [h.step(t) for t in ts]
    np.testing.assert_allclose(br, [r[0] for r in ref], rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(c, [r[1] for r in ref], rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(br, np.asarray(ts) - fx.play_operator(ts, width, start),
                               rtol=1e-12, atol=1e-9)


@SETTINGS
@given(xs=st.lists(FLOATS, min_size=1, max_size=50), alpha=st.floats(1e-4, 1.0),
       k=st.floats(-1, 1))
def test_creep_f_matches_reference(xs, alpha, k):
    c, y, _ = C.creep_f(xs, alpha, k)
    lag = R.LagF(alpha)
    ref = [R.creep_step_f(lag, k, x) for x in xs]
    np.testing.assert_allclose(c, [r[0] for r in ref], rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(y, [r[1] for r in ref], rtol=1e-12, atol=1e-9)


def test_float_gain_nonlin_cross_match_reference():
    rng = np.random.default_rng(1)
    u = rng.uniform(-1, 1, 200)
    x = rng.uniform(-500, 500, 200)
    coef = [1.01, -0.02, 0.003]
    np.testing.assert_allclose(C.gain_f(coef, u, x), [R.gain_apply_f(coef, a, b) for a, b in zip(u, x)],
                               rtol=1e-12)
    np.testing.assert_allclose(C.nonlin_f(coef, 10.0, 1 / 400, x),
                               [R.nonlin_apply_f(coef, 10.0, 1 / 400, b) for b in x], rtol=1e-12)
    o = rng.uniform(-300, 300, (200, 2))
    np.testing.assert_allclose(C.cross_f([0.03, -0.02], x, o),
                               [R.cross_apply_f([0.03, -0.02], b, oo) for b, oo in zip(x, o)], rtol=1e-12)


def test_fixed_lag_tracks_float_lag():
    """The Q16 temperature lag follows the float one within half a count
    (the output rounding) plus the floor bias of the state, at most
    1/alpha units of 2^-16 (here 90 / 65536 = 0.0014 count)."""
    t = np.round(2500 + 2000 * np.sin(np.arange(3000) / 300.0)).astype(np.int16)
    alpha = fx.lag_alpha(90.0, 1.0)
    q, s, _ = C.lag_q(t, int(round(alpha * 65536)), 16)
    f, _ = C.lag_f(t.astype(float), round(alpha * 65536) / 65536)
    assert np.max(np.abs(q - f)) <= 0.5 + (1 / alpha) / 65536 + 1e-9
    assert not s.any()


def test_bad_parameters_are_named_errors():
    with pytest.raises(RangeError, match="alpha_q16"):
        C.lag_q([1, 2], 0, 16)
    with pytest.raises(RangeError, match="alpha_q16"):
        C.lag_q([1, 2], 65537, 16)
    with pytest.raises(RangeError, match="frac"):
        C.lag_q([1, 2], 100, 17)
    with pytest.raises(RangeError, match="width"):
        C.hyst_q([1, 2], 0, 10)
    with pytest.raises(RangeError, match="alpha"):
        C.lag_f([1.0], 1.5)
    with pytest.raises(NonFiniteError, match="index 1"):
        C.lag_f([1.0, float("nan")], 0.5)
    with pytest.raises(RangeError, match="coefficients"):
        C.gain_q([], [0], [1])
    with pytest.raises(RangeError, match="cross-axis"):
        C.cross_q([1, 2, 3, 4], [1], [[1, 2, 3, 4]])


def test_saturation_is_reported_and_state_stays_valid():
    out, s, state = C.lag_q([(1 << 31) - 1, -(1 << 31)], 65536, 16)
    assert s[0] & R.SIG_WARN_SATURATED
    out2, s2, _ = C.lag_q([0, 0, 0], 65536, 16, state)
    assert out2.tolist() == [0, 0, 0]      # alpha = 1: the state follows the input again
