"""Zero tracking in the default chain ("auto"): it acts only while the
samples lie within its band (sigma) of the set zero - the offset at the last
tare, set_offset or reset - so its total correction never exceeds the band.
In raw ADC codes, code 0 is no zero until a tare: an empty scale whose zero
code lies a few sigma from code 0 must read that code, not be tracked to 0
(tracking around the moving offset, with a noise estimate still high at
power-up, walked the offset across 3.3 sigma and flagged the wrong 0
stable).

C (step and batch paths, through Cython) against the spec near zero, with a
tare or set_offset between pieces (fixed: bit for bit; float: within 1e-9,
flags equal); then the bound itself, and that no empty-scale sample is
flagged stable more than 3 sigma from its zero code."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import pysig.weigh as C
from spec import chain as R

from test_chain import RTOL, split

SETTINGS = settings(max_examples=80, deadline=None)


@st.composite
def near_zero(draw):
    """An empty scale whose zero code lies -6..6 sigma from 0, drifting or
    not, small loads placed and removed, glitches; split points and what to
    do between pieces (nothing, a tare, a set_offset)."""
    n = draw(st.integers(20, 400))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    sigma = draw(st.sampled_from([1.0, 7.0, 70.0, 1e-3]))
    truth = np.full(n, draw(st.floats(-6.0, 6.0)) * sigma)
    truth += draw(st.sampled_from([0.0, 0.01, -0.03])) * sigma * np.arange(n)     # a slow zero drift
    for _ in range(draw(st.integers(0, 2))):                                        # small loads on and off
        a = int(rng.integers(0, n))
        truth[a:a + int(rng.integers(5, 120))] += draw(st.sampled_from([1.0, 2.5, 5.0, -3.0])) * sigma
    x = truth + rng.normal(0, sigma, n)
    for _ in range(draw(st.integers(0, 2))):
        x[int(rng.integers(0, n))] += draw(st.sampled_from([50.0, -400.0])) * sigma
    if sigma >= 1.0 and draw(st.booleans()):
        x = np.round(x)
    cuts = sorted(draw(st.lists(st.integers(0, n), max_size=4)))
    between = draw(st.lists(st.sampled_from(["none", "tare", "offset"]), min_size=len(cuts), max_size=len(cuts)))
    offsets = [float(np.round(draw(st.floats(-6.0, 6.0)) * sigma)) for _ in cuts]
    return x, cuts, between, offsets


def run_pieces(chain, x, cuts, between, offsets, flags):
    outs = []
    for i, part in enumerate(split(x, cuts)):
        outs.append(chain.process(part, flags=True) if flags else chain.process(part))
        if i < len(between):
            if between[i] == "tare":
                chain.tare()
            elif between[i] == "offset":
                chain.set_offset(offsets[i])
    return tuple(np.concatenate([o[k] for o in outs]) for k in range(len(outs[0]))), chain.offset


@SETTINGS
@given(near_zero())
def test_fixed_default_chain_near_zero_equals_the_spec_bit_for_bit(sig):
    r_out, r_offset = run_pieces(R.Chain(fixed=True), *sig, flags=True)
    for flags in (True, False):           # the step loop and the batch path
        c_out, c_offset = run_pieces(C.Chain(fixed=True), *sig, flags=flags)
        for a, b in zip(c_out, r_out):
            np.testing.assert_array_equal(a, b)
        assert c_offset == r_offset


@SETTINGS
@given(near_zero())
def test_float_default_chain_near_zero_equals_the_spec(sig):
    (r_out, r_stable, r_status), r_offset = run_pieces(R.Chain(), *sig, flags=True)
    tol = RTOL * (1 + np.max(np.abs(r_out), initial=0))
    for flags in (True, False):
        c, c_offset = run_pieces(C.Chain(), *sig, flags=flags)
        np.testing.assert_allclose(c[0], r_out, rtol=RTOL, atol=tol)
        np.testing.assert_array_equal(c[1], r_stable)
        if flags:
            np.testing.assert_array_equal(c[2], r_status)
        assert c_offset == pytest.approx(r_offset, rel=RTOL, abs=tol)


def walk(chain, x):
    """(offset, band = the largest sigma so far, out, stable) per sample."""
    rows = []
    band = 0.0
    for v in x:
        out, stable = chain.step(v)
        band = max(band, chain.sigma)
        rows.append((chain.offset, band, out, stable))
    return np.array(rows).T


@pytest.mark.parametrize("fixed", [False, True])
@pytest.mark.parametrize("zero_sigmas", [2.5, 3.3, 4.0, 6.0, -3.3])
def test_empty_scale_off_code_0_reads_its_zero_code(fixed, zero_sigmas):
    """The load cell's zero code lies 2.5-6 sigma from code 0 (as in the
    load-cell simulator at sigma = S/5): over 40 noise seeds the offset never
    leaves the band of 0 (the set zero at reset), and no stable output lies
    more than 3 sigma from the zero code."""
    sigma = 70.0
    worst = 0.0
    for seed in range(40):
        x = np.round(zero_sigmas * sigma + np.random.default_rng(seed).normal(0, sigma, 300))
        offset, band, out, stable = walk(C.Chain(fixed=fixed), x)
        assert np.all(np.abs(offset) <= band + 1 / 128), f"seed {seed}"
        off = np.abs(out - zero_sigmas * sigma)[stable.astype(bool)]
        worst = max(worst, float(np.max(off, initial=0.0)) / sigma)
    assert worst <= 3.0


@pytest.mark.parametrize("fixed", [False, True])
def test_tracking_follows_a_drift_within_the_band_of_the_tare_only(fixed):
    """After a tare on an empty scale at code 5000, a zero drift of 0.02
    sigma per sample is followed (the output stays near 0) while the samples
    lie within sigma of the tare's zero; beyond, tracking stops and the
    output shows the rest of the drift instead of hiding it."""
    sigma = 50.0
    rng = np.random.default_rng(7)
    c = C.Chain(fixed=fixed)
    c.process(np.round(5000 + rng.normal(0, sigma, 200)))
    c.tare()
    c.process(np.round(5000 + rng.normal(0, sigma, 50)))
    assert not c.tare_pending
    zero = c.offset
    drift = 0.02 * sigma * np.arange(1500)
    offset, band, out, stable = walk(c, np.round(5000 + drift + rng.normal(0, sigma, drift.size)))
    assert np.all(np.abs(offset - zero) <= band + 1 / 128)
    early = slice(20, 45)                       # drift 0.4-0.9 sigma: followed
    assert np.max(np.abs(out[early])) < 0.8 * sigma
    assert np.max(offset[early] - zero) > 0.2 * sigma
    late = slice(1300, 1500)                    # drift 26-30 sigma: tracking stopped within the band
    assert np.min(out[late] - (drift[late] - band[late])) > -1.5 * sigma
    assert np.min(out[late]) > 20 * sigma


@pytest.mark.parametrize("fixed", [False, True])
def test_set_offset_is_the_set_zero_of_the_tracking(fixed):
    """set_offset names the zero: tracking bounds itself around it, as
    around a tare's."""
    sigma = 50.0
    rng = np.random.default_rng(11)
    c = C.Chain(fixed=fixed)
    c.set_offset(-800.0)
    x = np.round(-750 + rng.normal(0, sigma, 600))          # 1 sigma above the named zero
    offset, band, out, stable = walk(c, x)
    assert np.all(np.abs(offset + 800.0) <= band + 1 / 128)
    assert stable[-100:].any()
