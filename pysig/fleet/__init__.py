"""Fleet calibration: many devices of one log (or many logs) fitted at once,
screened, and written as one model and one device-bound NVM image each.

===============  ============================================================
load_fleet       read and check every log (devices sorted by serial)
fit_fleet        the batched fit of every device (numpy, no per-device loop);
                 equal to the single-device fit of pysig.tcomp
fit_fleet_dask   the same fit on a Dask cluster (optional extra ``fleet``)
connect          a Dask client (local, or a scheduler address)
write_fleet      per-device models and images, the summary CSV with its
                 screening, fleet plots; written atomically
DEFAULT_K        the screening band's width (in robust standard deviations)
SUMMARY          the summary file's name
===============  ============================================================
"""
from ._data import load_fleet
from ._fit import fit_fleet
from ._report import DEFAULT_K, SUMMARY, write_fleet

__all__ = ["load_fleet", "fit_fleet", "fit_fleet_dask", "connect", "write_fleet", "DEFAULT_K", "SUMMARY"]


def __getattr__(name):
    # Dask is an optional extra and slow to import: loaded only when asked for.
    if name in ("fit_fleet_dask", "connect"):
        from . import _dask
        return getattr(_dask, name)
    raise AttributeError(f"module 'pysig.fleet' has no attribute {name!r}")
