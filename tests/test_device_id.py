"""The device-id section: the C id and image check (through Cython) equal
the pure-Python spec for any serial and any image; device A's image offered
to device B is refused with SIG_ERR_DEVICE."""
import pytest
from hypothesis import given, settings, strategies as st

from pysig.errors import ModelFileError
from spec import device_id as ref
from spec import image as ref_image
from pysig.store._device_id import check_image, device_id
from pysig.store._device import (SIG_ERR_DEVICE, device_section, image_device_status,
                                   require_device)
from pysig.store._image import SECTION_OFFSET_POLY, build_image


@settings(max_examples=300, deadline=None)
@given(st.binary(min_size=1, max_size=80))
def test_c_device_id_equals_reference(serial):
    st_, ident = device_id(serial)
    assert st_ == 0 and ident == ref.make(serial)


@settings(max_examples=300, deadline=None)
@given(made_for=st.binary(min_size=1, max_size=40), runs_on=st.binary(min_size=1, max_size=40),
       other=st.binary(max_size=20), flip=st.integers(0, 10_000))
def test_c_check_equals_reference(made_for, runs_on, other, flip):
    image = bytearray(build_image([(SECTION_OFFSET_POLY, other or b"\0"),
                                   (ref.SECTION_DEVICE_ID, ref.payload(made_for))], 7))
    if flip % 3 == 0:                       # a third of the cases: a corrupt image
        image[flip % len(image)] ^= 1 << (flip % 8)
    want = ref.check_image(bytes(image), ref.make(runs_on))
    assert check_image(bytes(image), runs_on) == want
    if flip % 3 and made_for != runs_on and ref.make(made_for) != ref.make(runs_on):
        assert want == SIG_ERR_DEVICE


def test_device_a_image_offered_to_device_b_is_refused():
    image = build_image([(SECTION_OFFSET_POLY, b"\x01\x02"), device_section("A-0001")], 1)
    assert image_device_status(image, "A-0001") == 0
    assert image_device_status(image, "B-0002") == SIG_ERR_DEVICE
    require_device(image, "A-0001")
    with pytest.raises(ModelFileError, match="another device, not 'B-0002'"):
        require_device(image, "B-0002")


def test_image_without_id_is_refused_and_malformed_id_is_a_format_error():
    plain = build_image([(SECTION_OFFSET_POLY, b"\x01")], 1)
    assert image_device_status(plain, "A") == SIG_ERR_DEVICE
    bad = build_image([(ref.SECTION_DEVICE_ID, b"\x00\x05ab")], 1)
    assert image_device_status(bad, "ab") == ref_image.SIG_ERR_FORMAT == ref.check_image(bad, ref.make(b"ab"))


def test_long_serials_share_a_tail_but_not_an_id():
    a = "PLANT-01/LINE-4/LOT-2026-47/000123"
    b = "PLANT-02/LINE-4/LOT-2026-47/000123"
    assert ref.make(a.encode())[1][4:] == ref.make(b.encode())[1][4:]       # same last 12 bytes
    image = build_image([device_section(a)], 1)
    assert image_device_status(image, a) == 0 and image_device_status(image, b) == SIG_ERR_DEVICE
