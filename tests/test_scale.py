"""csrc/weigh/sig_scale.c (through pysig.weigh._scale) against spec.scale:
bit for bit on the fixed path, exactly on the host float path (double,
same operations), and the fixed image within its quantisation bound of the
float calibration."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from pysig.weigh import _scale
from pysig.errors import NonFiniteError, RangeError
from spec import scale as ref

# plain integers plus the edges the C splits on, so hypothesis hits the rails often
int32s = st.one_of(st.integers(-(1 << 31), (1 << 31) - 1),
                   st.sampled_from([0, 1, -1, 65535, 65536, -65536, (1 << 31) - 1, -(1 << 31),
                                    -(1 << 31) + 1, 1 << 30, -(1 << 30)]))
nonzero_int32s = int32s.filter(lambda v: v != 0)
shifts = st.integers(0, 62)


@settings(max_examples=300, deadline=None)
@given(offset=int32s, mant=nonzero_int32s, shift=shifts,
       counts=st.lists(int32s, min_size=1, max_size=40))
def test_fixed_equals_reference_any_int32(offset, mant, shift, counts):
    out, sat = _scale.ScaleQ16(offset, mant, shift).apply(np.array(counts, dtype=np.int64))
    ref_out, ref_sat = ref.apply_q16(counts, offset, mant, shift)
    np.testing.assert_array_equal(out, ref_out)
    np.testing.assert_array_equal(sat, ref_sat)


@settings(max_examples=200, deadline=None)
@given(counts=st.lists(st.integers(-(1 << 23), (1 << 23) - 1), min_size=1, max_size=40),
       offset=st.floats(-2e6, 2e6), counts_per_unit=st.floats(50.0, 2e5),
       sign=st.sampled_from([1.0, -1.0]))
def test_realistic_calibrations_fixed_vs_float(counts, offset, counts_per_unit, sign):
    """24-bit codes, 50..200000 codes per unit: the Q16 image agrees with the
    float calibration within half a code of offset plus the gain rounding
    plus one Q16 LSB, and C == reference bit for bit on both paths."""
    gain = sign / counts_per_unit
    off, mant, shift = ref.quantize(offset, gain)
    q, sat = _scale.ScaleQ16(off, mant, shift).apply(np.array(counts))
    rq, rsat = ref.apply_q16(counts, off, mant, shift)
    np.testing.assert_array_equal(q, rq)
    f = _scale.ScaleF(offset, gain).apply(np.array(counts, dtype=float))
    np.testing.assert_array_equal(f, ref.apply_f(counts, offset, gain))
    in_range = np.abs(f) < 32767
    assert not sat[in_range].any()
    d = np.abs(np.array(counts, dtype=float) - off)
    bound = (0.5 * abs(gain)                                   # offset rounding
             + d * abs(mant / 2.0 ** (16 + shift) - gain)       # gain rounding
             + 2.0 ** -16 + 1e-9 * np.abs(f))                   # floor + float rounding
    err = np.abs(q / 65536.0 - f)
    assert np.all(err[in_range] <= bound[in_range])


def test_saturation_flagged_and_clamped():
    s = _scale.ScaleQ16(0, 1 << 30, 0)                 # 16384 units per code: saturates fast
    out, sat = s.apply(np.array([0, 1, -1, 1 << 20, -(1 << 20)]))
    np.testing.assert_array_equal(out, [0, 1 << 30, -(1 << 30), 2**31 - 1, -2**31])
    np.testing.assert_array_equal(sat, [False, False, False, True, True])
    # d = counts - offset overflows int32, also from counts = 0 (found by the C oracle test)
    out, sat = _scale.ScaleQ16(-(1 << 31), 1, 0).apply(np.array([(1 << 31) - 1, 0, -1]))
    np.testing.assert_array_equal(out, [2**31 - 1, 2**31 - 1, 2**31 - 1])
    np.testing.assert_array_equal(sat, [True, True, False])
    out, sat = _scale.ScaleQ16((1 << 31) - 1, 1, 0).apply(np.array([0, -1, -2]))
    np.testing.assert_array_equal(out, [-(2**31) + 1, -(2**31), -(2**31)])
    np.testing.assert_array_equal(sat, [False, False, True])


def test_floor_rounds_towards_minus_infinity():
    # (-3 * 1) >> 1 = -2 (floor), not -1 (truncation)
    out, _ = _scale.ScaleQ16(0, 1, 1).apply(np.array([-3, 3, -1]))
    np.testing.assert_array_equal(out, [-2, 1, -1])


def test_bad_parameters_named():
    with pytest.raises(RangeError, match="gain_shift"):
        _scale.ScaleQ16(0, 1, 63)
    with pytest.raises(RangeError, match="gain_mant"):
        _scale.ScaleQ16(0, 0, 3)
    with pytest.raises(RangeError, match="outside its C type"):
        _scale.ScaleQ16(1 << 31, 1, 3)
    with pytest.raises(NonFiniteError):
        _scale.ScaleF(float("nan"), 1.0)
    with pytest.raises(NonFiniteError):
        _scale.ScaleF(0.0, float("inf"))
    with pytest.raises(RangeError):
        _scale.ScaleF(0.0, 0.0)
    with pytest.raises(NonFiniteError, match="index 2"):
        _scale.ScaleF(0.0, 1.0).apply(np.array([1.0, 2.0, float("nan")]))
    with pytest.raises(RangeError, match="int32"):
        _scale.ScaleQ16(0, 1, 0).apply(np.array([1 << 40]))
    with pytest.raises(RangeError):
        ref.quantize(0.0, 0.0)
    with pytest.raises(RangeError, match="too large"):
        ref.quantize(0.0, 1e5)


def test_quantize_keeps_precision():
    off, mant, shift = ref.quantize(85899.3, 1 / 64424.5)
    assert off == 85899
    assert 2**30 <= abs(mant) <= 2**31 - 1
    assert abs(mant / 2.0 ** (16 + shift) * 64424.5 - 1) < 2e-9


@pytest.mark.parametrize("offset,gain", [(5808.4, 1 / 997.1), (-12459.0, 4.5e-4), (0.0, -2.2e-3),
                                         (1e9, 1e-9), (3.0, 1e-20), (0.0, 0.0), (float("nan"), 1.0),
                                         (3e9, 1.0), (0.0, 1e6)])
def test_library_quantize_equals_the_spec(offset, gain):
    """The library's scale image (pysig.weigh._calibration) is the spec's, refusals included."""
    from pysig.errors import RangeError
    from spec import scale as ref
    from pysig.weigh import _calibration as lib
    try:
        want = ref.quantize(offset, gain)
    except RangeError as exc:
        with pytest.raises(RangeError, match=str(exc).split(":")[0]):
            lib.quantize(offset, gain)
        return
    assert lib.quantize(offset, gain) == want
