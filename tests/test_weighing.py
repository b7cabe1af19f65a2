"""Scale calibration (shared least-squares code), plateau detection and the
settle/glitch measurements used by the benches."""
import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from pysig.weigh import _scale
from pysig.weigh import _calibration as weighing
from pysig import lsq
from pysig.errors import InsufficientDataError, RangeError
from pysig.sim._loadcell import LoadCellParams, simulate

MASSES = np.arange(10.0, 50.1, 5.0)


def mean_readings(p, masses, n=5, seed=0):
    """The weighing paper's calibration: the mean of n readings at each standard mass."""
    out = []
    for i, m in enumerate(masses):
        run = simulate(p, seed=seed + i, load_steps=((0.0, float(m)),), duration_s=n / p.rate_hz)
        out.append(np.mean(run["counts"]))
    return np.array(out)


def test_calibration_uses_the_shared_solver():
    assert weighing.fit_poly is lsq.fit_poly


def test_noise_free_calibration_recovers_the_cell():
    p = LoadCellParams()
    cal = weighing.calibrate(mean_readings(p, MASSES), MASSES)
    assert cal.counts_per_unit == pytest.approx(p.counts_per_kg, rel=1e-6)
    assert cal.offset_counts == pytest.approx(p.zero_counts, abs=1.0)
    assert cal.linearity_err_pct_fs < 1e-4
    sens_mv_per_kg = cal.counts_per_unit * p.lsb_v * 1e3
    assert sens_mv_per_kg == pytest.approx(0.15, rel=1e-6)


def test_linearity_error_reports_the_bow():
    p = LoadCellParams(nonlinearity_frac_fs=0.001)
    cal = weighing.calibrate(mean_readings(p, MASSES), MASSES)
    # independent check: residual of numpy's polyfit line through the same bow
    x = MASSES / p.capacity_kg
    bow_kg = 4 * 0.001 * p.capacity_kg * x * (1 - x)
    resid = bow_kg - np.polyval(np.polyfit(MASSES, bow_kg, 1), MASSES)
    expect = 100 * np.max(np.abs(resid)) / MASSES.max()
    assert cal.linearity_err_pct_fs == pytest.approx(expect, rel=0.02)
    assert cal.linearity_err_pct_fs > 0.01


def test_noisy_calibration_and_application_paths_agree():
    p = LoadCellParams(noise_uv_rms=2.0)
    counts = mean_readings(p, MASSES, seed=5)
    cal = weighing.calibrate(counts, MASSES)
    assert cal.counts_per_unit == pytest.approx(p.counts_per_kg, rel=1e-3)
    codes = np.rint(counts).astype(np.int32)
    f = cal.to_mass(codes)
    np.testing.assert_allclose(f, MASSES, atol=0.035)   # 5 sigma of a 5-reading mean
    np.testing.assert_array_equal(_scale.ScaleF(cal.offset_counts, cal.gain).apply(codes.astype(float)), f)
    off, mant, shift = cal.fixed()
    q, sat = _scale.ScaleQ16(off, mant, shift).apply(codes)
    assert not sat.any()
    # Q16 image: half a code of offset (about 8 mg here) plus one Q16 step
    np.testing.assert_allclose(q / 65536.0, f, atol=0.5 * cal.gain + 2**-16 + 1e-9)


@pytest.mark.parametrize("counts, masses, exc", [
    ([1.0, 2.0], [10.0], RangeError),
    ([1.0, 2.0], [10.0, 10.0], InsufficientDataError),
    ([5.0, 5.0], [10.0, 20.0], InsufficientDataError),
])
def test_calibration_bad_input(counts, masses, exc):
    with pytest.raises(exc):
        weighing.calibrate(counts, masses)


def staircase(seed=0, glitches=()):
    levels = [0, 10, 20, 30, 20, 0]
    steps = tuple((12.0 * i, float(m)) for i, m in enumerate(levels))
    p = LoadCellParams(load_steps=steps, duration_s=72.0, noise_uv_rms=8.0, ringing_frac=0.1)
    run = simulate(p, seed=seed)
    counts = run["counts"].astype(float)
    for i in glitches:
        counts[i] = -(2**23)
    return p, run, counts, levels


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_plateaus_found_and_named_without_indices(seed):
    p, run, counts, levels = staircase(seed, glitches=(30, 250, 500))
    found = weighing.assign_nominal(weighing.find_plateaus(counts, p.rate_hz), 10.0)
    assert [pl.nominal for pl in found] == levels
    for pl in found:
        # every plateau lies inside its true hold and covers most of it
        held = run["ref_kg"][pl.start:pl.stop]
        assert np.all(held == pl.nominal)
        assert pl.stop - pl.start >= 0.7 * 120
        assert pl.level == pytest.approx(p.zero_counts + p.counts_per_kg * pl.nominal,
                                         abs=0.05 * p.counts_per_kg)


