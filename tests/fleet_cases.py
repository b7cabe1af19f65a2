"""Generated fleet logs for the fleet tests: devices with their own offset,
slope and curvature per axis, chamber plateaus or ramps, noise, and the
troubles a production line meets."""
import numpy as np

from pysig.io import write_csv


def fleet_rows(n_dev=40, temps=(0.0, 25.0, 50.0, 70.0), per_temp=12, seed=0, noise=2.0,
               ramp_devices=(), few_temp_devices=(), stray_devices=()):
    """(serial, temp, x, y, z) arrays.  ramp_devices log a continuous ramp
    (cut into pieces by the grouping rule); few_temp_devices only the first
    two plateaus; stray_devices a few start-up samples far from a plateau."""
    rng = np.random.default_rng(seed)
    serial, temp = [], []
    for d in range(n_dev):
        if d in ramp_devices:
            t = np.linspace(temps[0], temps[-1], per_temp * len(temps))
        else:
            plate = temps[:2] if d in few_temp_devices else temps
            t = np.repeat(plate, per_temp) + rng.normal(0, 0.03, per_temp * len(plate))
            if d in stray_devices:
                t = np.r_[t, [temps[-1] + 3.0]]
        serial += [f"SN-{d:04d}"] * t.size
        temp.append(t)
    temp = np.concatenate(temp)
    serial = np.array(serial, dtype=object)
    dev = np.unique(serial, return_inverse=True)[1]
    off = rng.normal(0, 300, (n_dev, 3))
    s1 = rng.normal(1.0, 0.3, (n_dev, 3))
    s2 = rng.normal(0.01, 0.002, (n_dev, 3))
    y = off[dev] + s1[dev] * temp[:, None] + s2[dev] * temp[:, None] ** 2
    y = np.round(y + rng.normal(0, noise, y.shape))
    return serial, temp, y


def write_fleet_log(path, serial, temp, y, device="serial"):
    write_csv(path, {device: serial, "temp": temp, "x": y[:, 0], "y": y[:, 1], "z": y[:, 2]})
    return path
