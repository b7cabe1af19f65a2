"""Refine where effects overlap: a nuisance drift in time under the physics
(reported on its own line, never exported to the device), search ranges
taken from the record and followed past their first top, and two effects
that fail alone judged as a pair.  Cases from lab.studies.overlap_cases,
whose parameters are drawn per seed; the judge is the bench's."""
import numpy as np
import pytest

from pysig.refine import FitData, device_model, refine
from pysig.refine import _effect_models as fx

from lab.studies import overlap_cases
from lab.studies.overlap_cases import (judge_case, options_for, overlap_case, plate_resistor_case,
                                       roaming_instrument_case)


@pytest.mark.parametrize("kind,seed", [("thermal_lag+drift", 1), ("hysteresis+drift", 2)])
def test_effect_under_a_drift_is_named_with_its_parameter(kind, seed):
    _, truth, data = overlap_case(kind, seed=seed, noise=2.0, dt=10.0)
    res = refine(data)
    j = judge_case(truth, res)
    assert j["named_right"], j
    assert all(j["params_within_50pct"].values()), j
    assert j["cv_cut"] > 1.2, j
    rep = res.report()
    shares = [r["share"] for r in rep["shares"]]
    assert shares and abs(sum(shares) - 1.0) < 1e-9 and min(shares) >= 0.0
    assert rep["cv_systematic"]["after"] < rep["cv_systematic"]["before"]


@pytest.mark.parametrize("seed", [0, 1])
def test_drift_alone_claims_no_physical_effect(seed):
    _, truth, data = overlap_case("drift", seed=seed, noise=0.5, dt=10.0)
    rep = refine(data).report()
    assert rep["effects_found"] == [], rep["steps"]
    d = rep["drift"]
    assert d is not None and d["exported"] is False
    # the same record without noise, with and without the drift: the drift itself
    true_drift = (overlap_case("drift", seed=seed, noise=0.0, dt=10.0)[2].y
                  - overlap_case("clean", seed=seed, noise=0.0, dt=10.0)[2].y)
    assert d["over_record"] == pytest.approx(np.ptp(true_drift), rel=0.5)    # in the reading's unit


def test_clean_generated_record_gets_nothing():
    for seed in (3, 4):
        _, _, data = overlap_case("clean", seed=seed, noise=2.0, dt=10.0)
        res = refine(data)
        assert res.steps == [], [s.effect for s in res.steps]


def test_drift_stays_out_of_the_device_correction():
    _, truth, data = overlap_case("thermal_lag+drift", seed=0, noise=0.5, dt=10.0)
    res = refine(data)
    assert "drift" in res.final.spec.names()
    dev = device_model(res)
    assert "drift" in dev["not_exported"] and dev["lag"] is not None


def test_wide_hysteresis_on_a_roaming_record_is_found_with_the_drift():
    """Width two thirds of the span: past the first search range (half the
    span), followed there instead of being called unresolvable; alone it
    loses to the drift, together they pass."""
    _, truth, data = roaming_instrument_case(seed=0)
    res = refine(data, options_for(truth))
    j = judge_case(truth, res)
    assert j["named_right"] and all(j["params_within_50pct"].values()), j
    assert res.report()["at_search_edge"] == [] or "hysteresis" not in {
        e["effect"] for e in res.report()["at_search_edge"]}
    width = j["params"]["hysteresis"]
    assert width > fx.FAMILIES["hysteresis"].bounds(data)[1]
    assert j["cv_cut"] > 1.2, j


def test_plate_resistor_lag_is_claimed_with_a_plausible_time_constant():
    _, truth, data = plate_resistor_case(seed=1)
    res = refine(data)
    j = judge_case(truth, res)
    assert "thermal_lag" in j["found"] and j["params_within_50pct"]["thermal_lag"], j
    assert set(j["found"]) <= {"thermal_lag", "warm_up"}, j
    assert j["cv_cut"] > 2.0, j


def test_hysteresis_needs_the_temperature_to_turn_twice():
    t = np.arange(0.0, 4000.0, 2.0)
    T = np.interp(t, [0, 2000, 4000], [20.0, 40.0, 22.0])
    data = FitData(y=T.copy(), t=t, T=T)
    assert "turns only once" in fx.FAMILIES["hysteresis"].unavailable(data)
    T2 = np.interp(t, [0, 1000, 2000, 3000, 4000], [20.0, 40.0, 22.0, 38.0, 21.0])
    assert fx.FAMILIES["hysteresis"].unavailable(FitData(y=T2.copy(), t=t, T=T2)) is None


