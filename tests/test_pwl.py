"""Piecewise-linear table: C sig_pwl_eval_q16 == reference bit for
bit, float form within tolerance, clamping flagged, init checks identical,
and the least-squares fit with its bad-input errors."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from pysig.tcomp import _pwl
from pysig.errors import InsufficientDataError, NonFiniteError, RangeError
from pysig.tcomp._table_fit import fit_pwl, fit_pwl_q16, hat_basis, plan_q16, quantize_values
from spec import pwl as ref

int16 = st.integers(-32768, 32767)


@st.composite
def q16_tables(draw):
    """Valid fixed-point tables: a range, a knot count, the planned mapping
    (or any other valid reciprocal) and arbitrary int16 entries."""
    t_lo = draw(st.integers(-32768, 32765))
    t_hi = draw(st.integers(t_lo + 2, 32767))
    span = t_hi - t_lo
    n = draw(st.integers(2, min(255, span)))
    recip = plan_q16(t_lo, t_hi, n)
    if draw(st.booleans()):
        # any recip whose range still ends in the last segment
        lo_r = -(-((n - 2) << 32) // span)
        hi_r = min((1 << 32) - 1, (((n - 1) << 32) + (1 << 16) - 1) // span)
        if 1 <= lo_r <= hi_r:
            recip = draw(st.integers(max(1, lo_r), hi_r))
    table = draw(st.lists(int16, min_size=n, max_size=n))
    vf = draw(st.integers(0, 15))
    return table, t_lo, t_hi, recip, vf


@settings(max_examples=300, deadline=None)
@given(q16_tables(), st.lists(int16, min_size=1, max_size=40))
def test_q16_c_equals_reference_bit_for_bit(params, temps):
    table, t_lo, t_hi, recip, vf = params
    if not ref.params_valid_q16(len(table), t_lo, t_hi, recip, vf):
        with pytest.raises(RangeError):
            _pwl.eval_q16(table, t_lo, t_hi, recip, vf, np.array([0], np.int16))
        return
    temps = temps + [t_lo, t_hi, -32768, 32767]
    out, status = _pwl.eval_q16(table, t_lo, t_hi, recip, vf, np.array(temps, np.int16))
    expect = [ref.eval_q16(table, t_lo, t_hi, recip, vf, t) for t in temps]
    assert [int(v) for v in out] == [e[0] for e in expect]
    assert [int(s) for s in status] == [e[1] for e in expect]
    # interpolation never leaves the knots' range
    scale = 2.0 ** (16 - vf)
    assert min(table) * scale <= out.min() and out.max() <= max(table) * scale


def test_planned_tables_are_valid():
    for t_lo, t_hi, n in [(-32768, 32767, 2), (-32768, 32767, 255), (0, 255, 255), (0, 2, 2),
                          (667, 4111, 184), (-1000, 7000, 9)]:
        recip = plan_q16(t_lo, t_hi, n)
        assert ref.params_valid_q16(n, t_lo, t_hi, recip, 15)
        last = t_lo + ref.knot_offsets_q16(n, recip)[-1]
        assert t_hi <= last < t_hi + 1e-3 * (t_hi - t_lo)


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 300), int16, int16, st.integers(0, (1 << 32) - 1), st.integers(0, 20))
def test_q16_init_checks_equal_reference(n, t_lo, t_hi, recip, vf):
    table = np.zeros(n, np.int16)
    valid = ref.params_valid_q16(n, t_lo, t_hi, recip, vf)
    if valid:
        out, _ = _pwl.eval_q16(table, t_lo, t_hi, recip, vf, np.array([t_lo], np.int16))
        assert out[0] == 0
    else:
        with pytest.raises(RangeError):
            _pwl.eval_q16(table, t_lo, t_hi, recip, vf, np.array([t_lo], np.int16))


def test_clamping_is_flagged_and_flat():
    table = [100, -200, 300]
    t_lo, t_hi = -1000, 1000
    recip = plan_q16(t_lo, t_hi, 3)
    temps = np.array([-32768, -1001, -1000, 0, 1000, 1001, 32767], np.int16)
    out, status = _pwl.eval_q16(table, t_lo, t_hi, recip, 0, temps)
    assert list(status) == [1, 1, 0, 0, 0, 1, 1]
    assert out[0] == out[1] == out[2] == 100 * 65536
    # the last knot sits at or just past t_hi (recip rounded down): the value
    # there is 300 to within one position LSB of the last segment's rise (500)
    assert out[4] == out[5] == out[6]
    assert abs(out[4] / 65536 - 300) <= 500 / 4096
    outf, statf = _pwl.eval_f(np.array(table, float), -10.0, 10.0, 0.1,
                              np.array([-np.inf, -11.0, -10.0, 0.0, 10.0, 11.0, np.inf, np.nan]))
    assert list(statf) == [1, 1, 0, 0, 0, 1, 1, -2]
    assert list(outf[:7]) == [100, 100, 100, -200, 300, 300, 300] and np.isnan(outf[7])


def test_exact_at_knots_and_linear_between():
    # value_frac 4 means acc units are exactly Q16: knots and midpoints are exact
    table = [16 * 5, 16 * -3, 16 * 7]
    recip = 1 << 22                   # 2^32 / 2^22 = 1024 units per segment
    out, _ = _pwl.eval_q16(table, 0, 2048, recip, 4, np.array([0, 512, 1024, 1536, 2048], np.int16))
    assert list(out / 65536) == [5, 1, -3, 2, 7]
    for vf in (0, 3, 5, 12):          # every rescaling branch of the C
        tab = [v << vf for v in (5, -3, 7)]
        out, _ = _pwl.eval_q16(tab, 0, 2048, recip, vf, np.array([0, 1024, 2048], np.int16))
        assert list(out / 65536) == [5, -3, 7]


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(-1e6, 1e6), min_size=2, max_size=30),
       st.floats(-100, 100), st.floats(0.01, 50),
       st.lists(st.floats(-1e4, 1e4), min_size=1, max_size=30))
def test_float_c_matches_reference(values, t_lo, width, temps):
    n = len(values)
    t_hi = t_lo + width
    inv_step = (n - 1) / width
    out, status = _pwl.eval_f(np.array(values), t_lo, t_hi, inv_step, np.array(temps))
    for t, y, s in zip(temps, out, status):
        ry, rs = ref.eval_f(values, t_lo, t_hi, inv_step, t)
        assert s == rs
        # same formula in double on both sides; tolerance covers the order of operations
        assert y == pytest.approx(ry, rel=1e-12, abs=1e-9 * max(1.0, max(map(abs, values))))
        assert min(values) <= y <= max(values)


def test_float_init_rejections():
    tab = np.array([1.0, 2.0])
    with pytest.raises(NonFiniteError):
        _pwl.eval_f(np.array([1.0, np.nan]), 0.0, 1.0, 1.0, [0.5])
    for t_lo, t_hi, inv in [(1.0, 1.0, 1.0), (0.0, 1.0, 0.0), (0.0, 1.0, 5.0), (0.0, np.inf, 1.0)]:
        with pytest.raises(RangeError):
            _pwl.eval_f(tab, t_lo, t_hi, inv, [0.5])
    with pytest.raises(RangeError):
        _pwl.eval_f(np.array([1.0]), 0.0, 1.0, 1.0, [0.5])


# ---- fitting ---------------------------------------------------------------

def _truth(temp):
    return np.interp(temp, [0.0, 10.0, 20.0, 30.0], [5.0, -40.0, 12.0, 3.0])


def test_fit_recovers_a_piecewise_linear_curve():
    temp = np.linspace(0.0, 30.0, 301)
    fit = fit_pwl(temp, _truth(temp), 4)
    assert np.allclose(fit.knots, [0, 10, 20, 30])
    assert np.allclose(fit.values, [5, -40, 12, 3], atol=1e-9)
    assert fit.rms < 1e-9
    y, status = fit.eval_c(temp)
    assert np.allclose(y, _truth(temp), atol=1e-9) and not status.any()


def test_fit_q16_is_the_c_evaluation_and_close_to_float():
    rng = np.random.default_rng(3)
    temp = np.sort(rng.uniform(0.0, 30.0, 400))
    y = _truth(temp) + rng.normal(0, 0.5, temp.size)
    ffit = fit_pwl(temp, y, 7)
    qfit = fit_pwl_q16(temp, y, 7, units_per_c=256)
    ti = qfit.temp_int(temp)
    out, status = qfit.eval_c(ti)
    table = [int(v) for v in qfit.table]
    expect = [ref.eval_q16(table, qfit.t_lo, qfit.t_hi, qfit.recip, qfit.value_frac, int(t))[0]
              for t in ti]
    assert list(out) == expect
    assert abs(qfit.rms - ffit.rms) < 0.01
    assert np.allclose(qfit.knots_c()[[0, -1]], [temp.min(), temp.max()], atol=2 / 256)
    assert qfit.data_bytes == 2 * 7 + 10


def test_hat_basis_rows_sum_to_one():
    knots = np.linspace(-5, 5, 6)
    design = hat_basis(np.linspace(-7, 7, 57), knots)
    assert np.allclose(design.sum(axis=1), 1.0)
    assert np.all(design >= 0)


def test_quantize_picks_largest_fraction_bits():
    table, vf = quantize_values([1.5, -0.25, 3.0])
    assert vf == 13 and list(table) == [12288, -2048, 24576]
    with pytest.raises(RangeError, match="int16"):
        quantize_values([40000.0])


@pytest.mark.parametrize("n", [0, 1, 256, 2.5])
def test_bad_knot_count(n):
    temp = np.linspace(0, 30, 50)
    with pytest.raises(RangeError, match="knots"):
        fit_pwl(temp, _truth(temp), n)


def test_knots_outside_the_data():
    temp = np.linspace(5, 30, 50)
    with pytest.raises(RangeError, match="outside the data"):
        fit_pwl(temp, _truth(temp), 4, lo=0.0)
    with pytest.raises(RangeError, match="outside the data"):
        fit_pwl_q16(temp, _truth(temp), 4, 256, hi=31.0)


def test_knot_without_data_is_named():
    temp = np.concatenate([np.linspace(0, 10, 20), np.linspace(20, 30, 20)])
    with pytest.raises(InsufficientDataError, match=r"knot \d+ at 1[0-9.]+ °C has no data"):
        fit_pwl(temp, _truth(temp), 31)
    # bridged (cross-validation): linear across the gap, data side undisturbed
    fit = fit_pwl(temp, _truth(temp), 31, bridge=True)
    assert fit.rms < 1e-9
    inside = (fit.knots > 11) & (fit.knots < 19)
    gap = fit.values[inside]
    assert np.allclose(np.diff(gap, 2), 0.0, atol=1e-8)


def test_more_knots_than_distinct_temperatures():
    temp = np.repeat([0.0, 10.0, 20.0], 5)
    with pytest.raises(InsufficientDataError):
        fit_pwl(temp, np.ones_like(temp), 5)


def test_nonfinite_and_length_mismatch():
    temp = np.linspace(0, 30, 50)
    y = _truth(temp)
    y[7] = np.nan
    with pytest.raises(NonFiniteError, match="index 7"):
        fit_pwl(temp, y, 4)
    with pytest.raises(ValueError):
        fit_pwl(temp, y[:-1], 4)


def test_too_many_knots_for_the_fixed_point_resolution():
    temp = np.linspace(0, 0.5, 50)          # 50 units of 0.01 °C
    with pytest.raises(RangeError, match="closer than one unit"):
        fit_pwl_q16(temp, temp, 60)


@settings(max_examples=100, deadline=None)
@given(st.integers(2, 30), st.floats(-50, 50), st.floats(1, 80),
       st.lists(st.floats(-1000, 1000), min_size=30, max_size=30), st.integers(0, 2**31))
def test_fit_recovers_any_table_on_its_own_knots(n, lo, width, values, seed):
    """Data drawn from a table with the fit's own knots (and enough points per
    segment) is recovered exactly, by the float fit and, to the int16
    rounding, by the fixed-point fit evaluated in C."""
    values = np.array(values[:n])
    knots = np.linspace(lo, lo + width, n)
    rng = np.random.default_rng(seed)
    temp = np.concatenate([knots, rng.uniform(lo, lo + width, 6 * n)])
    y = np.interp(temp, knots, values)
    fit = fit_pwl(temp, y, n)
    assert np.allclose(fit.values, values, atol=1e-6 * (1 + np.abs(values).max()))
    if width * 100 > n:                      # fixed point: knots at least 0.01 °C apart
        q = fit_pwl_q16(temp, y, n)
        lsb = 2.0 ** -q.value_frac
        # knots sit where the C puts them (within 1e-4 of a segment of the float
        # knots); the error is the int16 rounding plus that shift times the slope
        slope = np.abs(np.diff(values)).max() * (n - 1) / width
        tol = lsb + 2e-4 * width / (n - 1) * slope + 0.02 * slope + 1e-9
        assert q.rms <= tol
