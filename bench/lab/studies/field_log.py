"""Field logs for the device learner: a drift curve seen through natural
temperature swings (day/night, weather fronts; heating and cooling alike),
still and moving periods, sensor noise, one sample a minute.

The curves come from the real recordings in ../shared/data (the MPU-6000
gyro offset table, the BMI270 gyro bias at two temperatures) or are made
up in other shapes (cubic, a step).  Readings are int16 sensor codes."""
from dataclasses import dataclass

import numpy as np

from pysig.io import read_csv

MINUTES_PER_DAY = 1440


@dataclass(frozen=True)
class Curve:
    """offset(T °C) in LSB, defined on [t_min, t_max] °C."""
    name: str
    temp_c: np.ndarray
    offset: np.ndarray

    @property
    def t_min(self):
        return float(self.temp_c[0])

    @property
    def t_max(self):
        return float(self.temp_c[-1])

    def __call__(self, temp_c):
        return np.interp(temp_c, self.temp_c, self.offset)


def mpu6000_curves(path, scale=4.0):
    """The three MPU-6000 gyro offset curves.  The table is in units of 64
    raw LSB; the field reading here is the raw gyro shifted right by 4 bits
    (units of 16 LSB), so offset = 4 x the table value (|offset| < 1700)."""
    d = read_csv(path)
    return [Curve(f"mpu6000_{a}", d["temp_c"], scale * d[f"gyro_{a}"]) for a in "xyz"]


def bmi270_curve(cold_path, hot_path, lsb_per_dps=16.4, axis="x"):
    """The BMI270 gyro bias, linear through its mean at the two recorded
    temperatures (the only shape two points give), at +-2000 dps (16.4
    LSB/dps), extended over 0..60 °C."""
    pts = []
    for p in (cold_path, hot_path):
        d = read_csv(p)
        pts.append((float(np.mean(d["temp_c"])), float(np.mean(d[f"gyro_{axis}_dps"])) * lsb_per_dps))
    (t1, y1), (t2, y2) = pts
    t = np.linspace(0.0, 60.0, 121)
    return Curve(f"bmi270_{axis}", t, y1 + (y2 - y1) * (t - t1) / (t2 - t1))


def made_up_curves():
    """Shapes the real curves do not have: a cubic over -20..60 °C, a step
    of 30 LSB at 20 °C (a 3 °C wide sigmoid) over -10..50 °C."""
    t1 = np.linspace(-20.0, 60.0, 321)
    u = (t1 - 20.0) / 40.0
    t2 = np.linspace(-10.0, 50.0, 241)
    return [Curve("cubic", t1, 60 * u ** 3 - 35 * u + 12),
            Curve("step", t2, 30.0 / (1.0 + np.exp(-(t2 - 20.0) / 3.0)) - 8.0)]


def temperature(days, lo, hi, rng):
    """One sample a minute: a day/night sine (random phase) plus weather
    fronts (a smoothed random walk), scaled into [lo, hi] °C; it heats and
    cools many times."""
    n = int(days * MINUTES_PER_DAY)
    k = np.arange(n)
    day = np.sin(2 * np.pi * k / MINUTES_PER_DAY + rng.uniform(0, 2 * np.pi))
    walk = np.cumsum(rng.normal(0, 1, n // 60 + 2))
    walk = np.interp(k / 60.0, np.arange(walk.size), walk - np.linspace(walk[0], walk[-1], walk.size))
    walk /= max(1e-9, np.abs(walk).max())
    x = 0.55 * day + 0.45 * walk
    x = (x - x.min()) / max(1e-9, np.ptp(x))
    return lo + (hi - lo) * x


def still_gate(n, rng, still_share=0.6, mean_block=30):
    """Still and moving blocks (exponential lengths, mean `mean_block`
    minutes), still about `still_share` of the time."""
    out = np.empty(n, dtype=bool)
    i, state = 0, True
    while i < n:
        mean = mean_block if state else mean_block * (1 - still_share) / still_share
        m = max(1, int(rng.exponential(mean)))
        out[i:i + m] = state
        i += m
        state = not state
    return out


def field_log(curve, days, noise, rng, lo=None, hi=None, shift_at=None, shift=0.0):
    """(temp_c, reading int64, still, true offset) of a field log: the
    curve at the swinging temperature, noise (sd `noise` LSB), motion
    (sd 300 LSB) while moving, and optionally an offset step of `shift` LSB
    from sample `shift_at` on."""
    lo = curve.t_min if lo is None else lo
    hi = curve.t_max if hi is None else hi
    temp = temperature(days, lo, hi, rng)
    n = temp.size
    still = still_gate(n, rng)
    true = curve(temp)
    if shift_at is not None:
        true = true + np.where(np.arange(n) >= shift_at, shift, 0.0)
    x = true + rng.normal(0, noise, n) + np.where(still, 0.0, rng.normal(0, 300, n))
    return temp, np.clip(np.rint(x), -32768, 32767).astype(np.int64), still, true
