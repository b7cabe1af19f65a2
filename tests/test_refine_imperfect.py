"""refine on records with the imperfections of real clean logs and no
physical effect: coloured (AR(1)) noise, a quantised reading and a
quantised temperature, gaps between sessions, jittered sample times.
Nothing may be claimed on them.  Time stamps that are not uniform: a lag is
filtered over the real time between samples, and a break between sessions
gives the drift a step.  Cases from lab.studies.imperfect_cases (parameters
drawn per seed)."""
import numpy as np

from pysig.refine import FitData, refine
from pysig.refine import _effect_models as fx

from lab.studies.imperfect_cases import UNITS, imperfect_case


def test_coloured_noise_and_quantisation_get_no_claim():
    # AR(1) rho 0.94 at the sample rate, the reading quantised to 2 LSB,
    # a raw temperature code of 16 per °C
    _, truth, data = imperfect_case("coloured", "ramp_hold", seed=3, unit=UNITS[1])
    assert truth["imperfections"]["rho"] > 0.9 and truth["imperfections"]["adc_step"] > 1.0
    assert np.all(data.T == np.round(data.T))
    assert refine(data).report()["effects_found"] == []


def test_two_sessions_with_a_missing_hour_get_no_claim():
    _, truth, data = imperfect_case("gaps", "steps", seed=4, unit=UNITS[1])
    assert len(data.breaks) == 2        # the missing hour and the gap between sessions
    assert refine(data).report()["effects_found"] == []


def test_a_zero_that_wandered_between_sessions_is_a_drift_step_not_a_hysteresis():
    """A random-walk zero logged in two sessions hours apart: the zero moved
    while nothing was logged.  A smooth drift across the gap cannot follow
    that step; a hysteresis took it (and a warm-up the rest) before."""
    _, _, data = imperfect_case("walk+gaps", "ramp_hold", seed=3, unit=UNITS[1])
    rep = refine(data).report()
    assert rep["effects_found"] == [], rep["steps"]


def test_lag_over_uniform_times_is_the_device_filter():
    rng = np.random.default_rng(0)
    t = np.arange(0.0, 600.0, 2.0)
    x = np.cumsum(rng.standard_normal(t.size))
    data = FitData(y=x, t=t, T=x)
    assert len(data.runs) == 1 and data.breaks == ()
    np.testing.assert_array_equal(fx.lag_on_times(x, 30.0, data),
                                  fx.first_order_lag(x, fx.lag_alpha(30.0, 2.0)))


def test_lag_relaxes_over_a_gap_as_that_much_time_does():
    """A step of the input just after a gap of 5 time constants: the state
    is 1 - exp(-5) of the way there, not one sample's worth."""
    tau, dt = 60.0, 2.0
    t = np.concatenate([np.arange(0.0, 200.0, dt), 200.0 + 5 * tau + np.arange(0.0, 200.0, dt)])
    x = np.where(t > 200.0, 1.0, 0.0)
    data = FitData(y=x, t=t, T=x)
    z = fx.lag_on_times(x, tau, data)
    first = int(np.flatnonzero(t > 200.0)[0])
    assert z[first - 1] == 0.0
    assert abs(z[first] - (1.0 - np.exp(-(t[first] - t[first - 1]) / tau))) < 1e-12
    # after the gap, the filter carries on at the sample interval
    assert abs(z[first + 1] - (z[first] + fx.lag_alpha(tau, dt) * (1.0 - z[first]))) < 1e-12


def exact_lag(x, t, tau):
    """The lag over each interval's own length, sample by sample (the
    reference lag_on_times approximates within runs of regular intervals)."""
    z = np.empty(x.size)
    z[0] = x[0]
    for k in range(1, x.size):
        z[k] = z[k - 1] + (1.0 - np.exp(-(t[k] - t[k - 1]) / tau)) * (x[k] - z[k - 1])
    return z


def test_jittered_times_lag_close_to_the_exact_one():
    """Sample intervals jittered by +-30 % and 2 % of samples dropped: each
    run filtered at its mean interval stays within 1 % of the input's swing
    of the lag over every interval's own length, and within half the error
    of filtering every sample at the median interval (measured: 0.12 and
    0.25 of a 25 swing)."""
    rng = np.random.default_rng(1)
    tau, dt = 120.0, 5.0
    t = np.arange(dt, 19990.0, dt) + rng.uniform(-0.3, 0.3, 3997) * dt
    t = np.sort(t[rng.random(t.size) >= 0.02])
    x = 10.0 * np.sin(2 * np.pi * t / 3000.0) + np.where(t > 9000.0, 5.0, 0.0)
    data = FitData(y=x, t=t, T=x)
    assert len(data.runs) > 10
    exact = exact_lag(x, t, tau)
    err = np.abs(fx.lag_on_times(x, tau, data) - exact).max()
    uniform = np.abs(fx.first_order_lag(x, fx.lag_alpha(tau, data.dt)) - exact).max()
    assert err < 0.01 * np.ptp(x) and err < 0.5 * uniform, (err, uniform)


def test_drift_steps_at_a_break_between_sessions():
    t = np.concatenate([np.arange(0.0, 3600.0, 10.0), 4 * 3600.0 + np.arange(0.0, 3600.0, 10.0)])
    data = FitData(y=np.zeros(t.size), t=t, T=np.sin(t / 500.0))
    assert data.breaks == (360,)
    assert data.span_t < 2 * 3600.0     # the logged time: the gap is not resolved
    X, names = fx.design(data, fx.ModelSpec(1, (fx.Effect("drift", 3),)))
    assert names[-1] == "drift:session@360"
    np.testing.assert_array_equal(X[:, -1], (np.arange(t.size) >= 360).astype(float))
