"""The weighing chain: the C core (through Cython) against the pure-Python
spec.  Fixed point: equal bit for bit.  Float: equal within 1e-9 relative
(same operations in the same order; in practice the results are identical).
State is carried across process() calls split at random points."""
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

import pysig.weigh as C
from pysig.errors import NonFiniteError, RangeError
from spec import chain as R

RTOL = 1e-9
SETTINGS = settings(max_examples=120, deadline=None)


# the input clamp's edges: on it, one code beyond, one code inside
CLAMP_EDGES = [float(v) for c in (R.CODE_MAX, -R.CODE_MAX) for v in (c, c + np.sign(c), c - np.sign(c))]


@st.composite
def signals(draw, allow_nonfinite=False, extreme=False):
    """A load-cell-like signal: levels with steps, Gaussian noise, impulses,
    optionally NaN/inf and values at the int32 rails; plus split points."""
    n = draw(st.integers(1, 300))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    # levels anywhere in the 24-bit range, some at the input clamp +-CODE_MAX
    # (2^24 - 1) so that noise and steps cross it
    level = float(draw(st.one_of(st.floats(-1e6, 1e6), st.floats(-R.CODE_MAX, R.CODE_MAX),
                                 st.sampled_from([R.CODE_MAX, -R.CODE_MAX, R.CODE_MAX - 40, 40 - R.CODE_MAX]))))
    noise = draw(st.sampled_from([0.0, 1.0, 70.0, 3000.0]))
    x = np.full(n, level) + rng.normal(0, noise, n) if noise else np.full(n, level)
    for _ in range(draw(st.integers(0, 3))):                     # load steps
        i = int(rng.integers(0, n))
        x[i:] += draw(st.sampled_from([50.0, 500.0, 5000.0, -20000.0, 1e6]))
    for _ in range(draw(st.integers(0, 4))):                     # impulses
        x[int(rng.integers(0, n))] = draw(st.sampled_from([-8388608.0, 8388607.0, -4.2e6, level + 1e5,
                                                           *CLAMP_EDGES]))
    if extreme:
        for _ in range(draw(st.integers(0, 3))):
            x[int(rng.integers(0, n))] = draw(st.sampled_from([2.0**31 - 1, -(2.0**31), 1e12, -3e7]))
    if allow_nonfinite:
        for _ in range(draw(st.integers(0, 4))):
            x[int(rng.integers(0, n))] = draw(st.sampled_from([math.nan, math.inf, -math.inf]))
    x = np.round(x) if draw(st.booleans()) else x
    cuts = sorted(draw(st.lists(st.integers(0, n), max_size=4)))
    return x, cuts


@st.composite
def chain_kwargs(draw):
    preset = draw(st.sampled_from(["paper", "recommended"]))
    kw = dict(preset=preset, units_per_kg=draw(st.sampled_from([1.0, 2204.6, 64500.0])))
    if draw(st.booleans()):
        kw.update(window=draw(st.integers(3, 32)), lockout_n=draw(st.integers(0, 6)),
                  motion_band=draw(st.sampled_from([0.0, 0.01, 0.03, 0.5])),
                  motion_count=draw(st.integers(1, 3)),
                  stable_count=draw(st.integers(1, 6)),
                  stable_step=draw(st.sampled_from([0.0, 0.001, 0.01, 1.0])),
                  zero_band=draw(st.sampled_from([0.0, 0.05, 10.0])),
                  zero_rate=draw(st.sampled_from([0.0, 0.0005, 0.1])),
                  A0=draw(st.sampled_from([0.01, 1.0, 2.0, 100.0])),
                  Q=draw(st.sampled_from([0.0, 1e-8, 1e-7, 1e-6])),
                  seed_first=draw(st.booleans()))
    return kw


def both(name, **kw):
    """C and reference objects; a parameter set that has no fixed-point form
    (for example A0 below one code) must be refused by both alike."""
    try:
        r = getattr(R, name)(**kw)
    except RangeError as exc:
        with pytest.raises(RangeError, match=str(exc).split(":")[0].split("=")[0]):
            getattr(C, name)(**kw)
        assume(False)
    return getattr(C, name)(**kw), r


