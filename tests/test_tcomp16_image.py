"""The compact model in the coefficient image (section 8, SIG_SECTION_COMPACT_POLY):
writer pysig/store/_image.py, spec tests/spec/image.py (load_compact), C loader
sig_tcomp16_load_image (csrc/tcomp/sig_tcomp16_image.c).  Round trip model ->
image -> C loader -> apply equals the Python spec bit for bit; every bit flip
and every truncation is refused with the C model untouched; on mutated
payloads the C loader and the spec agree (status and fields) and accept
exactly what sig_tcomp16_init accepts; the CLI round trip export --compact ->
apply, and its errors."""
import struct

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from conftest import I16, I32, draw_int16_rows
from pysig.tcomp import _tcomp16
from pysig.tcomp import _poly_fit as fit, _quant as quant
from pysig.store import _image as image
from pysig.sim import _chamber as sim_chamber
from pysig.cli import main
from pysig.errors import InputFileError, ModelFileError, RangeError
from pysig.io import read_csv
from spec import image as ref
from spec import tcomp16 as ref16
from test_tcomp16 import compact_models


@pytest.fixture(scope="module")
def compact_models_by_order():
    d = sim_chamber.simulate(sim_chamber.ChamberParams(seed=3, dwell_s=600))
    out = {}
    for order, axes in ((1, "x"), (2, "xyz"), (3, "xy")):
        m = fit.fit_tcomp(d["temp"], {k: d[k] for k in axes}, order=order)
        out[order] = quant.quantize_compact(m)
    return out


def c_status(data):
    """Status of sig_tcomp16_load_image on `data` into a fresh (zeroed) model."""
    return _tcomp16.Tcomp16Q.__new__(_tcomp16.Tcomp16Q).load(data)


def test_round_trip_model_image_c_loader_apply_bit_exact(compact_models_by_order):
    rng = np.random.default_rng(0)
    for order, cm in compact_models_by_order.items():
        img = image.compact_image(cm, sequence=order,
                                  extra_sections=[(image.SECTION_PWL_TABLE, b"xyz"), (0x8001, b"")])
        assert image.read_image(img)[0] == order
        c = _tcomp16.Tcomp16Q.from_image(img)
        fields = cm.fields()
        assert c.fields() == fields == image.parse_compact_poly(img) == ref.load_compact(img)[1]
        assert c.raw() == _tcomp16.Tcomp16Q.from_compact(cm).raw()
        n = len(fields["top"])
        t = np.concatenate([np.arange(cm.t_lo - 300, cm.t_hi + 300, 7), [cm.t_lo, cm.t_hi, -32768, 32767]])
        x = rng.integers(-32768, 32768, size=(t.size, n)).astype(np.int16)
        x[:4] = [[32767] * n, [-32768] * n, [0] * n, [1] * n]
        got, status = c.apply(t, x)
        for i in range(t.size):
            assert (list(got[i]), status[i]) == ref16.apply_q(fields, int(t[i]), [int(v) for v in x[i]])


def test_payload_layout_is_the_documented_one(compact_models_by_order):
    cm = compact_models_by_order[2]
    p = image.compact_poly_payload(cm)
    assert len(p) == image.COMPACT_POLY_FIXED_LEN + 3 * (2 + 4 * 2)
    assert struct.unpack_from("<BBBBhh", p) == (3, 2, cm.w_shift, 0, cm.t_lo, cm.t_hi)
    assert struct.unpack_from("<hii", p, 8) == (cm.top[0], *cm.add[0])
    with pytest.raises(RangeError, match="sig_tcomp16_init"):
        image.compact_poly_payload({**cm.fields(), "w_shift": 16})


