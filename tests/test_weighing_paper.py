"""The weighing-accuracy experiment (lab.studies.weighing_accuracy, printed by
bench/weighing_accuracy.py) reproduces the weighing paper's direction and
factors on the simulator, and the motion-aware mode settles fast without
losing accuracy.  Margins, not exact numbers; 20 seeds as the bench."""
import json

import pytest

from lab.studies import weighing_accuracy


@pytest.fixture(scope="module")
def figures():
    return weighing_accuracy.run(20)


def test_calibration_recovers_the_cell(figures):
    c = figures["calibration"]
    assert c["sensitivity_mv_per_kg_median"] == pytest.approx(0.15, rel=0.01)
    assert 0.0 < c["linearity_err_pct_fs_median"] < 0.05     # the 0.02 % FS bow, after the fit


def test_noise_setting_matches_the_paper_raw_error(figures):
    assert figures["raw_max_err_pct_30kg"] == pytest.approx(6.2, abs=0.05)


def test_paper_direction_and_factors(figures):
    f = figures
    # 30 kg: the chain improves on raw readings by more than the weighing paper's 20x
    assert f["chain_max_err_pct_30kg"] < f["raw_max_err_pct_30kg"] / 20
    assert f["chain_max_err_pct_30kg"] <= 0.3
    # over the masses: the plain Kalman filter errs about as the weighing paper's (1.8 %),
    # the chain stays under the weighing paper's 0.4 % (median over seeds), >= 4x better
    assert 1.0 < f["kalman_max_err_pct_all"] < 3.0
    assert f["chain_max_err_pct_all"] < 0.4
    assert f["kalman_max_err_pct_all"] / f["chain_max_err_pct_all"] > 4.0


def test_paper_chain_locks_out_and_lags(figures):
    # a 20-kg step is 10x A0: the weighing paper's chain never follows it
    assert figures["paper_settle_s"] is None
    assert figures["paper_settle_never"] == figures["seeds"]
    # with only the lock-out fix, the slow Kalman gain takes minutes
    assert figures["paper_lockfix_settle_s"] > 100


def test_adaptive_settles_fast_and_stays_accurate(figures):
    assert figures["adaptive_settle_s"] <= 2.0
    assert figures["adaptive_settle_s_worst"] <= 2.0
    assert figures["adaptive_max_err_pct_all"] <= 1.1 * figures["chain_max_err_pct_all"]
    # and no start-up lock-out: the worst run stays under 1 % (the weighing paper's chain
    # seeded on an impulse errs by up to ~95 % in the same runs)
    assert figures["adaptive_max_err_pct_all_worst"] < 1.0
    assert figures["chain_max_err_pct_all_worst"] > 10.0


def test_shipped_presets_given_the_sensors_noise(figures):
    """recommended (the default) and adaptive as shipped, given the sensor's R:
    their A0 / motion band follow from it, and they are as accurate as the
    weighing paper's chain over the calibrated 10-50 kg (and within the weighing paper's 0.4 %)
    while settling within 2 s after a load change."""
    for n in ("recommended", "adaptive_preset"):
        assert figures[f"{n}_max_err_pct_10to50kg"] <= 0.4, n
        assert figures[f"{n}_max_err_pct_10to50kg"] <= 1.05 * figures["chain_max_err_pct_10to50kg"], n
        assert figures[f"{n}_max_err_pct_30kg"] <= 1.1 * figures["chain_max_err_pct_30kg"], n
        assert figures[f"{n}_max_err_pct_10to50kg_worst"] < 1.0, n
        assert figures[f"{n}_settle_s"] <= 2.0 and figures[f"{n}_settle_s_worst"] <= 2.0, n
    # the thresholds follow R: left at the R of the HX711 recording the
    # default was tuned on (24x quieter than this simulator), it errs by %
    assert figures["recommended_hx711_R_max_err_pct_30kg"] > 1.0


def test_json_fields(figures):
    for key in ("raw_max_err_pct_30kg", "kalman_max_err_pct_30kg", "chain_max_err_pct_30kg",
                "kalman_max_err_pct_all", "chain_max_err_pct_all", "paper_settle_s",
                "adaptive_settle_s", "adaptive_max_err_pct_all"):
        assert key in figures
    assert [r["mass_kg"] for r in figures["per_mass"]] == [5.0 * k for k in range(1, 11)]
    json.dumps(figures)                                          # serialisable as written


def test_fixed_point_chain_reproduces_the_float_figures(figures):
    """The firmware's fixed-point form on integer codes: the same figures
    within 0.02 percentage points, the same settling."""
    for n in ("chain", "adaptive"):
        assert figures[f"{n}_fixed_max_err_pct_30kg"] == pytest.approx(figures[f"{n}_max_err_pct_30kg"], abs=0.02)
        assert figures[f"{n}_fixed_max_err_pct_all"] == pytest.approx(figures[f"{n}_max_err_pct_all"], abs=0.02)
    no_swing = figures["settle"]["by_swing"][0]
    assert no_swing["adaptive_fixed"]["worst"] <= 2.0
