"""Load-cell simulator: what the weighing paper's scale hardware would hand the filter.

An L6D-like strain-gauge cell (about 0.15 mV/kg at its excitation, rated
2.5-50 kg) feeds a 24-bit ADS1232-like ADC: full scale +-0.5*Vref/PGA, one
code = 0.5*Vref/PGA/2^23, codes rounded and clipped at the rails
[-2^23, 2^23 - 1], 10 or 80 samples/s.  With the defaults (Vref 5 V, PGA 128)
one code is 2.33 nV and 1 kg is about 64 400 codes.

Every disturbance is a parameter of LoadCellParams and is off (zero) unless
set, so a run contains exactly what its parameters say:

  noise_uv_rms         Gaussian white noise at the ADC input (uV rms).
  vibration_g_rms      floor vibration: white vertical acceleration (g rms)
                       acting on the load, so the cell sees load * a extra kg:
                       noise proportional to the load.
  impulse_rate_hz      impulse interference: each sample is hit with
  impulse_amp_uv       probability rate/fs; the amplitude is uniform in
  impulse_polarity     [amp/2, amp], sign +, - or random ("both").
  periodic_amp_uv      periodic interference, e.g. mains pickup left over
  periodic_hz          after the ADC's sinc filter: a sine of the physical
                       frequency sampled at the sample instants, so it
                       aliases (50.2 Hz at 10 samples/s shows up at 0.2 Hz).
  drift_uv_per_min     slow zero drift: a linear ramp ...
  drift_rw_uv          ... plus a random walk of this step per sqrt(second).
  load_steps           ((t_s, kg), ...): the load is piecewise constant,
                       `kg` from `t_s` on (put on and taken off by hand).
  creep_frac           creep: after a load change of dm the cell reads an
  creep_tau_s          extra dm*creep_frac*(1 - exp(-dt/tau)) kg.
  nonlinearity_frac_fs terminal nonlinearity: a parabolic bow through 0 and
                       capacity_kg whose peak (at half capacity) is this
                       fraction of the full-scale output.
  ringing_frac         motion after a load change (the load swings): a
  ringing_hz           damped sine of amplitude ringing_frac*dm kg,
  ringing_tau_s        frequency ringing_hz and decay time ringing_tau_s.

The CSV (write_run) has the columns t, counts, ref_kg; ref_kg is the load
applied (without creep, ringing or noise): the truth a scale should show.
"""
from dataclasses import dataclass, fields, replace

import numpy as np

from ..errors import RangeError
from ..io import write_csv

ADC_MIN = -(1 << 23)
ADC_MAX = (1 << 23) - 1
# A run is built in memory (about a dozen float64 arrays of its length): 10^7
# samples, 11.6 days at 10 samples/s or 35 h at 80, need about 1 GB.
MAX_SAMPLES = 10_000_000


@dataclass(frozen=True)
class LoadCellParams:
    # cell
    sensitivity_mv_per_kg: float = 0.15
    zero_offset_mv: float = 0.2          # bridge output at no load
    capacity_kg: float = 50.0
    # ADC (ADS1232-like)
    pga_gain: float = 128.0
    vref_v: float = 5.0
    rate_hz: float = 10.0
    # run
    duration_s: float = 30.0
    load_steps: tuple = ((0.0, 0.0),)
    # disturbances, all off by default
    noise_uv_rms: float = 0.0
    vibration_g_rms: float = 0.0
    impulse_rate_hz: float = 0.0
    impulse_amp_uv: float = 0.0
    impulse_polarity: str = "both"
    periodic_amp_uv: float = 0.0
    periodic_hz: float = 50.2
    drift_uv_per_min: float = 0.0
    drift_rw_uv: float = 0.0
    creep_frac: float = 0.0
    creep_tau_s: float = 60.0
    nonlinearity_frac_fs: float = 0.0
    ringing_frac: float = 0.0
    ringing_hz: float = 1.5
    ringing_tau_s: float = 0.5

    def __post_init__(self):
        for name in ("sensitivity_mv_per_kg", "capacity_kg", "pga_gain", "vref_v", "rate_hz",
                     "duration_s", "creep_tau_s", "ringing_tau_s"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v > 0):
                raise RangeError(f"LoadCellParams.{name} must be finite and > 0, got {v!r}")
        for f in fields(self):
            v = getattr(self, f.name)
            if isinstance(v, float) and not np.isfinite(v):
                raise RangeError(f"LoadCellParams.{f.name} must be finite, got {v!r}")
        for name in ("noise_uv_rms", "vibration_g_rms", "impulse_rate_hz", "impulse_amp_uv", "periodic_amp_uv",
                     "drift_rw_uv", "ringing_frac"):
            if getattr(self, name) < 0:
                raise RangeError(f"LoadCellParams.{name} must be >= 0, got {getattr(self, name)!r}")
        samples = self.duration_s * self.rate_hz
        if samples > MAX_SAMPLES:
            raise RangeError(f"LoadCellParams: duration_s={self.duration_s:g} s at rate_hz={self.rate_hz:g} is "
                             f"{samples:.3g} samples, more than the {MAX_SAMPLES:,} a run may have")
        if self.impulse_rate_hz > self.rate_hz:
            raise RangeError(f"LoadCellParams.impulse_rate_hz {self.impulse_rate_hz} exceeds "
                             f"the sample rate {self.rate_hz}")
        if self.impulse_polarity not in ("+", "-", "both"):
            raise RangeError(f"LoadCellParams.impulse_polarity must be '+', '-' or 'both', "
                             f"got {self.impulse_polarity!r}")
        if not self.load_steps:
            raise RangeError("LoadCellParams.load_steps is empty: give at least ((0.0, kg),)")
        times = [float(t) for t, _ in self.load_steps]
        if times[0] > 0 or any(b <= a for a, b in zip(times, times[1:])):
            raise RangeError(f"LoadCellParams.load_steps times must start at <= 0 and increase, got {times}")

    @property
    def lsb_v(self):
        """Volts per ADC code: full scale 0.5*Vref/PGA over 2^23 codes."""
        return 0.5 * self.vref_v / self.pga_gain / float(1 << 23)

    @property
    def counts_per_kg(self):
        """Nominal (linear) sensitivity in codes per kg."""
        return self.sensitivity_mv_per_kg * 1e-3 / self.lsb_v

    @property
    def zero_counts(self):
        """Nominal code at no load, before drift."""
        return self.zero_offset_mv * 1e-3 / self.lsb_v

    def uv_per_kg(self):
        return self.sensitivity_mv_per_kg * 1e3


