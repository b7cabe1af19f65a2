"""Compact temperature compensation (csrc/tcomp/sig_tcomp16.c) against its
pure-Python spec (tests/spec/tcomp16.py), bit for bit; the quantiser
(pysig.tcomp._quant.quantize_compact): its stated error is exact and honest, the
outputs stay within 0.5 LSB + that error of the float64 model on the chamber
simulator's data, and models it cannot hold are refused by name."""
import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from conftest import I16, I32, draw_int16_rows
from pysig.tcomp import _tcomp16
from pysig.tcomp import _poly_fit as fit, _quant as quant
from pysig.sim import _chamber as sim_chamber
from pysig.errors import RangeError
from spec import tcomp16 as ref

LEVEL_MAX = 32767 * 65536          # |h * x + add| <= this keeps the next h within int16


@st.composite
def compact_models(draw):
    """Models sig_tcomp16_init accepts, with intermediates drawn up to their
    limits (a level's budget is what the bound leaves after |h| * w_max)."""
    n_axes, order = draw(st.integers(1, 3)), draw(st.integers(1, 5))
    t_lo = draw(st.integers(-32768, 32766))
    t_hi = draw(st.integers(t_lo + 1, min(32767, t_lo + (32767 if order > 1 else 65535))))
    v_max = t_hi - t_lo
    w_shift = draw(st.integers(1 if order > 1 else 0, max(1, (0xFFFF // v_max).bit_length() - 1)))
    assume(v_max << w_shift <= 0xFFFF)
    w_max = v_max << w_shift
    tops, adds = [], []
    for _ in range(n_axes):
        lim = min(32767, (LEVEL_MAX if order > 1 else ref.INT32_MAX) // (w_max if order > 1 else v_max))
        top = draw(st.integers(-lim, lim))
        b, add = abs(top), []
        for k in range(order - 1, -1, -1):
            x_max = w_max if k > 0 else v_max
            budget = (LEVEL_MAX if k > 0 else ref.INT32_MAX) - b * x_max
            c = draw(st.integers(-budget, budget))
            add.append(c)
            b = -(-(b * x_max + abs(c)) // 65536)
        tops.append(top)
        adds.append(add)
    model = {"top": tops, "add": adds, "t_lo": t_lo, "t_hi": t_hi, "w_shift": w_shift}
    assert ref.valid(model)
    return model


@settings(max_examples=300, deadline=None)
@given(model=compact_models(), temps=st.lists(I16, min_size=1, max_size=8), data=st.data())
def test_apply_q_bit_exact(model, temps, data):
    n = len(model["top"])
    t = temps + [model["t_lo"], model["t_hi"]]                 # the range ends, where |h| peaks
    x = np.vstack([draw_int16_rows(data, len(temps), n), np.full((2, n), 32767, np.int16)])
    out, status = _tcomp16.Tcomp16Q.from_fields(**model).apply(np.array(t), x)
    for i, ti in enumerate(t):
        assert (list(out[i]), status[i]) == ref.apply_q(model, ti, [int(v) for v in x[i]])


@settings(max_examples=300, deadline=None)
@given(n_axes=st.integers(1, 3), order=st.integers(0, 6), t_lo=I16, t_hi=I16,
       w_shift=st.integers(0, 16), data=st.data())
def test_init_accepts_exactly_what_the_spec_calls_valid(n_axes, order, t_lo, t_hi, w_shift, data):
    top = [data.draw(st.integers(-600, 600) | I16) for _ in range(n_axes)]
    add = [[data.draw(st.integers(-(1 << 24), 1 << 24) | I32) for _ in range(order)]
           for _ in range(n_axes)]
    model = {"top": top, "add": add, "t_lo": t_lo, "t_hi": t_hi, "w_shift": w_shift}
    if order == 0 or order > 5:
        with pytest.raises(RangeError):
            _tcomp16.Tcomp16Q.from_fields(**model)
        return
    if ref.valid(model):
        _tcomp16.Tcomp16Q.from_fields(**model)
    else:
        with pytest.raises(RangeError, match="sig_tcomp16_init rejected"):
            _tcomp16.Tcomp16Q.from_fields(**model)


def test_clamped_temperature_is_flagged_and_flat():
    model = {"top": [500], "add": [[1 << 20, 3 << 15]], "t_lo": 0, "t_hi": 7000, "w_shift": 3}
    c = _tcomp16.Tcomp16Q.from_fields(**model)
    out, status = c.apply(np.array([-1000, 0, 7000, 9000]), np.zeros((4, 1), dtype=np.int16))
    assert list(status) == [ref.SIG_WARN_CLAMPED, 0, 0, ref.SIG_WARN_CLAMPED]
    assert out[0, 0] == out[1, 0] and out[2, 0] == out[3, 0]   # evaluated at the limit


def test_output_saturation_is_flagged_at_both_rails():
    model = {"top": [0], "add": [[-(1000 << 16)]], "t_lo": 0, "t_hi": 100, "w_shift": 0}
    c = _tcomp16.Tcomp16Q.from_fields(**model)           # corr = -1000
    out, status = c.apply([50, 50, 50], np.array([[32000], [31767], [-32768]], dtype=np.int16))
    assert list(out[:, 0]) == [32767, 32767, -31768]
    assert list(status) == [ref.SIG_WARN_SATURATED, 0, 0]
    model["add"] = [[1000 << 16]]
    c = _tcomp16.Tcomp16Q.from_fields(**model)
    out, status = c.apply([50, 50], np.array([[-32000], [-31768]], dtype=np.int16))
    assert list(out[:, 0]) == [-32768, -32768] and list(status) == [ref.SIG_WARN_SATURATED, 0]


# ------------------------------------------------------------- quantiser ---
CHAMBER = sim_chamber.simulate(sim_chamber.ChamberParams(seed=3))
READINGS = np.array([-32768, -20000, -1, 0, 1, 12345, 32767], dtype=np.int16)


@pytest.mark.parametrize("order", [1, 2, 3, 4, 5])
def test_chamber_model_within_half_lsb_plus_stated_error(order):
    """Every 0.01 °C of the calibrated range (and 3 °C beyond, clamped), the
    C output is within 0.5 LSB + error_lsb of in - delta_float64(T); the stated
    error_lsb is the measured maximum and stays under the quantiser's limit."""
    m = fit.fit_tcomp(CHAMBER["temp"], {k: CHAMBER[k] for k in "xyz"}, order=order)
    cm = quant.quantize_compact(m)
    assert max(cm.error_lsb) <= quant.COMPACT_MAX_ERROR_LSB
    c = _tcomp16.Tcomp16Q.from_compact(cm)
    t = np.arange(cm.t_lo - 300, cm.t_hi + 301)
    zeros = np.zeros((t.size, 3), dtype=np.int16)
    out, status = c.apply(t, zeros)
    assert np.all((status & ref.SIG_WARN_CLAMPED) == ((t < cm.t_lo) | (t > cm.t_hi)))
    for axis in range(3):
        delta = m.delta(t / 100.0, axis)
        err = np.abs(-out[:, axis].astype(float) - delta)
        assert err.max() <= 0.5 + cm.error_lsb[axis] + 1e-9
        # error_lsb is the exact maximum of the unrounded compact correction
        v = np.arange(cm.t_hi - cm.t_lo + 1)
        exact = quant.compact_eval(cm.top[axis], cm.add[axis], cm.w_shift, v)
        assert np.max(np.abs(exact - m.delta((cm.t_lo + v) / 100.0, axis))) == cm.error_lsb[axis]
    # whole int16 reading range at a few temperatures: within rounding, or flagged at a rail
    for tt in t[::700]:
        x = np.tile(READINGS[:, None], (1, 3))
        out, status = c.apply(np.full(len(READINGS), tt), x)
        for axis in range(3):
            want = x[:, axis] - m.delta(np.array([tt / 100.0]), axis)[0]
            tol = 0.5 + cm.error_lsb[axis] + 1e-9
            assert np.max(np.abs(out[:, axis] - np.clip(want, -32768, 32767))) <= tol
            assert np.all(status[(want > 32767 + tol) | (want < -32768 - tol)] & ref.SIG_WARN_SATURATED)


def test_compact_error_is_small_next_to_the_int32_form():
    """Order 2 (the magnetometer paper's choice) on the chamber data: measured figures."""
    m = fit.fit_tcomp(CHAMBER["temp"], {k: CHAMBER[k] for k in "xyz"}, order=2)
    cm = quant.quantize_compact(m)
    assert max(cm.error_lsb) < 0.15             # 0.5 * 2 levels * 7038 / 65536 = 0.107 + rounding
    assert max(m.error_bound_lsb) < max(cm.error_lsb)   # the int32 form is the precise one


def _model(order=2, t_lo=0.0, t_hi=70.0, slope=2.0, curve=0.03):
    temp = np.repeat(np.linspace(t_lo, t_hi, 8), 5)
    y = slope * (temp - 25) + curve * (temp - 25) ** 2
    return fit.fit_tcomp(temp, {"x": y}, order=order, t0=min(max(25.0, t_lo), t_hi))


def test_refuses_order_above_five():
    with pytest.raises(RangeError, match="order 6 is not supported"):
        quant.quantize_compact(_model(order=6))


def test_refuses_a_range_wider_than_327_degrees_at_order_two():
    with pytest.raises(RangeError, match="wider than 327.67"):
        quant.quantize_compact(_model(t_lo=-55.0, t_hi=300.0))
    quant.quantize_compact(_model(order=1, t_lo=-55.0, t_hi=300.0, curve=0.0), max_error_lsb=1.0)


def test_refuses_a_drift_too_steep_for_int16_levels():
    with pytest.raises(RangeError, match="does not fit the int16 levels"):
        quant.quantize_compact(_model(slope=80.0))      # 80 LSB/°C > 50 LSB/°C


def test_refuses_when_the_measured_error_exceeds_the_limit():
    with pytest.raises(RangeError, match="compact quantisation error"):
        quant.quantize_compact(_model(), max_error_lsb=0.01)
