"""Automatic fixed-point formats (pysig/tcomp/_quant.py): the fixed-point correction
stays within 0.5 LSB of float64 over the whole calibrated range and the whole
int16 reading range, and the stated bound is honest."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from pysig.tcomp import _tcomp
from pysig.tcomp import _poly_fit as fit, _quant as quant
from pysig.sim import _chamber as sim_chamber
from pysig.errors import RangeError
from spec import tcomp as ref

READINGS = np.array([-32768, -32767, -20000, -1, 0, 1, 12345, 32766, 32767], dtype=np.int16)


def dense_grid(s):
    """Every 0.01 °C step of the range (sub-sampled to <= ~8000 points) plus
    the ends and 3 °C beyond them (clamped)."""
    step = max(1, (s.t_hi - s.t_lo) // 8000)
    t = np.arange(s.t_lo, s.t_hi + 1, step)
    extra = [max(-32768, s.t_lo - 300), s.t_lo, s.t_hi, min(32767, s.t_hi + 300)]
    return np.unique(np.concatenate([t, extra]))


def float_delta(coef, s, t_centi):
    temp = np.clip(t_centi / 100.0, s.t_lo / 100.0, s.t_hi / 100.0)
    return np.polynomial.polynomial.polyval((temp - s.center_c) / s.scale_c, coef)


def check_model(coefs, s):
    """Max |delta_fixed - delta_float64| (LSB) and the output check."""
    qa = [quant.quantize_axis(c) for c in coefs]
    c = _tcomp.TcompQ.from_fields([a.coef for a in qa], [a.q for a in qa], s.t_lo, s.t_hi,
                                  s.t_center, s.t_lo, s.u_mul, s.u_shift)
    t = dense_grid(s)
    worst = 0.0
    for axis, (coef, a) in enumerate(zip(coefs, qa)):
        d, status = c.delta(axis, t)
        assert not np.any(status & ref.SIG_WARN_SATURATED)
        err = np.abs(d.astype(float) / 2 ** a.q - float_delta(coef, s, t))
        assert err.max() <= a.error_bound_lsb + 1e-12, "the stated bound is not honest"
        worst = max(worst, float(err.max()))
    # outputs for readings across the whole int16 range, at a few temperatures
    for tt in t[:: max(1, t.size // 40)]:
        x = np.tile(READINGS[:, None], (1, len(coefs)))
        out, status = c.apply(np.full(x.shape[0], tt), x)
        for axis, coef in enumerate(coefs):
            want = x[:, axis].astype(float) - float_delta(coef, s, np.array([tt]))[0]
            tol = 0.5 + qa[axis].error_bound_lsb + 1e-9
            # within rounding of the float64 result, clipped to the int16 rails
            assert np.max(np.abs(out[:, axis] - np.clip(want, -32768, 32767))) <= tol
            beyond = (want > 32767 + tol) | (want < -32768 - tol)
            assert np.all(status[beyond] & ref.SIG_WARN_SATURATED)
    return worst


@st.composite
def drift_models(draw):
    """Drift polynomials in u of order 1-8 whose slope sum k|c_k| stays within
    24000 LSB (a drift of up to ~3/4 of the int16 range across the range)."""
    lo = draw(st.floats(-55, 100))
    span = draw(st.floats(0.5, 150))
    s = quant.choose_scaling(int(round(lo * 100)), int(round((lo + span) * 100)))
    order = draw(st.integers(1, 8))
    n_axes = draw(st.integers(1, 3))
    coefs = []
    for _ in range(n_axes):
        raw = np.array([draw(st.floats(-1, 1)) for _ in range(order + 1)])
        budget = draw(st.floats(1, 24000))
        if sum(k * abs(v) for k, v in enumerate(raw)) < 1e-3:
            raw[1] = 1.0
        raw[1:] *= budget / sum(k * abs(v) for k, v in enumerate(raw))
        raw[0] = draw(st.floats(-20000, 20000))
        coefs.append(raw)
    return coefs, s


@settings(max_examples=120, deadline=None)
@given(model=drift_models())
def test_fixed_point_within_half_lsb_of_float64(model):
    coefs, s = model
    assert check_model(coefs, s) <= 0.5


def test_fitted_chamber_model_is_far_inside_the_bound():
    data = sim_chamber.simulate(sim_chamber.ChamberParams(seed=3))
    m = fit.fit_tcomp(data["temp"], {k: data[k] for k in "xyz"}, order=2)
    s = m.scaling
    c = _tcomp.TcompQ.from_fields(**m.fixed_fields())
    t = np.arange(s.t_lo - 500, s.t_hi + 501)      # every 0.01 °C step, and beyond
    for axis in range(3):
        d, _ = c.delta(axis, t)
        err = np.abs(d / 2 ** m.q[axis] - m.delta(t / 100.0, axis))
        assert err.max() < 0.01


@settings(max_examples=100, deadline=None)
@given(t_lo=st.integers(-32768, 32766), width=st.integers(1, 65535))
def test_choose_scaling_keeps_u_in_q15_with_15_bits(t_lo, width):
    t_hi = min(32767, t_lo + width)
    s = quant.choose_scaling(t_lo, t_hi)
    assert 16384 <= s.u_mul <= 32767 or s.u_shift == 0
    assert s.t_hi == t_hi and s.t_lo == (t_lo + 1 if t_hi - t_lo == 65535 else t_lo)
    t_lo = s.t_lo
    for t in (t_lo, t_hi):
        u, _ = ref.scale_q(t, t_lo, t_hi, s.t_center, s.u_mul, s.u_shift)
        assert abs(u) <= 32767
    # the abscissa of the float model equals the fixed one before rounding
    u_float = (t_hi - s.t_center) / 100.0 / s.scale_c * 32768
    u_fixed, _ = ref.scale_q(t_hi, t_lo, t_hi, s.t_center, s.u_mul, s.u_shift)
    assert abs(u_float - u_fixed) <= 0.5 + 1e-9


def test_q_is_the_largest_without_overflow():
    qa = quant.quantize_axis([1000.0, -500.0, 250.0])
    assert sum(abs(v) for v in qa.coef) + 2 + (1 << (qa.q - 1)) <= (1 << 31) - 1
    bigger = [int(round(v * 2)) for v in (1000.0, -500.0, 250.0)]
    assert sum(abs(v) for v in bigger) * (1 << qa.q) + (1 << qa.q) > (1 << 31) - 1


def test_coefficients_too_large_are_refused():
    with pytest.raises(RangeError, match="too large"):
        quant.quantize_axis([3e9, 1.0])


def test_fit_refuses_a_drift_too_steep_for_q15():
    temp = np.repeat(np.linspace(0, 70, 8), 10)
    y = 1e6 * (temp - 35) / 35            # +-1e6 LSB swing: not an int16 sensor
    with pytest.raises(RangeError, match="too steep"):
        fit.fit_tcomp(temp, {"x": y}, order=1)
