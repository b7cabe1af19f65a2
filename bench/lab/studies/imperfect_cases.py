"""Generated records with the imperfections of real clean logs and NO
physical effect (only the static offset in temperature, optionally a drift
in time), for checking that refine claims nothing on them; and the same
records with one real effect (a thermal lag, a hysteresis), for checking
that it still finds that.

White Gaussian noise and a smooth drift (overlap_cases) are not what a real
log holds.  Here, every parameter drawn per seed from a range:

- noise: AR(1) (rho 0.5..0.99 at the sample rate) plus white noise;
- a drift in time: a random walk or 1/f (flicker) noise;
- a room / HVAC cycle on the reading (period 10..40 min, not tied to the
  temperature profile);
- quantisation: the reading to an ADC step of 0.7..3 x its noise, the
  temperature to 0.0625 °C (or a raw integer code of 16 per °C);
- gaps in time: two sessions joined (2..10 h apart), a missing hour,
  dropped samples, and jittered sample intervals.

Three temperature profiles refine is used on: a chamber ramping to targets
and holding (ramp_hold), a plate stepped 1 K at a time up and down (steps),
and an instrument roaming between cold and warm places (roaming).  Two
units: LSB with °C, mV with a raw temperature code.

A case is (label, truth, FitData) as in overlap_cases; truth["effects"] is
empty on the clean ones."""
import numpy as np

from pysig.refine import FitData
from pysig.refine._effect_models import first_order_lag, lag_alpha, play_operator
from lab.studies.overlap_cases import ramp_hold_profile, roaming_temperature

PROFILES = ("ramp_hold", "steps", "roaming")
IMPERFECTIONS = ("coloured", "walk", "room", "gaps", "all")
# (label, reading scale, reading offset, temperature code per °C or None for °C)
UNITS = (("LSB, °C in 0.0625 steps", 1.0, 2000.0, None),
         ("mV, raw temperature code (16/°C)", 0.05, 1650.0, 16.0))


