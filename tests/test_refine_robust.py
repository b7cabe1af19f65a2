"""refine on real-world residuals: impulses do not hide an effect, an effect
is claimed only for the systematic error it removes from a reported reading
(the residual averaged over 10 s), a time constant under 3 sample periods is
noise smoothing and not claimed, and an offset shape a low order cannot
follow is named.  Built on the project's own generators (load-cell and
chamber simulators) and the real MPU-6000 curve."""
import numpy as np
import pytest

from pysig.io import read_csv
from pysig.refine import _effect_models as fx
from pysig.refine import _robust as robust
from pysig.refine._loop import refine
from pysig.sim._chamber import ChamberParams, simulate as simulate_chamber
from lab.studies.refine_cases import loadcell_creep_run

from conftest import require_shared_data

CREEP_TAU_S = 240.0


@pytest.fixture(scope="module")
def creep_under_impulses():
    """0 -> 40 -> 5 -> 45 kg held 13 min each at 10 samples/s, creep 0.05 % of
    each step (tau 240 s), 20 counts of noise, 0.25 % of samples hit by
    2 000-20 000-count impulses."""
    run = loadcell_creep_run(seed=21, loads=(0.0, 40.0, 5.0, 45.0), hold_s=780.0,
                             creep_frac=5e-4, creep_tau_s=CREEP_TAU_S, noise_counts=20.0,
                             impulse_frac=0.0025)
    return run, refine(fx.FitData(y=run["counts"], t=run["t"], r=run["ref_kg"]))


def test_creep_is_found_under_impulses(creep_under_impulses):
    run, res = creep_under_impulses
    assert [s.effect for s in res.steps] == ["creep"], res.report()["not_added"]
    tau = res.steps[0].params["tau_s"]
    assert 0.5 * CREEP_TAU_S <= tau <= 1.5 * CREEP_TAU_S, tau


def test_impulses_are_counted_and_left_out(creep_under_impulses):
    run, res = creep_under_impulses
    found = res.impulses
    hit = run["impulse"]
    assert found[hit].mean() >= 0.98, (int(found[hit].sum()), int(hit.sum()))
    assert int((found & ~hit).sum()) <= 0.001 * hit.size
    rep = res.report()
    assert rep["impulses"]["count"] == int(found.sum())
    # plain RMS (impulses in) is ruled by them; robust RMS is the noise and the creep
    assert rep["before"]["plain_rms"] > 10 * rep["before"]["rms"]
    assert rep["after"]["rms"] < rep["before"]["rms"]


def test_creep_cuts_the_reported_reading_error_3x(creep_under_impulses):
    _, res = creep_under_impulses
    rep = res.report()
    assert rep["before"]["averaged_rms"] >= 3.0 * rep["after"]["averaged_rms"], (rep["before"], rep["after"])
    assert rep["samples_per_report"] == 100          # 10 s at 10 samples/s


def _noisy_temperature_chamber(seed, **kw):
    """Chamber simulator, offset polynomial and noise only, the temperature
    read with 0.15 °C noise every 2 s (sizes varied with the seed)."""
    p = dict(seed=seed, sample_rate_hz=0.5, temp_noise_c=0.15, temp_resolution_c=0.01,
             noise_lsb=0.8 + 0.1 * (seed % 5), profile="ramp", step_temps_c=(-5.0, 40.0 + 5 * (seed % 3)),
             ramp_c_per_min=2.0, dwell_s=300.0)
    p.update(kw)
    run = simulate_chamber(ChamberParams(**p))
    return fx.FitData(y=run["x"], t=run["t"], T=run["temp"], r=run["ref_x"])


def test_clean_runs_with_noisy_temperature_get_nothing_over_20_seeds():
    claimed, short_lags = {}, 0
    for seed in range(20):
        res = refine(_noisy_temperature_chamber(200 + seed))
        if res.steps:
            claimed[seed] = [(s.effect, s.params) for s in res.steps]
        for r in res.not_claimed:
            if r["effect"] == "thermal_lag":
                assert "under 3 sample periods" in r["reason"]
                short_lags += 1
    assert not claimed, claimed
    assert short_lags >= 1        # the rule is what keeps the smoothing lag out