def split(x, cuts):
    edges = [0] + list(cuts) + [len(x)]
    return [x[a:b] for a, b in zip(edges[:-1], edges[1:])]


def run_split(obj, x, cuts, **kw):
    parts = [obj.process(p, **kw) for p in split(x, cuts)]
    if isinstance(parts[0], tuple):
        return tuple(np.concatenate([p[i] for p in parts]) for i in range(len(parts[0])))
    return np.concatenate(parts)


# ---- the chain ----------------------------------------------------------------

@SETTINGS
@given(signals(extreme=True), chain_kwargs())
def test_fixed_chain_equals_reference_bit_for_bit(sig, kw):
    x, cuts = sig
    c, r = both("Chain", fixed=True, **kw)
    c_out = run_split(c, x, cuts, flags=True)
    r_out = r.process(x, flags=True)
    for a, b in zip(c_out, r_out):
        np.testing.assert_array_equal(a, b)


@SETTINGS
@given(signals(allow_nonfinite=True), chain_kwargs())
def test_float_chain_equals_reference_within_tolerance(sig, kw):
    x, cuts = sig
    c_out, c_stable, c_status = run_split(C.Chain(**kw), x, cuts, flags=True)
    r_out, r_stable, r_status = R.Chain(**kw).process(x, flags=True)
    np.testing.assert_allclose(c_out, r_out, rtol=RTOL, atol=RTOL * (1 + np.nanmax(np.abs(r_out), initial=0)))
    np.testing.assert_array_equal(c_stable, r_stable)
    np.testing.assert_array_equal(c_status, r_status)


@SETTINGS
@given(signals(allow_nonfinite=True), chain_kwargs(), st.booleans())
def test_step_equals_process(sig, kw, fixed):
    x, _ = sig
    if fixed:
        x = np.nan_to_num(x, nan=0.0, posinf=1e9, neginf=-1e9)
    a, _ = both("Chain", fixed=fixed, **kw)
    stepped = [a.step(v) for v in x]
    out, stable = C.Chain(fixed=fixed, **kw).process(x)
    np.testing.assert_array_equal(np.array([s[0] for s in stepped]), out)
    np.testing.assert_array_equal(np.array([s[1] for s in stepped]), stable)


def _state(c):
    return (c.x, c.K, c.P, c.innovation, c.Dc, c.window_count, c.offset, c.stable, c.tare_pending)


@SETTINGS
@given(signals(allow_nonfinite=True, extreme=True), chain_kwargs(), st.booleans(), st.booleans())
def test_batch_process_equals_the_step_loop_split(sig, kw, fixed, tare):
    """process() without flags runs the C batch entry point (sig_chain_process_*,
    a fast path for the steady state); with flags it loops over the step
    function.  Split at random points, with a tare in between, the two give
    the same outputs, flags, final status and state, bit for bit."""
    x, cuts = sig
    if fixed:
        x = np.nan_to_num(x, nan=0.0, posinf=1e9, neginf=-1e9)
    stepped, _ = both("Chain", fixed=fixed, **kw)
    batch = C.Chain(fixed=fixed, **kw)
    outs = []
    for part in split(x, cuts):
        o1, s1, st1 = stepped.process(part, flags=True)
        o2, s2 = batch.process(part)
        outs.append((o1, s1, o2, s2))
        if len(part):
            assert batch.status == st1[-1]
        assert _state(batch) == pytest.approx(_state(stepped), rel=0, abs=0, nan_ok=True)
        if tare:
            assert batch.tare() == stepped.tare()
    for o1, s1, o2, s2 in outs:
        np.testing.assert_array_equal(o1, o2)
        np.testing.assert_array_equal(s1, s2)


