"""A hysteresis or a warm-up is claimed only if it also stands with a
random-walk zero estimated with it (a local-level state-space model): a
zero that wanders as a random walk and happens to move with the cold and
warm spells passes the blocked-CV test (the walk is correlated across all
held-out blocks) but not this one, whose evidence comes from the
increments.  A real hysteresis under a drift keeps its claim.  Cases from
lab.studies.imperfect_cases and lab.studies.overlap_cases; the bench
(bench/refine_table.py) runs more; docs/refine.md gives the rates."""
from dataclasses import replace

import numpy as np
import pytest
from scipy import stats

from pysig.cli.commands.refine import format_table
from pysig.refine import FitData, Options, refine
from pysig.refine import _effect_models as fx
from pysig.refine._random_walk import random_walk_check

from lab.studies.imperfect_cases import UNITS, imperfect_case
from lab.studies.overlap_cases import judge_case, options_for, roaming_imperfect_case


def test_random_walk_zero_that_passed_as_a_hysteresis_is_not_claimed():
    # no physical effect: a random-walk zero, AR(1) noise, a room cycle,
    # gaps, on a plate stepped 1 K up and down twice
    _, truth, data = imperfect_case("all", "steps", seed=7, unit=UNITS[0])
    assert truth["effects"] == {} and truth["drift"]
    without = refine(data, Options(random_walk_check=False)).report()
    assert without["effects_found"] == ["hysteresis"]            # the false claim the check removes
    result = refine(data)
    rep = result.report()
    assert rep["effects_found"] == [], rep["steps"]
    (walk,) = [r["random_walk"] for r in rep["not_added"] if "random_walk" in r]
    assert walk["effect"] == "hysteresis" and not walk["p_value"] < walk["p_threshold"]
    assert "not added: hysteresis (under a random-walk drift p = " in format_table("y", result)


def test_roaming_control_with_an_irregular_drift_gets_no_hysteresis():
    _, truth, data = roaming_imperfect_case(6, "mg", hysteresis=False, drift_mg=1.5)
    opts = options_for(truth)
    assert "hysteresis" in refine(data, replace(opts, random_walk_check=False)).report()["effects_found"]
    assert judge_case(truth, refine(data, opts))["found"] == []


def test_true_hysteresis_under_an_irregular_drift_keeps_its_claim():
    _, truth, data = roaming_imperfect_case(4, "mg", drift_mg=1.5)
    result = refine(data, options_for(truth))
    j = judge_case(truth, result)
    assert j["found"] == ["hysteresis"] and j["params_within_50pct"]["hysteresis"], j
    (step,) = [s for s in result.report()["steps"] if s["effect"] == "hysteresis"]
    assert step["random_walk"]["p_value"] < step["random_walk"]["p_threshold"]
    assert "hysteresis under a random-walk drift: p = " in format_table("y", result)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_without_a_walk_the_check_is_the_regression(seed):
    """A hysteresis under white noise and no drift: the level's variance
    fits to about zero and the effect's evidence is that of least squares."""
    rng = np.random.default_rng(seed)
    t = np.arange(4000) * 10.0
    T = 20.0 + 15.0 * np.sin(2 * np.pi * t / 8000.0)
    branch = (T - fx.play_operator(T, 6.0)) / 6.0
    y = 0.3 * T + 0.15 * branch + rng.standard_normal(t.size)
    data = FitData(y=y, t=t, T=T)
    model = fx.fit(data, fx.ModelSpec(1, (fx.Effect("hysteresis", 0, 6.0),)))
    walk = random_walk_check(data, model, ("hysteresis",), per_report=1)
    assert walk["level_sd"] < 0.05 * walk["irregular_sd"]
    X = model.design
    cov = np.linalg.inv(X.T @ X) * np.sum(model.residual ** 2) / (t.size - X.shape[1])
    z = model.beta[-1] / np.sqrt(cov[-1, -1])
    assert np.isclose(np.log(walk["p_value"]), np.log(stats.chi2.sf(z ** 2, 1)), rtol=0.1)
