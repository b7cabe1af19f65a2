"""`pysig chamber -o chamber.csv [--seed N] [--profile steps|ramp] [--lag S] [--hysteresis LSB]`

Simulate a thermal-chamber run of a QMC5883L-like magnetometer
(pysig.sim._chamber): CSV t, temp, x, y, z, ref_x, ref_y, ref_z, ready for
`pysig fit chamber.csv --columns x,y,z`."""
import math

from ...sim import ChamberParams, write_chamber_run
from ...errors import RangeError


def register(sub):
    p = sub.add_parser("chamber", help="simulate a thermal-chamber run (CSV)", description=__doc__)
    p.add_argument("-o", "--output", required=True, metavar="chamber.csv")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--profile", choices=("steps", "ramp"), default="steps",
                   help="chamber steps at 0/25/50/70 °C (default) or a ramp up and down")
    p.add_argument("--dwell", type=float, default=1800.0, help="seconds on each plateau")
    p.add_argument("--lag", type=float, default=0.0, help="thermal lag time constant, s (0: off)")
    p.add_argument("--hysteresis", type=float, default=0.0,
                   help="heating/cooling offset difference on every axis, LSB (0: off)")
    p.set_defaults(func=run)


def run(args):
    # math.isfinite first: NaN passes any comparison-based check
    for name, value, rule, ok in (("--dwell", args.dwell, "finite and > 0", args.dwell > 0),
                                  ("--lag", args.lag, "finite and >= 0", args.lag >= 0),
                                  ("--hysteresis", args.hysteresis, "finite", True)):
        if not (math.isfinite(value) and ok):
            raise RangeError(f"{name} must be {rule}, got {value}")
    params = ChamberParams(seed=args.seed, profile=args.profile, dwell_s=args.dwell,
                                       thermal_lag_s=args.lag, hysteresis_lsb=(args.hysteresis,) * 3)
    data = write_chamber_run(args.output, params)
    print(f"wrote {args.output}: {data['t'].size} samples, {data['temp'].min():.2f}..{data['temp'].max():.2f} °C")
