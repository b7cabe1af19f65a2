"""A reference for a weighing log given without one: the held load levels."""
import numpy as np

from ..errors import InsufficientDataError


def plateau_reference(y, t):
    """Reference for a weighing run given without --ref and --temp: the
    level of each held load (pysig.weigh._calibration.find_plateaus, median of the
    plateau).  Samples between plateaus (the load moving) and read glitches
    are masked out of fitting and scoring; the reference steps to the next
    level where the transition starts, so a creep term sees the step.
    Returns (reference, mask, number of plateaus)."""
    from ..weigh._calibration import find_plateaus, glitch_indices
    y = np.asarray(y, dtype=float)
    dt = float(np.median(np.diff(t)))
    plateaus = find_plateaus(y, 1.0 / dt)
    if len(plateaus) < 2:
        raise InsufficientDataError(
            f"refine: without --ref and --temp the reference is the held load levels, "
            f"and {len(plateaus)} plateau(s) were found; need at least 2 (or give --ref)")
    r = np.empty(y.size)
    mask = np.zeros(y.size, dtype=bool)
    start = 0
    for p in plateaus:
        r[start:p.stop] = p.level
        mask[p.start:p.stop] = True
        start = p.stop
    r[start:] = plateaus[-1].level
    mask[glitch_indices(y)] = False
    return r, mask, len(plateaus)