@pytest.mark.parametrize("huge", [1e299, 1e301, 1e307, 1.7e308])
def test_batch_process_at_the_overflow_guards(huge):
    """Samples around the batch fast path's magnitude bound (1e300) and the
    largest doubles take the step path where the overflow guards act: same
    results as the step loop, finite after the first finite sample."""
    rng = np.random.default_rng(3)
    x = np.concatenate([rng.normal(0, 1, 40), [huge, -huge, huge, huge, huge], rng.normal(5, 1, 60),
                        np.full(30, -huge), rng.normal(0, 1, 40)])
    for kw in (dict(preset="paper"), dict(preset="recommended", units_per_kg=1.0, lockout_n=2, A0=1e305)):
        a, b = C.Chain(**kw), C.Chain(**kw)
        o1, s1, _ = a.process(x, flags=True)
        o2, s2 = b.process(x)
        np.testing.assert_array_equal(o1, o2)
        np.testing.assert_array_equal(s1, s2)
        assert np.isfinite(o2).all()


@SETTINGS
@given(signals(allow_nonfinite=True), chain_kwargs())
def test_nonfinite_never_enters_the_state(sig, kw):
    x, _ = sig
    out, stable, status = C.Chain(**kw).process(x, flags=True)
    finite = np.isfinite(x)
    if not finite.any():
        assert np.isnan(out).all() and not stable.any() and (status == R.ERR_NONFINITE).all()
        return
    first = int(np.argmax(finite))
    assert np.isnan(out[:first]).all() and (status[:first] == R.ERR_NONFINITE).all()
    assert np.isfinite(out[first:]).all()
    assert ((status[first:][~finite[first:]] & R.WARN_REJECTED) != 0).all()
    # without the lock-out counter (which a non-finite sample leaves alone),
    # a non-finite sample acts exactly like a sample equal to the reference Dc
    kw = dict(kw, lockout_n=0)
    out = C.Chain(**kw).process(x)[0]
    ref = C.Chain(**kw)
    ref.process(x[:first])
    y = []
    for v in x[first:]:
        if not math.isfinite(v):
            v = ref.Dc
        y.append(ref.step(v)[0])
    np.testing.assert_array_equal(np.array(y), out[first:])


def test_fixed_rejects_nonfinite_with_index():
    with pytest.raises(NonFiniteError, match="sample 2"):
        C.Chain(fixed=True).process([1.0, 2.0, math.nan])
    with pytest.raises(NonFiniteError):
        R.Chain(fixed=True).process([1.0, 2.0, math.inf])


def test_fixed_clamps_codes_beyond_25_bits():
    out, _, status = C.Chain(fixed=True, preset="paper", units_per_kg=1000.0, seed_first=True).process(
        [5e7, 5e7, -5e7], flags=True)
    assert (status & R.WARN_CLAMPED).all()
    assert out[0] == R.CODE_MAX


# ---- stages alone -----------------------------------------------------------------

STAGES = [
    ("LimitFilter", dict(a0=1000.0, lockout_n=3)),
    ("LimitFilter", dict(a0=1.5, lockout_n=0)),
    ("AntiPulse", dict(window=12)),
    ("AntiPulse", dict(window=3)),
    ("AntiPulse", dict(window=32)),
    ("Kalman1", dict()),
    ("Kalman1", dict(Q=1e-3, R=4900.0, x0=0.0, P0=1e6, seed_first=True)),
    ("Kalman1", dict(Q=1.0, R=1.0, x0=5.0, P0=0.0)),
    ("StabilityDetector", dict(step=10.0, count=3)),
]


@pytest.mark.parametrize("name,kw", STAGES, ids=[f"{n}-{i}" for i, (n, _) in enumerate(STAGES)])
@settings(max_examples=60, deadline=None)
@given(sig=signals(extreme=True))
def test_stage_fixed_bit_exact_and_float_close(name, kw, sig):
    x, cuts = sig
    c_fixed = run_split(getattr(C, name)(fixed=True, **kw), x, cuts)
    r_fixed = getattr(R, name)(fixed=True, **kw).process(x)
    np.testing.assert_array_equal(c_fixed, r_fixed)
    c_float = run_split(getattr(C, name)(**kw), x, cuts)
    r_float = getattr(R, name)(**kw).process(x)
    if c_float.dtype == bool:
        np.testing.assert_array_equal(c_float, r_float)
    else:
        np.testing.assert_allclose(c_float, r_float, rtol=RTOL, atol=RTOL * (1 + np.abs(r_float).max()))


