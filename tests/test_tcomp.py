"""Temperature compensation in C (csrc/tcomp/sig_poly.c, sig_tcomp.c) against the
pure-Python spec (tests/spec/tcomp.py): bit for bit on the fixed-point
path for any int16 temperature and reading, within a stated tolerance on the
float path; clamping is flagged, never silent; bad parameters are refused."""
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from conftest import I16, I32, draw_int16_rows
from pysig.tcomp import _tcomp
from pysig.tcomp import _quant as quant
from pysig.errors import NonFiniteError, RangeError
from spec import tcomp as ref


@settings(max_examples=300, deadline=None)
@given(a=I32, u=I16)
def test_mul_q15_exact(a, u):
    assert _tcomp.mul_q15(a, u) == ref.mul_q15(a, u)
    uu = -32767 if u == -32768 else u
    assert _tcomp.mul_q15(a, u) == math.floor(a * uu / 32768)


def test_mul_q15_corners():
    for a in (-(1 << 31), (1 << 31) - 1, -1, 0, 1, 65535, -65536, 0x7FFF0000):
        for u in (-32768, -32767, -1, 0, 1, 32767, 16384):
            assert _tcomp.mul_q15(a, u) == ref.mul_q15(a, u)


@settings(max_examples=300, deadline=None)
@given(coef=st.lists(I32, min_size=1, max_size=9), u=I16)
def test_horner_q15_bit_exact_including_saturation(coef, u):
    assert _tcomp.horner_q15(coef, u) == ref.horner_q15(coef, u)


def test_horner_q15_reports_saturation():
    value, status = _tcomp.horner_q15([(1 << 31) - 1, (1 << 31) - 1], 32767)
    assert value == (1 << 31) - 1 and status == ref.SIG_WARN_SATURATED
    assert _tcomp.horner_q15([1, 2, 3], 0) == (1, ref.SIG_OK)


@settings(max_examples=200, deadline=None)
@given(coef=st.lists(st.floats(-1e3, 1e3), min_size=1, max_size=9), u=st.floats(-1, 1))
def test_horner_f_matches_reference(coef, u):
    value, status = _tcomp.horner_f(coef, u)
    assert status == 0
    assert value == pytest.approx(ref.horner_f(coef, u), rel=1e-12, abs=1e-9)


@st.composite
def fixed_models(draw, small=False):
    """Valid fixed models; small=True keeps sum |c| + 2^(q-1) < 2^31, the
    models pysig.tcomp._quant makes, which take the unsaturated fast path in C."""
    n_axes = draw(st.integers(1, 3))
    order = draw(st.integers(1, 8))
    t_lo = draw(st.integers(-32768, 32766))
    t_hi = draw(st.integers(t_lo + 1, min(32767, t_lo + 65534)))
    s = quant.choose_scaling(t_lo, t_hi)
    cint = st.integers(-(1 << 26), 1 << 26) if small else I32
    coef = [[draw(cint) for _ in range(order + 1)] for _ in range(n_axes)]
    q = [draw(st.integers(0, 29 if small else 30)) for _ in range(n_axes)]
    t0 = draw(st.integers(t_lo, t_hi))
    return {"coef": coef, "q": q, "t_lo": t_lo, "t_hi": t_hi, "t_center": s.t_center, "t0": t0,
            "u_mul": s.u_mul, "u_shift": s.u_shift}


@settings(max_examples=300, deadline=None)
@given(model=fixed_models(), temps=st.lists(I16, min_size=1, max_size=8), data=st.data())
def test_apply_q_bit_exact(model, temps, data):
    c = _tcomp.TcompQ.from_fields(**model)
    n = len(model["coef"])
    x = draw_int16_rows(data, len(temps), n)
    out, status = c.apply(np.array(temps), x)
    for i, t in enumerate(temps):
        want, want_st = ref.apply_q(model, t, [int(v) for v in x[i]])
        assert list(out[i]) == want and status[i] == want_st
        for a in range(n):
            d, dst = c.delta(a, [t])
            assert (int(d[0]), int(dst[0])) == ref.delta_q(model, a, t)


@settings(max_examples=300, deadline=None)
@given(model=fixed_models(small=True), temps=st.lists(I16, min_size=1, max_size=8), data=st.data())
def test_apply_q_fast_path_bit_exact(model, temps, data):
    c = _tcomp.TcompQ.from_fields(**model)
    assert c.no_overflow
    x = draw_int16_rows(data, len(temps), len(model["coef"]))
    out, status = c.apply(np.array(temps), x)
    for i, t in enumerate(temps):
        assert (list(out[i]), status[i]) == ref.apply_q(model, t, [int(v) for v in x[i]])


