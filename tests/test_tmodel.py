"""One C entry point for any model an image holds (sig_tmodel): the C loader
and evaluator equal the executable spec (spec.tmodel) bit for bit
on generated polynomial, compact and table models, with signed and unsigned
temperature codes; a failed load leaves the model as it was."""
import struct

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from spec import tmodel as ref
from pysig.store._image import (SECTION_OFFSET_POLY, SECTION_TEMP_CODE, TCODE_INT16, TCODE_UINT16,
                               build_image, temp_code_payload)
from pysig.tcomp import _tmodel
from pysig.tcomp import _quant as quant
from pysig.tcomp._table_fit import PwlQ16, plan_q16, pwl_payload
from pysig.store._image import SECTION_PWL_TABLE, compact_poly_payload, SECTION_COMPACT_POLY
from pysig.tcomp._tempcode import TempCode, raw_code, CELSIUS


@st.composite
def ranges(draw):
    t_lo = draw(st.integers(-32768, 32000))
    t_hi = draw(st.integers(t_lo + 300, min(32767, t_lo + 65535)))
    return t_lo, t_hi


@st.composite
def poly_sections(draw):
    t_lo, t_hi = draw(ranges())
    s = quant.choose_scaling(t_lo, t_hi)
    n_axes, order = draw(st.integers(1, 3)), draw(st.integers(1, 8))
    out = struct.pack("<BBBBhhhhh", n_axes, order, s.u_shift, 0, s.t_lo, s.t_hi, s.t_center, s.t_center, s.u_mul)
    for _ in range(n_axes):
        q = draw(st.integers(0, 30))
        coef = draw(st.lists(st.integers(-(1 << 31), (1 << 31) - 1), min_size=order + 1, max_size=order + 1))
        out += struct.pack("<B", q) + struct.pack(f"<{order + 1}i", *coef)
    return SECTION_OFFSET_POLY, out


@st.composite
def table_sections(draw):
    t_lo, t_hi = draw(ranges())
    n = draw(st.integers(2, min(255, t_hi - t_lo)))
    recip = plan_q16(t_lo, t_hi, n)
    tabs = []
    for _ in range(draw(st.integers(1, 3))):
        vf = draw(st.integers(0, 15))
        entries = np.array(draw(st.lists(st.integers(-32768, 32767), min_size=n, max_size=n)), dtype=np.int16)
        tabs.append(PwlQ16(table=entries, t_lo=t_lo, t_hi=t_hi, recip=recip, value_frac=vf,
                           units_per_c=100, rms=0.0))
    return SECTION_PWL_TABLE, pwl_payload(tabs)


def _compact_section():
    from pysig.tcomp import _poly_fit as fit
    t = np.linspace(-10.0, 60.0, 400)
    m = fit.fit_tcomp(t, {"x": 40 * np.sin(t / 20), "y": 0.02 * (t - 20) ** 2}, order=3)
    return SECTION_COMPACT_POLY, compact_poly_payload(quant.quantize_compact(m))


COMPACT = None


def _with_code(section, kind):
    extra = [] if kind is None else [(SECTION_TEMP_CODE, temp_code_payload(kind))]
    return build_image([section, *extra], 7)


def _same_as_reference(img, codes, readings):
    st_ref, m_ref = ref.load(img)
    c = _tmodel.TModel()
    st_c = c.load(img)
    assert st_c == st_ref
    if st_c != 0:
        return
    assert c.family == m_ref[0] and c.n_axes == len(readings[0])
    out, status = c.apply(codes, readings)
    for i, code in enumerate(codes):
        want, want_st = ref.apply(m_ref, int(code), [int(v) for v in readings[i]])
        assert list(out[i]) == want and status[i] == want_st, (i, code)


def _inputs(draw, n_axes):
    n = draw(st.integers(1, 30))
    codes = np.array(draw(st.lists(st.integers(0, 65535), min_size=n, max_size=n)))
    readings = np.array(draw(st.lists(st.lists(st.integers(-32768, 32767), min_size=n_axes, max_size=n_axes),
                                      min_size=n, max_size=n)), dtype=np.int16)
    return codes, readings


@settings(max_examples=150, deadline=None)
@given(st.one_of(poly_sections(), table_sections()), st.sampled_from([None, TCODE_INT16, TCODE_UINT16]),
       st.data())
def test_c_equals_reference_on_generated_models(section, kind, data):
    img = _with_code(section, kind)
    n_axes = section[1][0]
    codes, readings = _inputs(data.draw, n_axes)
    _same_as_reference(img, codes, readings)


@settings(max_examples=40, deadline=None)
@given(st.sampled_from([None, TCODE_INT16, TCODE_UINT16]), st.data())
def test_c_equals_reference_on_a_compact_model(kind, data):
    global COMPACT
    COMPACT = COMPACT or _compact_section()
    codes, readings = _inputs(data.draw, 2)
    _same_as_reference(_with_code(COMPACT, kind), codes, readings)


@settings(max_examples=150, deadline=None)
@given(table_sections(), st.sampled_from([None, TCODE_UINT16]), st.data())
def test_corrupt_images_are_refused_like_the_reference_model_untouched(section, kind, data):
    img = bytearray(_with_code(section, kind))
    c = _tmodel.TModel.from_image(bytes(img))
    before = c.apply([0, 40000], np.zeros((2, c.n_axes), np.int16))
    i = data.draw(st.integers(0, len(img) - 1))
    img[i] ^= 1 << data.draw(st.integers(0, 7))
    st_ref, _ = ref.load(bytes(img))
    assert c.load(bytes(img)) == st_ref
    if st_ref != 0:
        after = c.apply([0, 40000], np.zeros((2, c.n_axes), np.int16))
        assert all(np.array_equal(a, b) for a, b in zip(before, after))


def test_bad_temperature_code_section_is_a_format_error():
    section = (SECTION_PWL_TABLE, pwl_payload([PwlQ16(np.zeros(3, np.int16), 0, 100, plan_q16(0, 100, 3), 0, 1, 0.0)]))
    for payload in (b"\x02\x00", b"\x00\x01", b"\x00"):
        img = build_image([section, (SECTION_TEMP_CODE, payload)])
        assert ref.load(img)[0] == -3 and _tmodel.TModel().load(img) == -3
    assert _tmodel.TModel().load(build_image([(SECTION_TEMP_CODE, b"\x01\x00")])) == -5


@pytest.mark.parametrize("codes,kind,t", [
    ([63000, 65000, 65535, 0], TCODE_UINT16, [63000 - 32768, 65000 - 32768, 32767, -32768]),
    ([-10153, -1, 1559], TCODE_INT16, [-10153, -1, 1559])])
def test_code_to_t(codes, kind, t):
    tc = raw_code(codes)
    assert tc.code_kind == kind
    bits = tc.codes(tc.to_t(codes))
    assert list(_tmodel.code_to_t(kind, bits)) == t == [ref.code_to_t(kind, int(b)) for b in bits]