def test_search_is_followed_past_the_first_top():
    """A time constant beyond a third of the record is found where it is
    (the grid extends up to the whole record), not pinned at the top."""
    rng = np.random.default_rng(0)
    t = np.arange(0.0, 3000.0, 2.0)
    T = 20 + 10 * np.sign(np.sin(2 * np.pi * t / 1500.0))
    tau = 1400.0                                  # a third of the record is 1000 s
    y = 1.5 * fx.first_order_lag(T, fx.lag_alpha(tau, 2.0)) + 0.01 * rng.standard_normal(t.size)
    data = FitData(y=y, t=t, T=T)
    lag = fx.FAMILIES["thermal_lag"]
    assert lag.bounds(data)[1] < tau < lag.limit(data)
    m = fx.fit_param(data, fx.ModelSpec(1), lag, 0)
    assert abs(m.spec.effects[0].param / tau - 1.0) < 0.05


def test_drift_is_unavailable_when_temperature_ranks_with_time():
    """Rows sorted by temperature (a binned drift curve): a drift in time
    would be a second offset in temperature."""
    t = np.arange(200.0)
    T = np.linspace(-20.0, 60.0, 200)
    assert "moves with time" in fx.FAMILIES["drift"].unavailable(FitData(y=T.copy(), t=t, T=T))
    T2 = 20.0 + 15.0 * np.sin(t / 20.0)
    assert fx.FAMILIES["drift"].unavailable(FitData(y=T2.copy(), t=t, T=T2)) is None


def test_warm_up_under_a_lag_is_found_without_a_rider():
    """A single power-on's warm-up under a lag: found, and no hysteresis
    rides along on its gain (each member of a pair must carry part of it)."""
    _, truth, data = overlap_case("warm_up+thermal_lag", seed=0, noise=0.5, dt=10.0, length_s=12 * 3600.0)
    j = judge_case(truth, refine(data))
    assert j["found"] == ["thermal_lag", "warm_up"], j
    assert all(j["params_within_50pct"].values()), j


def test_warm_up_slower_than_the_drift_resolves_is_a_drift():
    """A settling of a fifth of the record is followed by a 5-knot drift:
    it is not named warm-up (the warm-up's range ends where it settles
    within the drift's first knot interval), and nothing else takes what
    the drift leaves (a piecewise-linear drift left its curvature to a wide
    hysteresis here)."""
    _, truth, data = overlap_case("drift", seed=7, noise=0.5, dt=2.0, unit=overlap_cases.UNITS[1])
    assert fx.FAMILIES["warm_up"].limit(data) == pytest.approx(data.span_t / 8.0)
    rep = refine(data).report()
    assert rep["effects_found"] == [], rep["steps"]
    assert rep["drift"] is not None


def test_drift_is_a_smooth_spline_through_its_knots():
    """2 knots: a line; 3: any parabola exactly; each column is 1 at its
    knot and 0 at the others; smooth (no corner at a knot)."""
    t = np.linspace(0.0, 100.0, 1001)
    data = FitData(y=np.zeros(t.size), t=t)
    drift = fx.FAMILIES["drift"]
    line, _ = drift.columns(data, None, fx.Effect("drift", 2))
    assert line[:, 0] == pytest.approx(t / 100.0)
    cols, _ = drift.columns(data, None, fx.Effect("drift", 3))
    X = np.column_stack([np.ones(t.size), cols])
    parabola = 3.0 - 0.2 * t + 0.01 * t ** 2
    beta = np.linalg.lstsq(X, parabola, rcond=None)[0]
    assert X @ beta == pytest.approx(parabola, abs=1e-9)
    cols5, _ = drift.columns(data, None, fx.Effect("drift", 5))
    at_knots = cols5[[0, 250, 500, 750, 1000]]          # the knots at 0, 25, 50, 75, 100
    assert at_knots == pytest.approx(np.eye(5)[:, 1:], abs=1e-12)    # each column: its knot's value
    slope = np.diff(cols5, axis=0)
    assert np.max(np.abs(np.diff(slope, axis=0))) < 1e-3      # no jump in slope anywhere


