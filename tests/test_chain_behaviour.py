"""What the chain does beyond matching its spec: the lock-out fix, motion-
aware settling on a synthetic step, tare and zero tracking.  Each behaviour
is checked in both numeric forms (the fixed form on counts)."""
import numpy as np
import pytest

from pysig.weigh import CHAIN_MOTION, CHAIN_TARED, LIMIT_RESEEDED, Chain

FS = 10.0                         # samples per second
COUNTS_PER_KG = 10000.0           # for the fixed form: signal in codes


def step_signal(before, after, sigma, n_before=200, n_after=400, seed=1, scale=1.0):
    rng = np.random.default_rng(seed)
    x = np.r_[np.full(n_before, before), np.full(n_after, after)] + rng.normal(0, sigma, n_before + n_after)
    return np.round(x * scale) if scale != 1.0 else x


def settle_time(out, stable, target, tol, start):
    """Seconds from `start` until the output is stable and within tol of the
    target for good (None if never)."""
    ok = stable[start:] & (np.abs(out[start:] - target) <= tol)
    bad = np.flatnonzero(~ok)
    if bad.size == 0:
        return 0.0
    if bad[-1] == ok.size - 1:
        return None
    return (bad[-1] + 1) / FS


def run(x, fixed, **kw):
    scale = COUNTS_PER_KG if fixed else 1.0
    out, stable, status = Chain(fixed=fixed, units_per_kg=scale, **kw).process(x * scale, flags=True)
    return out / scale, stable, status


@pytest.mark.parametrize("fixed", [False, True])
def test_paper_chain_locks_out_and_the_fix_follows(fixed):
    x = step_signal(0.0, 10.0, 0.05)                    # a 10 kg step, A0 = 2 kg
    out, _, _ = run(x, fixed, preset="paper")
    assert np.all(out[250:] < 2.0), "the weighing paper's chain should refuse the new level"
    scale = COUNTS_PER_KG if fixed else 1.0
    c = Chain(preset="paper", lockout_n=3, fixed=fixed, units_per_kg=scale)
    out, _, status = c.process(x * scale, flags=True)
    out /= scale
    assert (status[200:204] & LIMIT_RESEEDED).any()
    assert c.Dc / scale == pytest.approx(10.0, abs=0.05)          # the limit stage follows
    # ... but the weighing paper's Kalman gain (~1/n, then 0.0014) only creeps after it
    assert np.all(np.diff(out[260:]) > 0) and out[-1] < 9.0
    out, _, _ = run(x, fixed, preset="adaptive")                   # + motion mode
    assert abs(np.mean(out[300:]) - 10.0) < 0.01


@pytest.mark.parametrize("fixed", [False, True])
@pytest.mark.parametrize("step_kg", [1.5, 10.0])       # below and above A0 = 2 kg
def test_motion_mode_settles_within_2_s(fixed, step_kg):
    x = step_signal(20.0, 20.0 + step_kg, 0.01)
    target, tol = 20.0 + step_kg, 0.001 * (20.0 + step_kg)         # 0.1 % of the new load
    out, stable, status = run(x, fixed, preset="adaptive", motion_band=0.03)
    t_adaptive = settle_time(out, stable, target, tol, 200)
    assert t_adaptive is not None and t_adaptive <= 2.0
    assert (status[200:] & (CHAIN_MOTION | LIMIT_RESEEDED)).any()
    out_p, stable_p, _ = run(x, fixed, preset="paper", lockout_n=3)          # no motion mode
    t_paper = settle_time(out_p, stable_p, target, tol, 200)
    assert t_paper is None or t_paper > 5 * t_adaptive


@pytest.mark.parametrize("fixed", [False, True])
def test_motion_mode_steady_state_error_no_worse_than_paper(fixed):
    errs = {}
    for preset in ("paper", "adaptive"):
        e = []
        for seed in range(8):
            x = step_signal(30.0, 30.0, 0.22, n_before=100, n_after=200, seed=seed)
            out, _, status = run(x, fixed, preset=preset)
            e.append(np.max(np.abs(out[-20:] - 30.0)))          # the last 20 readings
        errs[preset] = np.median(e)
    assert errs["adaptive"] <= 1.05 * errs["paper"] + 1e-3


@pytest.mark.parametrize("fixed", [False, True])
def test_tare_now_when_stable_and_pending_when_not(fixed):
    scale = COUNTS_PER_KG if fixed else 1.0
    c = Chain(preset="paper", fixed=fixed, units_per_kg=scale, stable_step=0.01, stable_count=3,
              seed_first=True)
    rng = np.random.default_rng(3)
    c.process((5.0 + rng.normal(0, 0.001, 100)) * scale)
    assert c.stable
    assert c.tare() is True
    assert c.offset == pytest.approx(5.0 * scale, rel=1e-3)
    out, _ = c.process((5.0 + rng.normal(0, 0.001, 20)) * scale)
    assert np.all(np.abs(out / scale) < 0.01)
    # while the output moves, tare waits for the next stable sample
    c2 = Chain(preset="paper", fixed=fixed, units_per_kg=scale, stable_step=0.01, stable_count=3,
               seed_first=True)
    c2.step(7.0 * scale)
    assert c2.tare() is False and c2.tare_pending
    out, stable, status = c2.process(np.full(50, 7.0 * scale), flags=True)
    first = int(np.argmax(stable))
    assert status[first] & CHAIN_TARED and not c2.tare_pending
    assert abs(out[-1]) <= 0.01 * scale


@pytest.mark.parametrize("fixed", [False, True])
def test_zero_tracking_only_when_stable_near_zero_at_bounded_rate(fixed):
    scale = COUNTS_PER_KG if fixed else 1.0
    kw = dict(preset="paper", fixed=fixed, units_per_kg=scale, seed_first=True,
              stable_step=0.01, stable_count=2, zero_band=0.05, zero_rate=0.0005)
    # a slow drift of 0.2 g per sample near zero is followed: output stays near 0
    drift = np.arange(400) * 0.0002
    c = Chain(**kw)
    out, stable = c.process(drift * scale)
    assert stable[50:].all()
    assert np.max(np.abs(out[100:] / scale)) < 0.01
    assert c.offset == pytest.approx(c.x, abs=0.01 * scale)
    # the offset never moves faster than zero_rate per sample
    c = Chain(**kw)
    offsets = []
    for v in np.r_[np.zeros(20), np.full(100, 0.04)]:
        c.step(v * scale)
        offsets.append(c.offset / scale)
    assert np.max(np.abs(np.diff(offsets))) <= 0.0005 + 1 / 128 / scale
    # a load outside the band is never tracked away
    c = Chain(**kw)
    out, _ = c.process(np.full(300, 2.0 * scale))
    assert c.offset == 0 and out[-1] / scale == pytest.approx(2.0, abs=1e-3)
    # not stable (every step moves more than stable_step): no tracking
    c = Chain(**dict(kw, stable_step=0.0, Q=0.01))
    rng = np.random.default_rng(5)
    c.process((0.02 + rng.normal(0, 0.01, 300)) * scale)
    assert c.offset == 0
