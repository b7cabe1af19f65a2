"""The weighing benches' peers do what their libraries' sources do
(bench/lab/studies/peers.py cites each file and default): worked by hand
from the C, on small inputs."""
import numpy as np
import pytest

from lab.studies import peers


def test_hx711_adc_drops_max_and_min_of_18_and_shifts_by_4():
    x = np.array([100.0] * 17 + [-7.0])                  # window full after 18 samples
    x[3] = 5000.0                                        # the largest: dropped
    out = peers.hx711_adc(x)
    # smoothedData(): sum of 18 minus max and min, >> 4 (floor, also below zero)
    assert out[-1] == (sum(x) - 5000.0 - (-7.0)) // 16
    neg = peers.hx711_adc(np.full(18, -3.0))
    assert neg[-1] == -3.0                               # (-48) >> 4
    assert peers.hx711_adc(np.array([1.0] * 17 + [2.0]))[-1] == 1.0   # (19 - 2 - 1) >> 4
    # in another unit (no whole code to round to) the same window, not rounded
    assert peers.hx711_adc(np.full(18, 0.3))[-1] == pytest.approx(0.3, rel=1e-12)
    assert peers.hx711_adc(0.3 + np.arange(18) / 64)[-1] == pytest.approx(0.3 + 8.5 / 64, rel=1e-12)


def test_bogde_average_truncates_toward_zero():
    x = np.array([0.0] * 9 + [-15.0])                    # sum -15: -15 / 10 in C is -1
    assert peers.average10(x)[-1] == -1.0
    assert peers.average10(np.array([0.0] * 9 + [15.0]))[-1] == 1.0
    assert peers.average10(np.array([0.0] * 9 + [1.5]))[-1] == 0.15   # kg: no code


def test_robtillaart_medavg_includes_the_last_index():
    x = np.array([1.0, 9.0, 3.0, 7.0, 5.0, 2.0, 100.0])   # sorted: 1 2 3 5 7 9 100
    assert peers.medavg7(x)[-1] == (3.0 + 5.0 + 7.0) / 3   # indices 2..4 inclusive
    assert peers.median7(x)[-1] == 5.0


def test_simple_kalman_starts_at_zero_in_float32():
    out = peers.simple_kalman(np.array([10.0, 10.0]), e_mea=2.0, q=0.01)
    f = np.float32
    gain = f(2.0) / (f(2.0) + f(2.0))                    # e_est = e_mea: 0.5
    first = f(0.0) + gain * (f(10.0) - f(0.0))           # from _last_estimate = 0
    err = (f(1.0) - gain) * f(2.0) + abs(f(0.0) - first) * f(0.01)
    gain2 = err / (err + f(2.0))
    assert out[0] == first == 5.0
    assert out[1] == first + gain2 * (f(10.0) - first)


def test_simple_kalman_is_unit_free():
    """q has no unit: the same test in counts and in kg (e_mea in the unit)
    gives the same output up to the scale."""
    rng = np.random.default_rng(0)
    counts = np.repeat([0.0, 10000.0], 100) + rng.normal(0, 50.0, 200)
    kg = counts / 2204.6
    a = peers.simple_kalman(counts, 50.0)
    b = peers.simple_kalman(kg, 50.0 / 2204.6)
    np.testing.assert_allclose(a / 2204.6, b, rtol=1e-4, atol=1e-6)
