"""Coefficient image (csrc/store/sig_image.c, sig_crc16.c; pysig/store/_image.py): C ==
Python spec on every byte string, generic sections, and the power-cut test
of the A/B slot storage: cut after every byte and after every programmed
bit, flip every bit, and the C loader always returns exactly the old or the
new calibration and says which."""
import struct

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from pysig.store import _image_c
from pysig.tcomp import _tcomp
from pysig.tcomp import _poly_fit as fit
from pysig.store import _image as image
from pysig.sim import _chamber as sim_chamber
from pysig.errors import ModelFileError
from spec import image as ref


def chamber_model(seed, order=2, axes="xyz"):
    data = sim_chamber.simulate(sim_chamber.ChamberParams(seed=seed, dwell_s=600))
    return fit.fit_tcomp(data["temp"], {k: data[k] for k in axes}, order=order)


@pytest.fixture(scope="module")
def old_new():
    return chamber_model(1), chamber_model(2, order=3)


def test_crc16_check_value():
    assert _image_c.crc16(b"123456789") == 0x29B1 == ref.crc16_ccitt(b"123456789")
    assert _image_c.crc16(b"") == 0xFFFF


@settings(max_examples=200, deadline=None)
@given(st.binary(max_size=300))
def test_crc16_c_equals_reference(data):
    assert _image_c.crc16(data) == ref.crc16_ccitt(data)


@st.composite
def images(draw):
    secs = draw(st.lists(st.tuples(st.integers(1, 0xFFFF), st.binary(max_size=40)), max_size=5))
    return image.build_image(secs, draw(st.integers(0, 0xFFFFFFFF)))


@settings(max_examples=300, deadline=None)
@given(img=images(), data=st.data())
def test_validate_and_find_c_equals_reference_on_mutations(img, data):
    buf = bytearray(img)
    kind = data.draw(st.sampled_from(["none", "byte", "truncate", "extend", "length"]))
    if kind == "byte":
        i = data.draw(st.integers(0, len(buf) - 1))
        buf[i] = data.draw(st.integers(0, 255))
    elif kind == "truncate":
        buf = buf[:data.draw(st.integers(0, len(buf)))]
    elif kind == "extend":
        buf += data.draw(st.binary(max_size=10))
    elif kind == "length" and len(buf) >= 8:
        struct.pack_into("<H", buf, 6, data.draw(st.integers(0, 0xFFFF)))
    buf = bytes(buf)
    assert _image_c.image_validate(buf) == ref.validate(buf)
    if kind == "none":
        assert ref.validate(buf) == ref.SIG_OK
    for typ in (1, 2, 7, 0x8000):
        assert _image_c.image_find_section(buf, typ) == ref.find_section(buf, typ)


def test_generic_sections_round_trip_and_unknown_types_are_skipped():
    secs = [(image.SECTION_PWL_TABLE, b"\x01\x02\x03"), (0x8123, b""), (image.SECTION_GAIN_POLY, bytes(range(50)))]
    img = image.build_image(secs, sequence=77)
    assert image.read_image(img) == (77, secs)
    assert _image_c.image_find_section(img, image.SECTION_GAIN_POLY) == (0, bytes(range(50)))
    assert _image_c.image_find_section(img, image.SECTION_OFFSET_POLY) == (ref.SIG_ERR_EMPTY, None)
    assert _image_c.image_sequence(img) == (0, 77)


def test_offset_section_c_loader_equals_python(old_new):
    for model in old_new:
        img = image.model_image(model, sequence=5, extra_sections=[(image.SECTION_PWL_TABLE, b"xyz")])
        c = _tcomp.TcompQ.from_image(img)
        assert c.fields() == model.fixed_fields()
        payload = image.find_section(img, image.SECTION_OFFSET_POLY)
        parsed = image.parse_offset_poly(payload)
        assert {k: parsed[k] for k in c.fields()} == c.fields()


