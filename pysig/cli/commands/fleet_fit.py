"""`pysig fleet-fit LOG [LOG ...] --device serial --temp temp --columns x,y,z [--model auto|poly:N] -o DIR`

Calibrate a whole fleet from long-format logs (one row per device and
sample; CSV or Parquet files, or directories of them such as a Parquet
dataset partitioned by device).  Every device gets the temperature-
compensation fit of `pysig fit` (batched: all devices at once), written as
DIR/<device>.json and the NVM image DIR/<device>.bin, which carries the
device's serial: the firmware's loader, given its own serial, refuses
another unit's image (SIG_ERR_DEVICE).  DIR/fleet_summary.csv has one row
per device; a device is flagged when its fit error or drift lies outside
the fleet's median +- k*MAD or it could not be fitted (too few
temperatures, ...): the fleet goes on without it.  Fleet plots go to DIR.
DIR appears whole or not at all.

--engine dask runs the fit on Dask (a local cluster by default,
--scheduler ADDRESS for an existing one; needs pip install 'pysig[fleet]')."""
import time

import numpy as np

from ...errors import InputFileError, RangeError
from ...tcomp import MAX_FIT_ORDER
from ...fleet import DEFAULT_K, SUMMARY, write_fleet


def register(sub):
    p = sub.add_parser("fleet-fit", help="calibrate every device of a fleet log (models, images, screening)",
                       description=__doc__)
    p.add_argument("logs", nargs="+", metavar="LOG")
    p.add_argument("--device", required=True, help="column holding the device serial")
    p.add_argument("--temp", default="temp", help="temperature column, °C (default: temp)")
    p.add_argument("--columns", required=True, help="1 to 3 reading columns, comma separated")
    p.add_argument("--model", default="auto", help="auto (order by cross-validation) or poly:N (N = 1..8)")
    p.add_argument("--t0", type=float, default=25.0, help="reference temperature T0, °C (default 25)")
    p.add_argument("--k", type=float, default=DEFAULT_K,
                   help=f"flag outside median +- k*MAD (default {DEFAULT_K:g})")
    p.add_argument("--engine", choices=["local", "dask"], default="local")
    p.add_argument("--scheduler", default=None, help="Dask scheduler address (default: a local cluster)")
    p.add_argument("--workers", type=int, default=2, help="local Dask cluster: workers (default 2)")
    p.add_argument("--no-plots", action="store_true", help="skip the fleet plots")
    p.add_argument("-o", "--output", required=True, metavar="DIR")
    p.set_defaults(func=run)


def parse_model(text):
    text = text.strip().lower()
    if text == "auto":
        return "auto"
    if text.startswith("poly:"):
        try:
            n = int(text[5:])
        except ValueError:
            n = None
        if n is not None and 1 <= n <= MAX_FIT_ORDER:
            return n
    raise RangeError(f"fleet-fit: --model must be 'auto' or poly:N with N = 1..{MAX_FIT_ORDER}, got {text!r}")


def run(args):
    columns = [c.strip() for c in args.columns.split(",") if c.strip()]
    if not 1 <= len(columns) <= 3:
        raise InputFileError(f"fleet-fit: --columns needs 1 to 3 column names, got {args.columns!r}")
    model = parse_model(args.model)
    if not args.k > 0:
        raise RangeError(f"fleet-fit: --k must be > 0, got {args.k}")
    t_start = time.perf_counter()
    if args.engine == "dask":
        from ...fleet import connect, fit_fleet_dask
        with connect(args.scheduler, args.workers) as client:
            fit = fit_fleet_dask(args.logs, args.device, args.temp, columns, model, args.t0, client=client)
    else:
        from ...fleet import fit_fleet, load_fleet
        log = load_fleet(args.logs, args.device, args.temp, columns)
        fit = fit_fleet(log.dev, log.temp, log.values, log.devices, columns, model=model, t0=args.t0)
    t_fit = time.perf_counter()
    flagged, _, spread = write_fleet(fit, args.output, k=args.k, temp_column=args.temp,
                                     plots=not args.no_plots)
    t_end = time.perf_counter()
    orders = np.bincount(fit.order[fit.ok], minlength=2)
    print(f"fleet-fit: {len(fit.devices)} devices, {int(fit.ok.sum())} fitted "
          f"({', '.join(f'poly:{n} {c}' for n, c in enumerate(orders) if c)}), {int(flagged.sum())} flagged "
          f"(outside median +- k*MAD, k = {args.k:g}; or not fitted: {int((~fit.ok).sum())})")
    for name, (med, mad, _) in spread.items():
        print(f"  {name:>16}: median {med:.4g}, MAD {mad:.3g}")
    print(f"wrote {args.output}/ ({SUMMARY}, <device>.json/.bin per fitted device"
          f"{', plots' if not args.no_plots else ''}); read+fit {t_fit - t_start:.2f} s "
          f"({args.engine}), write {t_end - t_fit:.2f} s")