@settings(max_examples=150, deadline=None)
@given(sig=signals(extreme=True),
       step=st.one_of(st.sampled_from([0.0, 1 / 128, 0.5, 10.0]), st.floats(0.0, 1e7)),
       count=st.one_of(st.sampled_from([1, 2, 255]), st.integers(1, 255)))
def test_stability_detector_over_parameters(sig, step, count):
    """The stability stage over its parameter range (step from zero to 1e7,
    count 1..255: the run counter saturates at 255): C == spec, fixed bit for
    bit and float, state carried across split calls."""
    x, cuts = sig
    for fixed in (True, False):
        c = run_split(C.StabilityDetector(step=step, count=count, fixed=fixed), x, cuts)
        np.testing.assert_array_equal(c, R.StabilityDetector(step=step, count=count, fixed=fixed).process(x))


def test_antipulse_fill_rule_and_exact_rounded_mean():
    a = C.AntiPulse(window=5, fixed=True)
    # 1 -> itself, 2 -> mean (half up), 3.. -> trimmed mean of what is held
    assert list(a.process([10, 11, 100, -50, 7])) == [10, 11, 11, 11, 9]
    f = C.AntiPulse(window=5)
    np.testing.assert_allclose(f.process([10, 11, 100, -50, 7]), [10, 10.5, 11, 10.5, 28 / 3])