def test_one_effect_alone_is_named_with_noisy_temperature():
    res = refine(_noisy_temperature_chamber(7, thermal_lag_s=300.0))
    assert [s.effect for s in res.steps] == ["thermal_lag"]
    assert 200.0 < res.steps[0].params["tau_s"] < 400.0


def test_short_time_constant_is_listed_not_claimed():
    res = refine(_noisy_temperature_chamber(3))
    rep = res.report()
    assert rep["steps"] == []
    assert any(r["effect"] == "thermal_lag" and r["tau_s"] < 3 * res.data.dt for r in rep["not_claimed"])


def test_mpu6000_curve_gets_a_table_and_ends_explained():
    path = require_shared_data("mpu6000_gyro_offset_vs_temp/mpu6000_sn102_gyro_offset.csv")
    d = read_csv(path, ["temp_c", "gyro_x"])
    res = refine(fx.FitData(y=d["gyro_x"], t=np.arange(d["gyro_x"].size, dtype=float), T=d["temp_c"]))
    rep = res.report()
    assert rep["steps"][0]["effect"] == "offset_shape", rep["not_added"]
    assert rep["steps"][0]["params"]["family"] == "table"
    assert rep["final_offset"].startswith("table, ")
    assert res.base_rms / res.final_rms >= 5.0
    assert rep["unexplained"]["unexplained"] is False, rep["unexplained"]


def test_hampel_rule_flags_spikes_not_steps():
    rng = np.random.default_rng(0)
    e = rng.standard_normal(3000)
    e[1500:] += 40.0                     # a step: not an impulse
    e[[100, 2200, 2900]] += (30.0, -50.0, 25.0)
    found = robust.impulse_mask(e, np.ones(e.size, bool))
    assert np.flatnonzero(found).tolist() == [100, 2200, 2900]


def test_systematic_part_of_white_noise_is_small():
    rng = np.random.default_rng(1)
    e = rng.standard_normal(20000)
    assert robust.systematic_rms(e, 100) < 0.03
    drift = e + 0.5 * np.sin(np.arange(e.size) / 800.0)
    assert 0.3 < robust.systematic_rms(drift, 100) < 0.4     # 0.5 / sqrt(2)


def test_warm_up_transient_alone_is_named():
    """8 LSB decaying with tau 300 s after power-on, the chamber holding 0 °C
    for the first 300 s; nothing else injected."""
    from lab.studies.refine_cases import WARM_UP_TAU_S, chamber_run, fit_data
    res = refine(fit_data(chamber_run("warm_up", seed=12)))
    assert [s.effect for s in res.steps] == ["warm_up"], res.report()["not_added"]
    assert 0.5 * WARM_UP_TAU_S < res.steps[0].params["tau_s"] < 1.5 * WARM_UP_TAU_S
    rep = res.report()
    assert rep["before"]["averaged_rms"] >= 2.0 * rep["after"]["averaged_rms"]


@pytest.mark.parametrize("n,per_block", [(1, 1), (7, 3), (100, 10), (1001, 7), (5761, 2), (50, 200)])
def test_block_means_are_the_means_of_array_split_blocks_without_nans(n, per_block):
    """The blocks summed at once are np.array_split's; NaNs are skipped and
    a block with none left is dropped, with each block's count."""
    rng = np.random.default_rng(n)
    e = rng.standard_normal(n)
    e[rng.random(n) < 0.3] = np.nan
    if n > 10:
        e[: n // 3] = np.nan        # a run of blocks with nothing left
    blocks = [b[np.isfinite(b)] for b in np.array_split(e, max(1, n // per_block))]
    means, counts = robust.block_means(e, per_block)
    np.testing.assert_allclose(means, [b.mean() for b in blocks if b.size], rtol=1e-12, atol=1e-15)
    assert list(counts) == [b.size for b in blocks if b.size]
