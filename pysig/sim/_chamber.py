"""Thermal-chamber simulator for a QMC5883L-like 3-axis magnetometer held
in a constant field: 12000 LSB/G at the ±2 G range, int16 output.  Seeded,
so a run is reproducible.  CSV columns: t, temp, x, y, z, ref_x, ref_y, ref_z
(t in s, temp = the MCU's temperature sensor in °C, x/y/z the int16
readings, ref_* the true field in LSB).

    reading = round( s(T_d) * (M @ B) * lsb_per_g + cubic * B^3
                     + offset(T_d) + hysteresis + noise )        clipped to int16
    s(T)      = 1 + gain_drift(T - 25)          (sensitivity drift, per axis)
    offset(T) = offset_poly(T - 25)             (LSB, per axis)
    T_d       = the sensor die temperature: the chamber temperature through a
                first-order lag of time constant thermal_lag_s (0: no lag)

Effects off by default (set the parameter to switch one on): thermal lag
(`thermal_lag_s`), hysteresis (`hysteresis_lsb`: +h/2 while the chamber
heats, -h/2 while it cools, the last direction held on a plateau),
cross-axis coupling (`cross_axis`, 3x3 matrix M, identity when None) and
nonlinearity (`cubic_lsb_per_g3`, a cubic term in the field).  The MCU's
temperature sensor reads the chamber temperature with Gaussian noise
`temp_noise_c`, quantised to `temp_resolution_c`."""
from dataclasses import dataclass

import numpy as np

from ..io import write_csv

COLUMNS = ("t", "temp", "x", "y", "z", "ref_x", "ref_y", "ref_z")


@dataclass(frozen=True)
class ChamberParams:
    seed: int = 0
    sample_rate_hz: float = 1.0
    profile: str = "steps"                      # "steps" or "ramp"
    step_temps_c: tuple = (0.0, 25.0, 50.0, 70.0)   # the magnetometer paper's chamber steps
    dwell_s: float = 1800.0                     # time on each plateau
    ramp_c_per_min: float = 1.0                 # chamber slew between steps / ramp speed
    ramp_cycles: int = 1                        # "ramp": up min->max and back down, this many times
    field_g: tuple = (0.30, -0.20, 0.45)        # constant field, G
    lsb_per_g: float = 12000.0
    range_g: float = 2.0
    offset_poly: tuple = ((30.0, 2.0, 0.030), (-50.0, -1.5, 0.020), (10.0, 0.8, -0.025))  # LSB, powers of (T-25)
    gain_drift: tuple = ((0.0, -3e-4), (0.0, -2e-4), (0.0, 1.5e-4))  # relative, powers of (T-25)
    noise_lsb: float = 4.0
    temp_noise_c: float = 0.05
    temp_resolution_c: float = 0.0625
    thermal_lag_s: float = 0.0                  # effect: off
    hysteresis_lsb: tuple = (0.0, 0.0, 0.0)     # effect: off
    cross_axis: tuple = None                    # effect: off (3x3 rows)
    cubic_lsb_per_g3: tuple = (0.0, 0.0, 0.0)   # effect: off


def chamber_temperature(p, t):
    """Chamber temperature profile at times t (s) and its total duration."""
    if p.profile == "steps":
        knots_t, knots_T = [0.0], [p.step_temps_c[0]]
        for temp in p.step_temps_c[1:]:
            knots_t.append(knots_t[-1] + p.dwell_s)
            knots_T.append(knots_T[-1])
            knots_t.append(knots_t[-1] + abs(temp - knots_T[-1]) * 60.0 / p.ramp_c_per_min)
            knots_T.append(temp)
        knots_t.append(knots_t[-1] + p.dwell_s)
        knots_T.append(knots_T[-1])
    elif p.profile == "ramp":
        lo, hi = min(p.step_temps_c), max(p.step_temps_c)
        leg = (hi - lo) * 60.0 / p.ramp_c_per_min
        knots_t, knots_T = [0.0, p.dwell_s], [lo, lo]
        for _ in range(p.ramp_cycles):
            knots_t += [knots_t[-1] + leg, knots_t[-1] + leg + p.dwell_s, knots_t[-1] + 2 * leg + p.dwell_s]
            knots_T += [hi, hi, lo]
    else:
        raise ValueError(f"profile must be 'steps' or 'ramp', got {p.profile!r}")
    if t is None:
        return knots_t[-1]
    return np.interp(t, knots_t, knots_T)


def simulate(p=ChamberParams()):
    """Simulate one thermal-chamber run of the magnetometer.

    Parameters
    ----------
    p : ChamberParams, optional
        Profile (the magnetometer paper's 0/25/50/70 °C steps by default),
        field, drift, noise and the switchable effects; seeded.

    Returns
    -------
    dict
        column -> array: t (s), temp (the MCU's sensor, °C), x, y, z (int16
        readings), ref_x, ref_y, ref_z (the true field, LSB).

    Raises
    ------
    ValueError
        An unknown profile.

    Examples
    --------
    >>> run = simulate(ChamberParams(dwell_s=600.0))
    >>> sorted(run)
    ['ref_x', 'ref_y', 'ref_z', 't', 'temp', 'x', 'y', 'z']
    >>> run["t"].size, float(run["temp"][0]), float(run["temp"][-1])
    (6600, 0.0, 70.0)
    """
    rng = np.random.default_rng(p.seed)
    dt = 1.0 / p.sample_rate_hz
    t = np.arange(0.0, chamber_temperature(p, None), dt)
    chamber = chamber_temperature(p, t)
    die = chamber.copy()
    if p.thermal_lag_s > 0:
        alpha = 1.0 - np.exp(-dt / p.thermal_lag_s)
        for i in range(1, t.size):
            die[i] = die[i - 1] + alpha * (chamber[i] - die[i - 1])
    slope = np.sign(np.diff(chamber, prepend=chamber[0]))
    heating = np.empty(t.size, dtype=bool)
    state = True
    for i, s in enumerate(slope):
        state = state if s == 0 else s > 0
        heating[i] = state
    field = np.asarray(p.field_g, dtype=float)
    coupled = field if p.cross_axis is None else np.asarray(p.cross_axis, dtype=float) @ field
    out = {"t": t, "temp": np.round((chamber + rng.normal(0, p.temp_noise_c, t.size))
                                    / p.temp_resolution_c) * p.temp_resolution_c}
    full_scale = p.range_g * p.lsb_per_g
    for a, name in enumerate("xyz"):
        dT = die - 25.0
        gain = 1.0 + np.polynomial.polynomial.polyval(dT, p.gain_drift[a])
        value = gain * coupled[a] * p.lsb_per_g + p.cubic_lsb_per_g3[a] * field[a] ** 3 \
            + np.polynomial.polynomial.polyval(dT, p.offset_poly[a]) \
            + np.where(heating, 0.5, -0.5) * p.hysteresis_lsb[a] + rng.normal(0, p.noise_lsb, t.size)
        value = np.clip(value, -full_scale, full_scale)
        out[name] = np.clip(np.round(value), -32768, 32767).astype(np.int64)
        out["ref_" + name] = np.full(t.size, field[a] * p.lsb_per_g)
    return out


def write(path, p=ChamberParams()):
    data = simulate(p)
    write_csv(path, {c: data[c] for c in COLUMNS})
    return data