@settings(max_examples=300, deadline=None)
@given(st.integers(-(2**29), 2**29), st.integers(1, 30))
def test_reciprocal_division_is_exact(s, d):
    """The fixed anti-pulse mean never divides: a window of d+2 equal-spread
    values whose trimmed sum is s gives round-half-up(s / d) exactly."""
    vals = [s // d] * d
    vals[0] += s - sum(vals)
    if abs(vals[0]) > R.CODE_MAX or abs(vals[-1]) > R.CODE_MAX:
        return
    lo, hi = min(vals), max(vals)
    a = C.AntiPulse(window=d + 2, fixed=True)
    out = a.process([lo] + vals + [hi])
    assert out[-1] == (s + d // 2) // d


def test_kalman_paper_gain_behaves_like_the_textbook():
    k = C.Kalman1()                                  # paper: Q 1e-7, R 0.05, P0 10
    kq = C.Kalman1(fixed=True)
    k.process(np.full(5000, 30.0))
    kq.process(np.full(5000, 30.0))
    assert k.K == pytest.approx(math.sqrt(1e-7 / 0.05), rel=0.05)
    assert kq.K == pytest.approx(k.K, rel=1e-3)     # division-free Q30 gain tracks the float one
    # the fixed state stops within its dead band: |K * e| < half an LSB of Q24.7
    assert kq.x == pytest.approx(30.0, abs=0.5 / (128 * kq.K) + 1 / 128)


# ---- parameters --------------------------------------------------------------------

@pytest.mark.parametrize("kw,name", [
    (dict(window=33), "window"), (dict(window=2), "window"), (dict(R=-1.0), "R"),
    (dict(R=0.0), "R"), (dict(Q=-1e-9), "Q"), (dict(A0=0.0), "A0"), (dict(A0=math.nan), "A0"),
    (dict(stable_count=0), "stable_count"), (dict(lockout_n=256), "lockout_n"),
    (dict(motion_band=-1.0), "motion_band"), (dict(units_per_kg=0.0), "units_per_kg"),
    (dict(P0=-1.0), "P0"), (dict(zero_rate=math.inf), "zero_rate"), (dict(bogus=1), "bogus"),
])
@pytest.mark.parametrize("fixed", [False, True])
def test_bad_parameters_raise_named_errors(kw, name, fixed):
    with pytest.raises(RangeError, match=name):
        C.Chain(fixed=fixed, **kw)
    with pytest.raises(RangeError, match=name):
        R.Chain(fixed=fixed, **kw)


def test_fixed_only_limits_are_named():
    with pytest.raises(RangeError, match="Q"):
        C.Chain("recommended", fixed=True, Q=1.0, R=0.5)           # Q/R > 1 has no Q30 form
    with pytest.raises(RangeError, match="window"):
        C.AntiPulse(window=40)
    with pytest.raises(RangeError, match="R"):
        C.Kalman1(R=-0.05)
    with pytest.raises(RangeError, match="preset"):
        C.Chain(preset="fast")


@pytest.mark.parametrize("preset", ["recommended", "adaptive"])
@pytest.mark.parametrize("units", [None, 1.0, 64414.0])
@pytest.mark.parametrize("r_kg", [None, 1e-4, 1.43])
def test_presets_derive_thresholds_from_the_noise(preset, units, r_kg):
    """A0 / motion_band "auto": A0_sigmas * sqrt(R) and motion_sigmas *
    sqrt(R / (window - 2)), R in signal units; a number given wins."""
    p = C.chain_params(preset, units_per_kg=units, R=r_kg)
    base = C.PRESETS[preset]
    s = units if units is not None else base["units_per_kg"]
    r = (r_kg if r_kg is not None else base["R"]) * s * s
    assert p["R"] == pytest.approx(r, rel=1e-12)
    assert p["motion_band"] == pytest.approx(4.0 * math.sqrt(r / 10), rel=1e-12)
    if base["A0"] == "auto":
        assert p["A0"] == pytest.approx(6.0 * math.sqrt(r), rel=1e-12)
    else:
        assert p["A0"] == pytest.approx(base["A0"] * s, rel=1e-12)
    q = C.chain_params(preset, units_per_kg=units, R=r_kg, window=7, motion_sigmas=3.0, A0_sigmas=8.0)
    assert q["motion_band"] == pytest.approx(3.0 * math.sqrt(r / 5), rel=1e-12)
    given = C.chain_params(preset, units_per_kg=units, R=r_kg, motion_band=0.5, A0=3.0)
    assert (given["motion_band"], given["A0"]) == pytest.approx((0.5 * s, 3.0 * s), rel=1e-12)
    # the C chain runs the derived numbers, in both forms
    for fixed in (False, True):
        try:
            C.Chain(preset, fixed=fixed, units_per_kg=units, R=r_kg)
        except RangeError:
            assert fixed                      # e.g. Q/R beyond the fixed form's range
    assert C.chain_params("paper", motion_band="auto")["motion_band"] == pytest.approx(4 * math.sqrt(0.05 / 10))


def test_auto_thresholds_bad_values_are_named():
    with pytest.raises(RangeError, match="motion_band"):
        C.chain_params("recommended", motion_band="fast")
    with pytest.raises(RangeError, match="A0_sigmas"):
        C.chain_params("recommended", A0_sigmas=0.0)
    with pytest.raises(RangeError, match="motion_sigmas"):
        C.chain_params("recommended", motion_sigmas=-1.0)
    with pytest.raises(RangeError, match="A0"):
        C.chain_params("recommended", units_per_kg=1.0, R=1e-300, A0_sigmas=1e-200)    # underflows to 0


def test_presets_paper_values():
    p = C.chain_params("paper")
    assert (p["Q"], p["R"], p["x0"], p["P0"], p["window"], p["stable_count"]) == (1e-7, 0.05, 1.0, 10.0, 12, 1)
    assert p["lockout_n"] == 0 and p["motion_band"] == 0 and p["zero_band"] == 0
    s = C.chain_params("paper", units_per_kg=1000.0)
    assert s["Q"] == pytest.approx(0.1) and s["R"] == pytest.approx(5e4) and s["A0"] == 2000.0
    assert C.Chain().params == C.chain_params("auto")