def load_profile(params, t):
    """Applied load (kg) at times t, and the (time, change) list of steps."""
    times = np.array([float(s[0]) for s in params.load_steps])
    kgs = np.array([float(s[1]) for s in params.load_steps])
    idx = np.searchsorted(times, t, side="right") - 1
    ref = kgs[np.clip(idx, 0, None)]
    changes = [(times[i], kgs[i] - kgs[i - 1]) for i in range(1, len(times))]
    return ref, changes


def simulate(params=None, seed=0, **overrides):
    """Simulate one load-cell run.

    Parameters
    ----------
    params : LoadCellParams, optional
        The cell, ADC, load steps and disturbances (LoadCellParams() when
        None: a still, noiseless 0 kg for 30 s).
    seed : int, optional
        The same params and seed give the same run, bit for bit.
    **overrides
        Fields of LoadCellParams replacing those of `params`.

    Returns
    -------
    dict
        t (s), counts (int32 ADC codes, clipped at the 24-bit rails),
        ref_kg (the load applied: the truth a scale should show).

    Raises
    ------
    RangeError
        A parameter outside its range (named), e.g. a rate of 0.

    Examples
    --------
    >>> import numpy as np
    >>> run = simulate(seed=1, load_steps=((0.0, 0.0), (5.0, 20.0)), duration_s=10.0,
    ...                noise_uv_rms=0.3)
    >>> run["t"].size, run["counts"].dtype, run["ref_kg"][-1]
    (100, dtype('int32'), np.float64(20.0))
    >>> step = run["counts"][-10:].mean() - run["counts"][:10].mean()
    >>> round(float(step / LoadCellParams().counts_per_kg), 1)        # kg
    20.0
    >>> simulate(rate_hz=0.0)
    Traceback (most recent call last):
        ...
    pysig.errors.RangeError: LoadCellParams.rate_hz must be finite and > 0, got 0.0
    """
    if params is None:
        params = LoadCellParams(**overrides)
    elif overrides:
        params = replace(params, **overrides)
    p = params
    rng = np.random.default_rng(seed)
    n = int(round(p.duration_s * p.rate_hz))
    t = np.arange(n) / p.rate_hz
    ref_kg, changes = load_profile(p, t)

    # every random draw first, in a fixed order, so that a seed gives the same
    # numbers whichever disturbances are switched on
    white = rng.standard_normal(n)
    hit = rng.random(n) < p.impulse_rate_hz / p.rate_hz
    amp = rng.uniform(0.5, 1.0, n)
    sign = np.where(rng.random(n) < 0.5, -1.0, 1.0)
    walk = rng.standard_normal(n)
    phase = rng.uniform(0.0, 2 * np.pi)
    accel = rng.standard_normal(n)

    # mechanical part, in kg seen by the cell
    kg = ref_kg.astype(float)
    for t0, dm in changes:
        dt = t - t0
        after = dt >= 0
        if p.creep_frac:
            kg[after] += dm * p.creep_frac * (1.0 - np.exp(-dt[after] / p.creep_tau_s))
        if p.ringing_frac:
            kg[after] += (dm * p.ringing_frac * np.exp(-dt[after] / p.ringing_tau_s)
                          * np.sin(2 * np.pi * p.ringing_hz * dt[after]))
    if p.vibration_g_rms:
        kg += ref_kg * p.vibration_g_rms * accel

    # bridge output (uV): linear sensitivity plus the terminal bow
    uv = p.zero_offset_mv * 1e3 + p.uv_per_kg() * kg
    if p.nonlinearity_frac_fs:
        x = kg / p.capacity_kg
        uv += 4.0 * p.nonlinearity_frac_fs * p.uv_per_kg() * p.capacity_kg * x * (1.0 - x)

    # electrical disturbances at the ADC input (uV)
    uv += p.noise_uv_rms * white
    if p.impulse_polarity != "both":
        sign = np.full(n, 1.0 if p.impulse_polarity == "+" else -1.0)
    uv += np.where(hit, p.impulse_amp_uv * amp * sign, 0.0)
    uv += p.periodic_amp_uv * np.sin(2 * np.pi * p.periodic_hz * t + phase)
    uv += p.drift_uv_per_min * t / 60.0
    if p.drift_rw_uv:
        uv += np.cumsum(walk) * p.drift_rw_uv / np.sqrt(p.rate_hz)

    codes = np.clip(np.rint(uv * 1e-6 / p.lsb_v), ADC_MIN, ADC_MAX).astype(np.int32)
    return {"t": t, "counts": codes, "ref_kg": ref_kg}


def write_run(path, run):
    """Write a run as CSV t, counts, ref_kg (atomically)."""
    write_csv(path, {"t": run["t"], "counts": run["counts"], "ref_kg": run["ref_kg"]})
