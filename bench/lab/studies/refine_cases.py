"""Small synthetic chamber runs for the refine tests: a temperature profile
with ramps at different rates and holds (so a lag, which decays during a
hold, can be told from hysteresis, which stays), a rotating reference field,
and one injected effect the fit is not told about.  Written here, in plain
numpy, so the loop's tests do not depend on the simulators' defaults; the
simulator-based tests are in test_refine_sim.py."""
import numpy as np

from pysig.refine import _effect_models as fx

# (duration s, target °C): ramps at 0.1, 0.05, 0.2 and 0.1 °C/s between holds
PROFILE = ((300, 0.0), (500, 50.0), (300, 50.0), (800, 10.0), (300, 10.0),
           (150, 40.0), (300, 40.0), (400, 0.0), (250, 0.0))
EFFECTS = ("gain_drift", "thermal_lag", "hysteresis", "nonlinearity", "cross_axis")
WARM_UP_TAU_S = 300.0          # the "warm_up" case: 8 LSB decaying after power-on


def temperature_profile(dt=1.0, start=0.0):
    t_knots, T_knots = [0.0], [start]
    for dur, target in PROFILE:
        t_knots.append(t_knots[-1] + dur)
        T_knots.append(target)
    t = np.arange(0.0, t_knots[-1], dt)
    return t, np.interp(t, t_knots, T_knots)


def chamber_run(effect=None, seed=0, noise=1.0, t_noise=0.02, dt=2.0, constant_field=False):
    """dict t, temp, x, ref, ref_y, ref_z; `effect`: one name or a tuple of
    names, None for clean data, "step" for a step in time outside the library."""
    rng = np.random.default_rng(seed)
    names = (effect,) if isinstance(effect, str) or effect is None else tuple(effect)
    t, T_true = temperature_profile(dt)
    n = t.size
    if constant_field:
        r = np.full(n, 250.0)
    else:
        r = 300.0 * np.sin(2 * np.pi * t / 97.0)
    ry = 300.0 * np.cos(2 * np.pi * t / 97.0)
    rz = 200.0 * np.sin(2 * np.pi * t / 331.0 + 0.4)
    T_sensor = T_true
    if "thermal_lag" in names:
        T_sensor = fx.first_order_lag(T_true, fx.lag_alpha(90.0, dt))
    offset = 30.0 + 1.5 * (T_sensor - 25.0) + 0.004 * (T_sensor - 25.0) ** 2
    y = 1.03 * r + offset
    if "gain_drift" in names:
        y += r * 0.0015 * (T_sensor - 25.0)
    if "hysteresis" in names:
        w = 0.8
        y += 5.0 * (T_sensor - fx.play_operator(T_sensor, w)) / w
    if "nonlinearity" in names:
        y += 2e-4 * r ** 2
    if "cross_axis" in names:
        y += 0.03 * ry - 0.02 * rz
    if "warm_up" in names:
        y += 8.0 * np.exp(-t / WARM_UP_TAU_S)
    if "step" in names:
        y += np.where(t > t[-1] * 0.55, 8.0, 0.0)
    unknown = set(names) - set(EFFECTS) - {None, "step", "warm_up"}
    if unknown:
        raise ValueError(unknown)
    y = y + noise * rng.standard_normal(n)
    temp = T_true + t_noise * rng.standard_normal(n)
    return {"t": t, "temp": temp, "x": y, "ref": r, "ref_y": ry, "ref_z": rz}


def fit_data(run, use_ref=True, others=("ref_y", "ref_z")):
    return fx.FitData(y=run["x"], t=run["t"], T=run["temp"],
                      r=run["ref"] if use_ref else None,
                      others={k: run[k] for k in others})


def loadcell_creep_run(seed=0, loads=(0.0, 50.0, 0.0, 50.0), hold_s=1200.0, rate_hz=10.0,
                       creep_frac=4e-4, creep_tau_s=300.0, noise_counts=25.0,
                       impulse_frac=0.002, impulse_counts=(2000.0, 20000.0)):
    """A load-cell run from the load-cell simulator, scaled like an HX711
    (pga 4: about 2 000 counts per kg): `loads` (kg) each held `hold_s`,
    creep of `creep_frac` of each step with time constant `creep_tau_s`,
    white noise of `noise_counts`, and read impulses on `impulse_frac` of
    the samples, of uniform size in `impulse_counts` and random sign (what
    real HX711 read glitches look like).  Returns dict t, counts, ref_kg,
    impulse (bool: the samples hit)."""
    from pysig.sim._loadcell import LoadCellParams, simulate
    steps = tuple((i * hold_s, float(kg)) for i, kg in enumerate(loads))
    base = LoadCellParams(pga_gain=4.0)
    noise_uv = noise_counts * base.lsb_v * 1e6
    run = simulate(base, seed=seed, rate_hz=rate_hz, duration_s=hold_s * len(loads),
                   load_steps=steps, noise_uv_rms=noise_uv, creep_frac=creep_frac,
                   creep_tau_s=creep_tau_s)
    rng = np.random.default_rng(10_000 + seed)
    n = run["counts"].size
    hit = rng.random(n) < impulse_frac
    size = rng.uniform(*impulse_counts, n) * np.where(rng.random(n) < 0.5, -1.0, 1.0)
    counts = run["counts"].astype(float) + np.where(hit, np.rint(size), 0.0)
    return {"t": run["t"], "counts": counts, "ref_kg": run["ref_kg"], "impulse": hit}