@pytest.mark.parametrize("mutate, status", [
    (lambda b: b"PSIG" + b[4:], "bad format"),
    (lambda b: b[:4] + b"\x02" + b[5:], "bad format"),
    (lambda b: b[:-1] + bytes([b[-1] ^ 1]), "CRC"),
    (lambda b: b[:20], "bad format"),
])
def test_corrupt_images_are_refused_by_c_and_python(old_new, mutate, status):
    bad = mutate(image.model_image(old_new[0]))
    with pytest.raises(ModelFileError, match=status):
        _tcomp.TcompQ.from_image(bad)
    with pytest.raises(ModelFileError):
        image.read_image(bad)


def test_malformed_offset_payload_is_a_format_error_in_c():
    m = chamber_model(4, axes="x")
    payload = bytearray(image.offset_poly_payload(m))
    for patch in ({1: 9}, {0: 4}, {3: 1}):               # order 9, 4 axes, reserved != 0
        p = bytearray(payload)
        for k, v in patch.items():
            p[k] = v
        bad = image.build_image([(image.SECTION_OFFSET_POLY, bytes(p))])
        with pytest.raises(ModelFileError, match="bad format"):
            _tcomp.TcompQ.from_image(bad)
    with pytest.raises(ModelFileError, match="bad format"):
        _tcomp.TcompQ.from_image(image.build_image([(image.SECTION_OFFSET_POLY, bytes(payload[:-1]))]))


# ---- A/B slots and the power cut -------------------------------------------

SLOT_SIZE = 256


def slot(content, fill=0xFF):
    return bytes(content) + bytes([fill]) * (SLOT_SIZE - len(content))


def load(slot_a, slot_b):
    """What the firmware does at boot: choose a slot, load it with the C
    loader.  Returns (which, fields) or (None, None)."""
    st_c, which = _image_c.image_select_slot(slot_a, slot_b)
    assert (st_c, which) == ref.select_slot(slot_a, slot_b)
    if st_c != 0:
        return None, None
    return which, _tcomp.TcompQ.from_image(slot_a if which == 0 else slot_b).fields()