def test_every_bit_flip_and_truncation_is_refused_model_untouched(compact_models_by_order):
    old = image.compact_image(compact_models_by_order[1], sequence=1)
    new = image.compact_image(compact_models_by_order[2], sequence=2)
    c = _tcomp16.Tcomp16Q.from_image(old)
    before, fields = c.raw(), c.fields()
    for bit in range(len(new) * 8):
        bad = bytearray(new)
        bad[bit // 8] ^= 1 << (bit % 8)
        st_c = c.load(bytes(bad))
        assert st_c != 0 and st_c == ref.load_compact(bytes(bad))[0], bit
        assert c.raw() == before
    for n in range(len(new)):
        st_c = c.load(new[:n])
        assert st_c != 0 and st_c == ref.load_compact(new[:n])[0], n
        assert c.raw() == before
    with pytest.raises(ModelFileError, match="rejected the image"):
        _tcomp16.Tcomp16Q.from_image(new[:-1])
    assert c.fields() == fields
    assert c.load(new) == 0 and c.fields() == compact_models_by_order[2].fields()


def test_image_without_compact_section_and_wrong_section_type():
    off = image.build_image([(image.SECTION_OFFSET_POLY, b"\0" * 14)])
    assert c_status(off) == ref.SIG_ERR_EMPTY == ref.load_compact(off)[0]
    with pytest.raises(ModelFileError, match="no compact-polynomial section"):
        _tcomp16.Tcomp16Q.from_image(off)
    with pytest.raises(ModelFileError, match="no section of type 8"):
        image.parse_compact_poly(off)


@st.composite
def mutated_payloads(draw):
    """(payload, fields it was built from): a valid compact payload, then one
    mutation: a field set to any value, a coefficient or byte changed, the
    payload cut or extended."""
    model = draw(compact_models())
    fields = {k: (list(map(list, v)) if k == "add" else list(v) if k == "top" else v)
              for k, v in model.items()}
    kind = draw(st.sampled_from(["none", "t_lo", "t_hi", "w_shift", "top", "add", "counts",
                                 "reserved", "byte", "cut", "extend"]))
    if kind in ("t_lo", "t_hi"):
        fields[kind] = draw(I16)
    elif kind == "w_shift":
        fields["w_shift"] = draw(st.integers(0, 255))
    elif kind == "top":
        fields["top"][draw(st.integers(0, len(fields["top"]) - 1))] = draw(I16)
    elif kind == "add":
        row = fields["add"][draw(st.integers(0, len(fields["add"]) - 1))]
        row[draw(st.integers(0, len(row) - 1))] = draw(I32)
    payload = bytearray(ref.compact_payload(fields))
    if kind == "counts":
        payload[draw(st.integers(0, 1))] = draw(st.integers(0, 255))
    elif kind == "reserved":
        payload[3] = draw(st.integers(1, 255))
    elif kind == "byte":
        payload[draw(st.integers(0, len(payload) - 1))] = draw(st.integers(0, 255))
    elif kind == "cut":
        payload = payload[:draw(st.integers(0, len(payload) - 1))]
    elif kind == "extend":
        payload += draw(st.binary(min_size=1, max_size=6))
    return bytes(payload), fields, kind


@settings(max_examples=400, deadline=None)
@given(case=mutated_payloads(), temps=st.lists(I16, min_size=1, max_size=4), data=st.data())
def test_c_loader_equals_reference_reader_on_mutated_payloads(case, temps, data):
    payload, fields, kind = case
    img = image.build_image([(image.SECTION_COMPACT_POLY, payload)], sequence=data.draw(st.integers(0, 9)))
    want_st, want_fields = ref.load_compact(img)
    c = _tcomp16.Tcomp16Q.from_fields([1], [[0]], 0, 1, 0)
    before = c.raw()
    assert c.load(img) == want_st
    if kind in ("none", "t_lo", "t_hi", "w_shift", "top", "add"):
        # well-formed payload: the loader accepts exactly what sig_tcomp16_init accepts
        assert (want_st == ref.SIG_OK) == ref16.valid(fields)
        try:
            _tcomp16.Tcomp16Q.from_fields(**fields)
            init_ok = True
        except RangeError:
            init_ok = False
        assert init_ok == (want_st == ref.SIG_OK)
        if want_st == ref.SIG_OK:
            assert want_fields == fields
    if want_st != ref.SIG_OK:
        assert want_st == ref.SIG_ERR_FORMAT and c.raw() == before
        with pytest.raises(ModelFileError):
            image.parse_compact_poly(img)
        return
    assert c.fields() == want_fields == image.parse_compact_poly(img)
    n = len(want_fields["top"])
    x = draw_int16_rows(data, len(temps), n)
    got, status = c.apply(np.array(temps), x)
    for i, t in enumerate(temps):
        assert (list(got[i]), status[i]) == ref16.apply_q(want_fields, t, [int(v) for v in x[i]])


# ---- the command line --------------------------------------------------------

@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    d = tmp_path_factory.mktemp("compact")
    src, mj = d / "chamber.csv", d / "model.json"
    sim_chamber.write(src, sim_chamber.ChamberParams(seed=12, dwell_s=600))
    assert main(["fit", str(src), "--temp", "temp", "--columns", "x,y,z", "--order", "2",
                 "-o", str(mj)]) == 0
    return src, mj


def test_cli_export_compact_then_apply_runs_the_c_loader(tmp_path, fitted, capsys):
    src, mj = fitted
    img, out = tmp_path / "m16.bin", tmp_path / "out.csv"
    assert main(["export", str(mj), "--format", "image", "--compact", "--sequence", "4", "-o", str(img)]) == 0
    from pysig.tcomp import _poly_model as tmodel
    cm = quant.quantize_compact(tmodel.load(mj))
    assert img.read_bytes() == image.compact_image(cm, sequence=4)
    assert main(["apply", str(src), "--model", str(img), "--temp", "temp", "--columns", "x,y,z",
                 "-o", str(out)]) == 0
    d, o = read_csv(src), read_csv(out)
    t = quant.to_centi(d["temp"])
    x = np.column_stack([d[k] for k in "xyz"]).astype(np.int16)
    got = np.column_stack([o[k + "_comp"] for k in "xyz"])
    for i in range(0, len(t), 53):
        want, want_st = ref16.apply_q(cm.fields(), int(t[i]), [int(v) for v in x[i]])
        assert list(got[i]) == want and o["tcomp_clamped"][i] == want_st & 1
    want_all, _ = _tcomp16.Tcomp16Q.from_compact(cm).apply(t, x)
    np.testing.assert_array_equal(got, want_all)


def test_cli_corrupt_compact_image_is_exit_6_and_writes_nothing(tmp_path, fitted, capsys):
    src, mj = fitted
    img, out = tmp_path / "m16.bin", tmp_path / "out.csv"
    assert main(["export", str(mj), "--format", "image", "--compact", "-o", str(img)]) == 0
    good = img.read_bytes()
    for bad in (good[:-3], good[:20] + bytes([good[20] ^ 0x10]) + good[21:]):
        img.write_bytes(bad)
        capsys.readouterr()
        assert main(["apply", str(src), "--model", str(img), "--temp", "temp", "--columns", "x,y,z",
                     "-o", str(out)]) == ModelFileError.exit_status == 6
        err = capsys.readouterr().err
        assert err.startswith("pysig apply: error: ") and str(img) in err and "rejected the image" in err
        assert not out.exists()
    img.write_bytes(image.build_image([(image.SECTION_LINEAR_SCALE, b"abc")]))
    assert main(["apply", str(src), "--model", str(img), "--temp", "temp", "--columns", "x,y,z",
                 "-o", str(out)]) == 6
    assert "no model section" in capsys.readouterr().err


def test_cli_export_compact_refuses_a_model_that_does_not_fit(tmp_path, capsys):
    temp = np.repeat(np.linspace(0.0, 70.0, 8), 5)
    src, mj, img = tmp_path / "steep.csv", tmp_path / "steep.json", tmp_path / "m16.bin"
    src.write_text("temp,x\n" + "".join(f"{a:.2f},{80.0 * (a - 25):.1f}\n" for a in temp))
    assert main(["fit", str(src), "--temp", "temp", "--columns", "x", "--order", "2", "-o", str(mj)]) == 0
    capsys.readouterr()
    assert main(["export", str(mj), "--format", "image", "--compact", "-o", str(img)]) == RangeError.exit_status
    err = capsys.readouterr().err
    assert "steep.json: compact form, axis 'x'" in err and "int32 form" in err and not img.exists()
    # the int32 image still holds it
    assert main(["export", str(mj), "--format", "image", "-o", str(img)]) == 0
    assert main(["export", str(mj), "--format", "c", "--compact", "-o", str(tmp_path / "m.h")]) \
        == InputFileError.exit_status
    assert "--compact applies to --format image only" in capsys.readouterr().err