def _profile(kind, rng):
    """(dt s, record length s, function of time -> temperature °C)."""
    if kind == "ramp_hold":
        dt, L = float(rng.choice([5.0, 10.0])), rng.uniform(5.0, 8.0) * 3600.0
        grid = np.arange(0.0, L + dt, dt)
        T = ramp_hold_profile(rng, grid)
        return dt, L, lambda t: np.interp(t, grid, T)
    if kind == "steps":
        dt, hold = float(rng.choice([2.0, 5.0])), rng.uniform(240.0, 360.0)
        levels = np.concatenate([np.arange(20, 36), np.arange(34, 19, -1)] * 2).astype(float)
        L = hold * levels.size
        grid = np.arange(0.0, L + dt, dt)
        setpoint = levels[np.minimum((grid // hold).astype(int), levels.size - 1)]
        T = first_order_lag(setpoint, lag_alpha(rng.uniform(2.0, 5.0), dt))
        return dt, L, lambda t: np.interp(t, grid, T)
    if kind == "roaming":
        dt, L = 60.0, rng.uniform(24.0, 36.0) * 3600.0
        grid = np.arange(0.0, L + dt, dt)
        T = roaming_temperature(rng, grid.size, dt)
        return dt, L, lambda t: np.interp(t, grid, T)
    raise ValueError(kind)


def sample_times(rng, dt, L, gaps, jitter):
    """Sample times over [0, L): jittered intervals (+-30 % of dt, 2 % of
    samples dropped) when `jitter`; with `gaps`, a missing hour inside the
    record and a second session 2..10 h after the first (the time of the
    second session's samples shifted by the gap).  Returns (profile time,
    clock time): the profile pauses over the gap between sessions."""
    t = np.arange(0.0, L, dt)
    if jitter:
        t = t + rng.uniform(-0.3, 0.3, t.size) * dt
        t = np.sort(t[rng.random(t.size) >= 0.02])
        t = t[(t >= 0.0) & (t < L)]
    if gaps:
        start = rng.uniform(0.2, 0.35) * L
        t = t[(t < start) | (t >= start + 3600.0)]
        split = rng.uniform(0.55, 0.7) * L
        return t, np.where(t >= split, t + rng.uniform(2.0, 10.0) * 3600.0, t)
    return t, t


def ar1(rng, n, rho, sigma):
    """AR(1) noise of stationary standard deviation `sigma`, per sample."""
    e = rng.standard_normal(n) * sigma * np.sqrt(1.0 - rho ** 2)
    z = np.empty(n)
    z[0] = rng.standard_normal() * sigma
    for k in range(1, n):
        z[k] = rho * z[k - 1] + e[k]
    return z


def slow_noise(rng, t, size):
    """A drift in time of about `size` RMS: a random walk, or 1/f noise
    (a spectrum shaped on a uniform grid over the span, interpolated)."""
    span = t[-1] - t[0]
    grid = np.linspace(t[0], t[-1], 4096)
    if rng.random() < 0.5:
        walk = np.cumsum(rng.standard_normal(grid.size))
    else:
        f = np.fft.rfftfreq(grid.size, d=span / grid.size)
        amp = np.zeros(f.size)
        amp[1:] = 1.0 / np.sqrt(f[1:])
        walk = np.fft.irfft(amp * np.exp(2j * np.pi * rng.random(f.size)), grid.size)
    walk = walk - walk.mean()
    return np.interp(t, grid, size * walk / (walk.std() or 1.0))


def room_cycle(rng, t, size):
    """An HVAC cycle on the reading: a period of 10..40 min that wanders by
    +-10 %, an asymmetric (thermostat-like) wave of amplitude `size`."""
    period = rng.uniform(600.0, 2400.0)
    phase = 2 * np.pi * np.cumsum(np.r_[0.0, np.diff(t)]) / period
    phase = phase + 0.1 * 2 * np.pi * np.sin(2 * np.pi * t / rng.uniform(3.0, 6.0) / period)
    phase = phase + rng.uniform(0, 2 * np.pi)
    return size * (np.sin(phase) + 0.35 * np.sin(2 * phase + rng.uniform(0, 2 * np.pi)))


def imperfect_case(imperfection, profile="ramp_hold", seed=0, unit=UNITS[0], effect=None):
    """One record: the static offset of the sensor's temperature (about
    1.5 LSB/°C, curved), the imperfections of `imperfection` (one of
    IMPERFECTIONS, or several joined by "+"; every record has AR(1) + white
    noise and quantisation),
    and `effect` (None, "thermal_lag" of 1/80..1/30 of the record, or
    "hysteresis" of 20..60 % of the span, 4 LSB) when the check is for power."""
    rng = np.random.default_rng(seed)
    dt, L, temp_of = _profile(profile, rng)
    use = set(IMPERFECTIONS) if imperfection == "all" else set(imperfection.split("+"))
    t_profile, t_phys = sample_times(rng, dt, L, "gaps" in use, "gaps" in use)
    T_true = temp_of(t_profile)
    truth = {"effects": {}, "drift": "walk" in use}
    T_sensor = T_true
    if effect == "thermal_lag":
        tau = L * rng.uniform(1 / 80, 1 / 30)
        fine = np.arange(t_phys[0], t_phys[-1] + dt, dt / 4)
        T_fine = np.interp(fine, t_phys, T_true)
        T_sensor = np.interp(t_phys, fine, first_order_lag(T_fine, lag_alpha(tau, dt / 4)))
        truth["effects"]["thermal_lag"] = {"tau_s": tau}
    y = 1.5 * (T_sensor - 25.0) + 0.006 * (T_sensor - 25.0) ** 2
    if effect == "hysteresis":
        w = float(np.ptp(T_sensor)) * rng.uniform(0.2, 0.6)
        y = y + 4.0 * (T_sensor - play_operator(T_sensor, w)) / w
        truth["effects"]["hysteresis"] = {"width": w}
    white = rng.uniform(0.3, 1.5)
    rho = rng.uniform(0.5, 0.99)
    coloured = white * rng.uniform(0.5, 2.0) if use & {"coloured", "all"} else white * rng.uniform(0.2, 0.6)
    y = y + white * rng.standard_normal(t_phys.size) + ar1(rng, t_phys.size, rho, coloured)
    noise_sd = float(np.hypot(white, coloured))
    if "walk" in use:
        y = y + slow_noise(rng, t_phys, noise_sd * rng.uniform(1.0, 4.0))
    if "room" in use:
        y = y + room_cycle(rng, t_phys, noise_sd * rng.uniform(0.5, 2.0))
    name, y_scale, y_off, code = unit
    lsb = noise_sd * rng.uniform(0.7, 3.0) * y_scale
    reading = lsb * np.round((y_off + y_scale * y) / lsb)
    temp = T_true + 0.02 * rng.standard_normal(t_phys.size)
    temp_out = np.round(temp * 16.0) / 16.0 if code is None else np.round(temp * code)
    t_scale = 1.0 if code is None else code
    if "hysteresis" in truth["effects"]:
        truth["effects"]["hysteresis"]["width"] *= t_scale
    truth["scale"] = {"reading": y_scale, "temperature": t_scale}
    truth["imperfections"] = {"rho": rho, "white": white, "coloured": coloured, "adc_step": lsb / y_scale,
                              "dt": dt, "samples": int(t_phys.size)}
    label = (f"{effect or 'clean'} imperfect: {imperfection}, {profile}, {name}, rho {rho:.2f}, "
             f"ADC step {lsb / y_scale:.2g} LSB, seed {seed}")
    return label, truth, FitData(y=reading, t=t_phys, T=temp_out, labels={"unit": name.split(",")[0]})


def imperfect_clean_cases(seeds=range(10), imperfections=IMPERFECTIONS):
    """Every imperfection over `seeds`; the profile and the unit turn with the seed."""
    for imp in imperfections:
        for seed in seeds:
            yield imperfect_case(imp, PROFILES[seed % len(PROFILES)], seed=seed,
                                 unit=UNITS[(seed // len(PROFILES)) % len(UNITS)])


def imperfect_effect_cases(seeds=range(3), effects=("thermal_lag", "hysteresis")):
    """The same imperfections (all at once) with one real effect."""
    for effect in effects:
        for seed in seeds:
            yield imperfect_case("all", PROFILES[seed % len(PROFILES)], seed=100 + seed,
                                 unit=UNITS[seed % len(UNITS)], effect=effect)