def test_an_effect_whose_gain_was_the_drifts_knots_is_not_claimed():
    """A lag under a drift: a hysteresis tried with the drift's knots chosen
    again took the knots' gain as its own (share 0 %); the newcomer must
    carry its own.  The lag's time constant is the final model's (it was
    fitted before the drift was in and moved once it was)."""
    _, truth, data = overlap_case("thermal_lag+drift", seed=3, noise=0.5, dt=2.0)
    res = refine(data)
    j = judge_case(truth, res)
    assert j["found"] == ["thermal_lag"], j
    step = next(s for s in res.steps if s.effect == "thermal_lag")
    final_tau = next(e.param for e in res.final.spec.effects if e.name == "thermal_lag")
    assert step.params["tau_s"] == final_tau
    assert abs(final_tau / truth["effects"]["thermal_lag"]["tau_s"] - 1.0) < 0.05


def test_no_warm_up_next_to_a_hysteresis_under_a_drift():
    """The drift's knots chosen before the hysteresis was in were too few;
    chosen again after it, nothing is left for a short warm-up to take."""
    _, truth, data = overlap_case("hysteresis+drift", seed=0, noise=0.5, dt=10.0)
    j = judge_case(truth, refine(data))
    assert j["found"] == ["hysteresis"] and j["params_within_50pct"]["hysteresis"], j


def test_an_effect_the_kept_model_no_longer_needs_is_dropped():
    """An effect added with a drift of few knots can carry less than the
    material margin once the drift's knots are chosen again with it in: it
    is taken out and reported as dropped, not claimed with a share near 0.
    On this record (a hysteresis of 54 % of the span under a drift, 1 LSB
    of noise, every 5 s, 8 h) the re-chosen drift (5 knots) takes over most
    of the hysteresis: it removes 0.22 of a reading's systematic error
    against a margin of 0.35 (at its true width on that drift, 0.21); a
    warm-up taken for part of the drift's settling went the same way when
    a fold's time constant was the least tail SSE."""
    _, truth, data = overlap_case("hysteresis+drift", seed=14, noise=1.0, dt=5.0, length_s=8 * 3600.0)
    rep = refine(data).report()
    assert "warm_up" not in rep["effects_found"], rep["steps"]
    assert rep["dropped"], rep["steps"]
    for d in rep["dropped"]:        # each taken out for carrying less than the material margin
        assert d["systematic_removed"] < 0.5 * d["reading_noise"], d
        assert d["effect"] not in rep["effects_found"]
    assert all(r["share"] > 0.0 for r in rep["shares"]), rep["shares"]


def test_drift_knots_are_chosen_again_with_the_effect_in():
    """The drift taken first bends to imitate part of a wide hysteresis;
    with its knots chosen again the hysteresis is found."""
    _, truth, data = roaming_instrument_case(seed=1)
    j = judge_case(truth, refine(data, options_for(truth)))
    assert j["named_right"] and all(j["params_within_50pct"].values()), j


def test_a_function_of_time_alone_does_not_trade_for_a_drift_knot():
    """With the drift's knots chosen again, a warm-up is only another drift:
    the re-drift trials hold the effects of temperature, never a warm-up
    (a drift alone, 12 h, got a warm-up of an eighth of the record in
    place of its fifth knot)."""
    from pysig.refine import Options
    from pysig.refine._joint import redrift_trials
    _, _, data = overlap_case("hysteresis+drift", seed=0, noise=0.5, dt=10.0)
    model = fx.fit(data, fx.ModelSpec(2, (fx.Effect("drift", 5),)))
    tried = [(1.0, "warm_up", 0, None, None), (1.1, "hysteresis", 0, None, None)]
    out = redrift_trials(data, model, tried, Options(), lambda fam, spec: True)
    assert out and {name for _, name, _, _, _ in out} == {"hysteresis"}
    assert fx.FAMILIES["warm_up"].time_only and not fx.FAMILIES["hysteresis"].time_only


def test_a_pair_that_predicts_worse_than_the_best_single_candidate_is_not_claimed():
    """A warm-up under a lag (1 LSB, every 5 s, 8 h; a seed the bench does
    not hold) whose warm-up alone predicts held-out blocks best of the
    single candidates but misses the test (p = 0.023): a drift and a wide
    hysteresis together, predicting worse (CV RMS 1.50 against 1.10),
    passed as a pair and the hysteresis stayed on next to the warm-up added
    after it.  A pair is judged only when it predicts better than every
    single candidate."""
    _, truth, data = overlap_case("warm_up+thermal_lag", seed=36, noise=1.0, dt=5.0, length_s=8 * 3600.0)
    j = judge_case(truth, refine(data))
    assert "hysteresis" not in j["found"], j
    assert "thermal_lag" in j["found"] and j["params_within_50pct"]["thermal_lag"], j
