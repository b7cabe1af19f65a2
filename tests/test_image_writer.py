"""The library's coefficient-image writer and reader (pysig.store._image) are
library code, separate from the executable spec (spec.image):
they agree with it byte for byte on any sections and sequence, the reader
accepts exactly what the spec's validation accepts, and the library never
imports the reference."""
import subprocess
import sys

from hypothesis import given, settings, strategies as st

from spec import image as ref
from pysig.store import _image as lib

sections = st.lists(st.tuples(st.integers(1, 0xFFFF), st.binary(max_size=40)), max_size=5)


@settings(max_examples=200, deadline=None)
@given(sections, st.integers(0, 0xFFFFFFFF))
def test_writer_equals_reference(secs, seq):
    data = lib.build_image(secs, seq)
    assert data == ref.build(secs, seq)
    assert lib.read_image(data) == (ref.sequence(data), ref.sections(data))


@settings(max_examples=300, deadline=None)
@given(sections, st.integers(0, 0xFFFFFFFF), st.data())
def test_reader_accepts_exactly_what_the_spec_accepts(secs, seq, data):
    img = bytearray(lib.build_image(secs, seq))
    i = data.draw(st.integers(0, len(img) - 1))
    img[i] ^= 1 << data.draw(st.integers(0, 7))
    cut = data.draw(st.integers(0, len(img)))
    for candidate in (bytes(img), bytes(img[:cut])):
        ok = ref.validate(candidate) == ref.SIG_OK
        try:
            lib.read_image(candidate)
            accepted = True
        except lib.ModelFileError:
            accepted = False
        assert accepted == ok


def test_crc_equals_reference():
    for payload in (b"", b"123456789", bytes(range(256))):
        assert lib.crc16_ccitt(payload) == ref.crc16_ccitt(payload)
    assert lib.crc16_ccitt(b"123456789") == 0x29B1        # the CRC-16/CCITT-FALSE check value


def test_library_never_imports_the_reference():
    code = ("import sys, pysig.tcomp._poly_fit, pysig.tcomp._poly_model, pysig.tcomp._table_fit, pysig.tcomp._quant, "
            "pysig.tcomp._cross_validation, pysig.tcomp._tempcode, pysig.tcomp._calibration, pysig.store._image, "
            "pysig.cli.commands.fit, pysig.cli.commands.export, pysig.cli.commands.apply; "
            "print([m for m in sys.modules if m.startswith('spec')])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