@settings(max_examples=100, deadline=None)
@given(model=fixed_models())
def test_scaled_temperature_stays_in_q15(model):
    c = _tcomp.TcompQ.from_fields(**model)
    t = np.array([-32768, model["t_lo"], model["t_center"], model["t_hi"], 32767])
    u, status = c.scale(t)
    assert np.all(np.abs(u.astype(int)) <= 32767)
    assert u[2] == 0
    assert list(status) == [int(-32768 < model["t_lo"]), 0, 0, 0, int(32767 > model["t_hi"])]


def test_clamped_temperature_is_flagged_and_flat():
    s = quant.choose_scaling(0, 7000)
    model = {"coef": [[0, 1 << 20, 1 << 19]], "q": [16], "t_lo": 0, "t_hi": 7000,
             "t_center": s.t_center, "t0": 2500, "u_mul": s.u_mul, "u_shift": s.u_shift}
    c = _tcomp.TcompQ.from_fields(**model)
    out, status = c.apply(np.array([-1000, 0, 7000, 9000]), np.zeros((4, 1), dtype=np.int16))
    assert list(status) == [ref.SIG_WARN_CLAMPED, 0, 0, ref.SIG_WARN_CLAMPED]
    assert out[0, 0] == out[1, 0] and out[2, 0] == out[3, 0]   # evaluated at the limit


def test_output_saturation_is_flagged():
    s = quant.choose_scaling(0, 100)
    model = {"coef": [[-(1000 << 16), 0]], "q": [16], "t_lo": 0, "t_hi": 100,
             "t_center": s.t_center, "t0": 0, "u_mul": s.u_mul, "u_shift": s.u_shift}
    c = _tcomp.TcompQ.from_fields(**model)
    out, status = c.apply([50], np.array([[32000]], dtype=np.int16))
    assert out[0, 0] == 32767 and status[0] == ref.SIG_WARN_SATURATED


@pytest.mark.parametrize("bad", [
    {"t_lo": 100, "t_hi": 100}, {"t_center": 5000}, {"u_mul": 0}, {"u_shift": 31},
    {"q": [31]}, {"u_mul": 32767, "u_shift": 0},
])
def test_init_q_refuses_bad_parameters(bad):
    s = quant.choose_scaling(0, 1000)
    model = {"coef": [[1, 2]], "q": [10], "t_lo": 0, "t_hi": 1000, "t_center": s.t_center,
             "t0": 0, "u_mul": s.u_mul, "u_shift": s.u_shift, **bad}
    with pytest.raises(RangeError):
        _tcomp.TcompQ.from_fields(**model)


@st.composite
def float_models(draw):
    n_axes = draw(st.integers(1, 3))
    order = draw(st.integers(1, 8))
    lo = draw(st.floats(-40, 60))
    hi = lo + draw(st.floats(1, 100))
    coef = [[draw(st.floats(-500, 500)) for _ in range(order + 1)] for _ in range(n_axes)]
    return {"coef": coef, "t_lo": lo, "t_hi": hi, "center": (lo + hi) / 2, "inv_scale": 2 / (hi - lo)}


@settings(max_examples=200, deadline=None)
@given(model=float_models(), temps=st.lists(st.floats(-100, 200), min_size=1, max_size=6), data=st.data())
def test_apply_f_matches_reference(model, temps, data):
    """Float path: within 1e-9 relative (the host build is double; firmware
    float differs by rounding only)."""
    c = _tcomp.TcompF(**model)
    n = len(model["coef"])
    x = np.array([[data.draw(st.floats(-3e4, 3e4)) for _ in range(n)] for _ in temps])
    out, status = c.apply(np.array(temps), x)
    for i, t in enumerate(temps):
        want, want_st = ref.apply_f(model, t, list(x[i]))
        assert status[i] == want_st
        np.testing.assert_allclose(out[i], want, rtol=1e-9, atol=1e-7)


def test_apply_f_nan_temperature_is_an_error_not_a_value():
    c = _tcomp.TcompF([[1.0, 2.0]], 0.0, 10.0, 5.0, 0.2)
    out, status = c.apply([np.nan, np.inf, 5.0], np.array([[1.0], [1.0], [np.nan]]))
    assert status[0] == ref.SIG_ERR_NONFINITE and np.isnan(out[0, 0])
    assert status[1] == ref.SIG_WARN_CLAMPED                      # +inf clamps to t_hi
    assert status[2] == ref.SIG_ERR_NONFINITE                     # non-finite reading
    with pytest.raises(NonFiniteError):
        _tcomp.TcompF([[np.nan, 2.0]], 0.0, 10.0, 5.0, 0.2)
