"""Piecewise-linear tables in the coefficient image (section type 6): the
Python writer, the reference reader and the C loader (sig_pwl_load_image)
agree, and every malformed payload is refused by both without writing."""
import struct

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from pysig.tcomp import _pwl
from pysig.errors import ModelFileError, RangeError
from pysig.store._image import SECTION_OFFSET_POLY, SECTION_PWL_TABLE, build_image
from pysig.tcomp._table_fit import (PwlQ16, fit_pwl_q16, parse_pwl_payload, plan_q16, pwl_image, pwl_payload,
                       read_pwl_image)


def _tables(n_axes=3, n=9):
    temp = np.linspace(-5.0, 45.0, 1001)
    return [fit_pwl_q16(temp, np.cos(temp / 6.0) * 200.0 * (a + 1) - 30 * a, n)
            for a in range(n_axes)]


def _same(c_loaded, tables):
    assert len(c_loaded) == len(tables)
    for c, t in zip(c_loaded, tables):
        assert np.array_equal(c["table"], t.table)
        assert (c["t_lo"], c["t_hi"], c["recip"], c["value_frac"]) == \
            (t.t_lo, t.t_hi, t.recip, t.value_frac)


@pytest.mark.parametrize("n_axes,n", [(1, 2), (2, 17), (3, 184), (3, 255)])
def test_round_trip_python_and_c(n_axes, n):
    tables = _tables(n_axes, n)
    img = pwl_image(tables, sequence=42)
    back = read_pwl_image(img)
    for b, t in zip(back, tables):
        assert np.array_equal(b.table, t.table) and b.recip == t.recip
    _same(_pwl.load_image(img), tables)
    # the loaded tables evaluate exactly like the fitted ones
    temps = np.arange(-700, 4800, 37, dtype=np.int16)
    for b, t in zip(back, tables):
        assert np.array_equal(b.eval_c(temps)[0], t.eval_c(temps)[0])


def test_payload_layout():
    t = _tables(1, 3)[0]
    p = pwl_payload([t])
    assert len(p) == 10 + 1 + 2 * 3
    assert struct.unpack_from("<BBhhI", p) == (1, 3, t.t_lo, t.t_hi, t.recip)
    assert p[10] == t.value_frac
    assert list(struct.unpack_from("<3h", p, 11)) == [int(v) for v in t.table]


def test_tables_must_share_knots():
    a = _tables(1, 9)[0]
    b = _tables(1, 10)[0]
    with pytest.raises(RangeError, match="table 1 has other knots"):
        pwl_payload([a, b])
    with pytest.raises(RangeError):
        pwl_payload([])
    with pytest.raises(RangeError):
        pwl_payload(_tables(3, 5) + _tables(1, 5))


def test_image_without_table_section():
    img = build_image([(SECTION_OFFSET_POLY, b"\0" * 14)])
    with pytest.raises(ModelFileError, match="no section of type 6"):
        read_pwl_image(img)
    with pytest.raises(ModelFileError, match="no piecewise-linear table section"):
        _pwl.load_image(img)


def test_corrupt_image_is_refused():
    img = bytearray(pwl_image(_tables(2, 9)))
    img[20] ^= 0x10
    with pytest.raises(ModelFileError, match="CRC"):
        read_pwl_image(bytes(img))
    with pytest.raises(ModelFileError, match="CRC"):
        _pwl.load_image(bytes(img))
    with pytest.raises(ModelFileError):
        _pwl.load_image(bytes(img[:30]))


@pytest.mark.parametrize("mutate,what", [
    (lambda p: p[:-1], "length"),
    (lambda p: p + b"\0", "length"),
    (lambda p: bytes([0]) + p[1:], "axes"),
    (lambda p: bytes([4]) + p[1:], "axes"),
    (lambda p: p[:1] + bytes([1]) + p[2:], "knots"),
    (lambda p: p[:6] + struct.pack("<I", 0) + p[10:], "recip"),
    (lambda p: p[:2] + struct.pack("<h", 5000) + p[4:], "range"),
    (lambda p: p[:10] + bytes([16]) + p[11:], "value_frac"),
])
def test_malformed_payload_refused_by_both(mutate, what):
    payload = mutate(pwl_payload(_tables(1, 9)))
    img = build_image([(SECTION_PWL_TABLE, payload)])
    with pytest.raises(ModelFileError):
        parse_pwl_payload(payload)
    with pytest.raises(ModelFileError, match="bad format"):
        _pwl.load_image(img)


@st.composite
def payloads(draw):
    n_axes = draw(st.integers(1, 3))
    t_lo = draw(st.integers(-32768, 32000))
    t_hi = draw(st.integers(t_lo + 2, min(32767, t_lo + 65535)))
    n = draw(st.integers(2, min(40, t_hi - t_lo)))
    recip = plan_q16(t_lo, t_hi, n)
    tables = [PwlQ16(table=np.array(draw(st.lists(st.integers(-32768, 32767), min_size=n,
                                                  max_size=n)), np.int16),
                     t_lo=t_lo, t_hi=t_hi, recip=recip, value_frac=draw(st.integers(0, 15)),
                     units_per_c=100.0, rms=0.0) for _ in range(n_axes)]
    raw = bytearray(pwl_payload(tables))
    for _ in range(draw(st.integers(0, 3))):          # random byte edits, valid CRC
        i = draw(st.integers(0, len(raw) - 1))
        raw[i] = draw(st.integers(0, 255))
    return bytes(raw)


@settings(max_examples=300, deadline=None)
@given(payloads())
def test_c_loader_agrees_with_reference_reader(payload):
    img = build_image([(SECTION_PWL_TABLE, payload)])
    try:
        expect = parse_pwl_payload(payload)
    except ModelFileError:
        with pytest.raises(ModelFileError):
            _pwl.load_image(img)
        return
    _same(_pwl.load_image(img), expect)