def test_plateau_needs_data():
    with pytest.raises(InsufficientDataError):
        weighing.find_plateaus([1.0, 2.0], 10.0)
    with pytest.raises(InsufficientDataError):
        weighing.assign_nominal([], 10.0)


def test_glitches_found():
    _, _, counts, _ = staircase(0, glitches=(30, 250, 500))
    np.testing.assert_array_equal(weighing.glitch_indices(counts), [30, 250, 500])


def test_settle_index():
    out = np.array([0.0, 5.0, 9.0, 10.2, 9.96, 10.01, 10.0, 10.02, 9.99])
    assert weighing.settle_index(out, 10.0, 0.05, 1, out.size) == 4
    stable = np.array([0, 0, 0, 0, 0, 0, 1, 1, 1], dtype=bool)
    assert weighing.settle_index(out, 10.0, 0.05, 1, out.size, stable) == 6
    assert weighing.settle_index(out, 10.0, 0.05, 1, 4) is None       # still outside at the end
    assert weighing.settle_index(out, 0.0, 0.05, 1, out.size) is None
    assert weighing.settle_index(out, 10.0, 0.05, 5, 5) is None       # empty interval


def _plateaus(levels):
    return [weighing.Plateau(10 * i, 10 * i + 5, float(v)) for i, v in enumerate(levels)]


def test_nominal_levels_see_a_skipped_step_and_refuse_unequal_steps():
    # 0, 10, 30, 10, 0 lb at 1000 counts/lb above a 5800-count zero, a few counts of noise
    got = weighing.assign_nominal(_plateaus([5803, 15790, 35810, 15802, 5797]), 10.0)
    assert [p.nominal for p in got] == [0, 10, 30, 10, 0]
    with pytest.raises(RangeError, match="whole number"):
        weighing.assign_nominal(_plateaus([0, 1000, 2500]), 10.0)
    assert [p.nominal for p in weighing.assign_nominal(_plateaus([7.0, 7.5]), 1.0, min_gap=1.0)] == [0, 0]


@settings(max_examples=25, deadline=None)
@given(moves=st.lists(st.sampled_from([-2, -1, 1, 2]), min_size=4, max_size=7),
       holds=st.lists(st.floats(6.0, 15.0), min_size=8, max_size=8),
       noise=st.floats(0.5, 10.0), swing=st.floats(0.0, 0.05),
       glitch_at=st.lists(st.floats(0.0, 1.0), max_size=3), seed=st.integers(0, 2**16))
def test_plateau_finder_on_random_staircases(moves, holds, noise, swing, glitch_at, seed):
    levels = [0]
    for m in moves:
        levels.append(min(5, max(0, levels[-1] + m)))
    levels = [v for i, v in enumerate(levels) if i == 0 or v != levels[i - 1]]
    assume(len(levels) >= 3 and any(abs(a - b) == 1 for a, b in zip(levels, levels[1:])))
    times = np.concatenate(([0.0], np.cumsum(holds[:len(levels) - 1])))
    p = LoadCellParams(load_steps=tuple((float(t), 10.0 * v) for t, v in zip(times, levels)),
                       duration_s=float(times[-1] + holds[len(levels) - 1]), noise_uv_rms=noise,
                       ringing_frac=swing)
    run = simulate(p, seed=seed)
    counts = run["counts"].astype(float)
    glitches = sorted({int(g * (counts.size - 1)) for g in glitch_at})
    counts[glitches] = -(2**23)
    found = weighing.assign_nominal(weighing.find_plateaus(counts, p.rate_hz), 10.0)
    assert [pl.nominal / 10.0 for pl in found] == levels
    for pl in found:
        assert np.all(run["ref_kg"][pl.start:pl.stop] == pl.nominal)
