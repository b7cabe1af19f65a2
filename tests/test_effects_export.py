"""A refined model on the device: the firmware's sig_refined_step_q (C via
Cython) equals the Python fixed-point reference bit for bit, follows the
float model refine fitted, and travels in the coefficient image."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from pysig.refine import _device as ed
from pysig.errors import ModelFileError
from pysig.tcomp._quant import choose_scaling, quantize_axis
from pysig.refine._loop import refine

from spec import effects as R
from lab.studies.refine_cases import chamber_run, fit_data


def correct_reference(dev, t_centi, y):
    """The Python fixed-point spec of sig_refined_step_q: corrected readings
    in Q16.16 LSB and the status of each sample."""
    r = R.RefinedQ(dev["offset"], dev["lag"], dev["hyst"])
    out = [r.step(int(t), int(v)) for t, v in zip(t_centi, y)]
    return np.array([o for o, _ in out], dtype=np.int64), np.array([s for _, s in out])


@st.composite
def device_models(draw):
    lo = draw(st.integers(-4000, 3000))
    hi = draw(st.integers(lo + 100, 9000))
    sc = choose_scaling(lo, hi)
    order = draw(st.integers(1, 4))
    coef = draw(st.lists(st.floats(-500, 500), min_size=order + 1, max_size=order + 1))
    qa = quantize_axis(coef)
    offset = {"coef": list(qa.coef), "q": qa.q, "t_lo": sc.t_lo, "t_hi": sc.t_hi,
              "t_center": sc.t_center, "t0": sc.t_center, "u_mul": sc.u_mul, "u_shift": sc.u_shift}
    lag = draw(st.none() | st.integers(1, 65536))
    hyst = draw(st.none() | st.tuples(st.integers(1, 2000), st.integers(-(1 << 31), (1 << 31) - 1),
                                      st.sampled_from([-1, 0, 1])))
    return {"offset": offset, "lag": lag, "hyst": hyst}


@settings(max_examples=120, deadline=None)
@given(dev=device_models(), data=st.data())
def test_refined_c_equals_reference(dev, data):
    n = data.draw(st.integers(1, 40))
    t = data.draw(st.lists(st.integers(-32768, 32767), min_size=n, max_size=n))
    y = data.draw(st.lists(st.integers(-32768, 32767), min_size=n, max_size=n))
    out, status = ed.correct_c(dev, t, y)
    ref_out, ref_status = correct_reference(dev, t, y)
    assert out.tolist() == ref_out.tolist()
    assert status.tolist() == ref_status.tolist()


@pytest.fixture(scope="module")
def refined_run():
    """A constant-field run with both a thermal lag (90 s) and hysteresis
    (+-5 LSB, 0.8 °C) that the fit is not told about; noise 1 LSB."""
    run = chamber_run(("thermal_lag", "hysteresis"), seed=2, constant_field=True)
    return run, refine(fit_data(run, use_ref=False, others=()))


def test_refined_model_on_device_follows_the_fit(refined_run):
    run, res = refined_run
    names = {s.effect for s in res.steps}
    assert {"thermal_lag", "hysteresis"} <= names, names
    dev = ed.device_model(res)
    assert dev["lag"] is not None and dev["hyst"] is not None
    t_centi = np.rint(run["temp"] * 100).astype(np.int64)
    y = np.rint(run["x"]).astype(np.int64)          # the sensor's int16 readings
    out, status = ed.correct_c(dev, t_centi, y)
    ref_out, _ = correct_reference(dev, t_centi, y)
    assert out.tolist() == ref_out.tolist()
    assert not np.any(status < 0)
    fixed = out / 65536.0
    flt = ed.correct_float(dev, run["temp"], y)
    # fixed vs float: Q16 rounding, 0.01 °C temperature steps through the lag and the
    # play operator; stated tolerance 0.05 LSB RMS, 1 LSB worst case (a branch edge)
    assert np.sqrt(np.mean((fixed - flt) ** 2)) < 0.05
    assert np.max(np.abs(fixed - flt)) < 1.0
    # and the correction works: what is left is the reading's noise (1 LSB) around a constant
    assert np.std(fixed) < 1.2
    assert np.std(run["x"]) > 3 * np.std(fixed)


def test_refined_image_round_trip(refined_run):
    from pysig.tcomp._tcomp import TcompQ
    _, res = refined_run
    dev = ed.device_model(res)
    img = ed.refined_image(dev, sequence=7)
    got = ed.read_refined_image(img)
    assert got["lag"] == dev["lag"] and got["hyst"] == dev["hyst"]
    m = TcompQ.from_image(img)           # the firmware's loader reads the offset section
    assert m.n_axes == 1 and m.order == res.final.spec.base_order
    bad = bytearray(img)
    bad[20] ^= 0x40
    with pytest.raises(ModelFileError):
        ed.read_refined_image(bytes(bad))


def test_section_parsers_reject_malformed_payloads():
    with pytest.raises(ModelFileError, match="6"):
        ed.parse_lag(b"\x00" * 5)
    with pytest.raises(ModelFileError, match="out of range"):
        ed.parse_lag(ed.lag_payload(0))
    with pytest.raises(ModelFileError, match="out of range"):
        ed.parse_hyst(ed.hyst_payload(0, 5, 0))
    assert ed.parse_creep(ed.creep_payload(300, 7, -1234)) == (300, 7, -1234)
    assert ed.parse_gain(ed.gain_payload([65536, -100, 3])) == [65536, -100, 3]
    with pytest.raises(ModelFileError, match="gain"):
        ed.parse_gain(ed.gain_payload([1, 2])[:-1])