def test_power_cut_after_every_byte_and_bit(old_new):
    old, new = old_new
    img_old = image.model_image(old, sequence=41)
    img_new = image.model_image(new, sequence=42)
    f_old, f_new = old.fixed_fields(), new.fixed_fields()
    assert f_old != f_new
    a = slot(img_old)
    # initially: A holds the live calibration, B an erased (or stale) region
    assert load(a, slot(b"")) == (0, f_old)
    cases = 0
    # 1. byte-wise writing into the erased slot B, cut after every byte
    for k in range(len(img_new) + 1):
        b = slot(img_new[:k])
        which, fields = load(a, b)
        # complete when every byte is written, or when the unwritten tail
        # already holds the new bytes (0xFF in both)
        want = (1, f_new) if b[:len(img_new)] == img_new else (0, f_old)
        assert (which, fields) == want, f"cut after byte {k}"
        cases += 1
    # 2. flash programming clears bits 1 -> 0 one at a time: cut after every bit
    erased = np.full(SLOT_SIZE, 0xFF, dtype=np.uint8)
    bits_new = np.unpackbits(np.frombuffer(slot(img_new), dtype=np.uint8))
    bits = np.unpackbits(erased)
    for j in range(len(img_new) * 8 + 1):
        partial = bits.copy()
        partial[:j] = bits_new[:j]
        b = np.packbits(partial).tobytes()
        which, fields = load(a, b)
        want = (1, f_new) if b[:len(img_new)] == img_new else (0, f_old)
        assert (which, fields) == want, f"cut after bit {j}"
        cases += 1
    # 3. every single bit flipped in the freshly written slot B: old stays live
    b_full = slot(img_new)
    for j in range(len(img_new) * 8):
        flipped = bytearray(b_full)
        flipped[j // 8] ^= 0x80 >> (j % 8)
        assert load(a, bytes(flipped)) == (0, f_old), f"bit {j} flipped in the new image"
        cases += 1
    # 4. and once B is complete, a bit flip in the old slot A changes nothing
    for j in range(0, len(img_old) * 8, 7):
        flipped = bytearray(a)
        flipped[j // 8] ^= 0x80 >> (j % 8)
        assert load(bytes(flipped), b_full) == (1, f_new)
        cases += 1
    # 5. writing over a stale image (no erase): cut after every byte
    stale = slot(image.model_image(old, sequence=40))
    for k in range(len(img_new) + 1):
        b = img_new[:k] + stale[k:]
        which, fields = load(a, b)
        want = (1, f_new) if b[:len(img_new)] == img_new else (0, f_old)
        assert (which, fields) == want, f"cut after byte {k} over a stale image"
        cases += 1
    assert cases > 2 * len(img_new) * 8      # every byte, every bit, every flip ran


def test_nothing_valid_is_reported_empty():
    assert _image_c.image_select_slot(slot(b""), slot(b"")) == (ref.SIG_ERR_EMPTY, None)
    assert _image_c.image_select_slot(None, None) == (ref.SIG_ERR_EMPTY, None)


@pytest.mark.parametrize("seq_a, seq_b, which", [
    (1, 2, 1), (2, 1, 0), (5, 5, 0), (0xFFFFFFFF, 0, 1), (0, 0xFFFFFFFF, 0), (0x7FFFFFF0, 0x80000001, 1),
])
def test_sequence_numbers_wrap(seq_a, seq_b, which):
    a = slot(image.build_image([(7, b"a")], seq_a))
    b = slot(image.build_image([(7, b"b")], seq_b))
    assert _image_c.image_select_slot(a, b) == (0, which) == ref.select_slot(a, b)
    assert _image_c.image_select_slot(None, b) == (0, 1)


def test_offset_section_with_u_shift_above_15_is_refused():
    m = chamber_model(5, axes="x")
    p = bytearray(image.offset_poly_payload(m))
    p[2] = 16
    with pytest.raises(ModelFileError, match="bad format"):
        _tcomp.TcompQ.from_image(image.build_image([(image.SECTION_OFFSET_POLY, bytes(p))]))


def test_python_constants_match_the_c_headers():
    import re
    from conftest import CSRC_INCLUDE
    from pysig.tcomp import _quant as quant
    from spec import tcomp as rtc
    hdr = (CSRC_INCLUDE / "sig_image.h").read_text()
    ids = {m.group(1): int(m.group(2), 0) for m in re.finditer(r"#define SIG_SECTION_(\w+)\s+(0x[0-9A-Fa-f]+|\d+)u", hdr)}
    for name, value in ids.items():
        if name != "INVALID":
            assert getattr(image, "SECTION_" + name) == value, name
    from pysig.store import _device as device_id
    from spec import device_id as ref_device_id
    assert device_id.SECTION_DEVICE_ID == ref_device_id.SECTION_DEVICE_ID == ids["DEVICE_ID"]
    assert int(re.search(r"SIG_OFFSET_POLY_FIXED_LEN (\d+)u", hdr).group(1)) == image.OFFSET_POLY_FIXED_LEN
    assert int(re.search(r"SIG_IMAGE_HEADER_LEN\s+(\d+)u", hdr).group(1)) == ref.HEADER_LEN
    tc = (CSRC_INCLUDE / "sig_tcomp.h").read_text()
    assert int(re.search(r"SIG_TCOMP_T_PER_DEGC (\d+)", tc).group(1)) == quant.T_PER_DEGC == rtc.T_PER_DEGC
    assert int(re.search(r"SIG_TCOMP_MAX_Q\s+(\d+)u", tc).group(1)) == quant.MAX_Q == rtc.MAX_Q
