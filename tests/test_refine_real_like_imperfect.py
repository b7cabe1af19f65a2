"""Refine on imperfect records built like two real bench logs: a resistor
that follows a 1-K-stepped plate through two time constants, and an
instrument whose offset follows a spread of play operators as it is carried
between cold and warm places; both with coloured noise, a room cycle, a
quantised reading and temperature, an irregular drift and structure no
candidate explains, in the reading's unit and in raw codes.  The right
effect is claimed with a plausible parameter, and nothing physical is
claimed on the same records without it.  The bench
(bench/refine_table.py) runs more seeds; docs/refine.md gives the rates."""
import pytest

from pysig.refine import refine

from lab.studies.overlap_cases import judge_case, options_for, plate_imperfect_case, roaming_imperfect_case


@pytest.mark.parametrize("seed,unit", [(0, "ohm"), (1, "counts")])
def test_two_pole_plate_lag_is_claimed_with_a_plausible_time_constant(seed, unit):
    _, truth, data = plate_imperfect_case(seed, unit)
    j = judge_case(truth, refine(data, options_for(truth)))
    assert "thermal_lag" in j["found"] and j["named_right"], j
    assert j["lag_plausible"], (j["params"], truth["lag_poles_s"])
    assert j["params_within_50pct"]["thermal_lag"], j
    assert j["cv_cut"] > 1.5, j


@pytest.mark.parametrize("seed,unit", [(3, "counts"), (6, "mg")])
def test_spread_hysteresis_is_claimed_near_its_dominant_width(seed, unit):
    _, truth, data = roaming_imperfect_case(seed, unit, drift_mg=0.5)
    j = judge_case(truth, refine(data, options_for(truth)))
    assert j["found"] == ["hysteresis"], j
    assert j["params_within_50pct"]["hysteresis"], j
    assert j["cv_cut"] > 1.3, j


@pytest.mark.parametrize("make", [lambda: plate_imperfect_case(0, "ohm", lag=False),
                                  lambda: plate_imperfect_case(1, "counts", lag=False),
                                  lambda: roaming_imperfect_case(3, "counts", hysteresis=False, drift_mg=0.5),
                                  lambda: roaming_imperfect_case(6, "mg", hysteresis=False, drift_mg=0.5)])
def test_same_records_without_the_effect_get_no_physical_claim(make):
    _, truth, data = make()
    assert judge_case(truth, refine(data, options_for(truth)))["found"] == []
