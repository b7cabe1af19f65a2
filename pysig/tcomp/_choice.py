"""Choosing a temperature model's family and size from the data, and saying
where the calibration is weak.

* `prepare`: samples averaged per distinct temperature (per int16 t: 0.01 °C
  or one raw code), so a temperature the board crossed slowly does not
  outweigh the others (PX4 bins for the same reason); whole-degree logs
  become one point per degree.  Said in `notes`.
* `score`: blocked cross-validation over temperature
  (pysig.tcomp._cross_validation.cross_validate: interior blocks of the range held
  out in turn) for every candidate family and size, per axis; the pooled CV
  RMS over the axes ranks them.
* `choose`: of the candidates within 5 % of the best pooled CV RMS, the
  cheapest on the MCU (pysig.tcomp._cost: cycles, then bytes).
* `coverage`: gaps wider than a CV block and blocks with too few points.
* `hysteresis`: with heating and cooling in one log, the difference between
  the branches per axis."""
from dataclasses import dataclass, field

import numpy as np

from . import _cost as mcu_cost
from ._cross_validation import blocked_folds, cross_validate, poly_fitter, pwl_fitter
from ..errors import InsufficientDataError

N_BLOCKS = 8
TOLERANCE = 0.05
MIN_BLOCK_POINTS = 3
POLY_ORDERS = tuple(range(1, 9))
MAX_POINTS = 2000
MIN_RUN = 20          # samples per heating or cooling run, on average, for a log in time order
TABLE_SIZES = (2, 3, 4, 5, 6, 8, 9, 12, 17, 24, 33, 48, 65, 97, 129)


@dataclass(frozen=True)
class Prepared:
    """Averaged calibration points: x in the model's float unit (sorted),
    values per axis, samples per point."""
    x: np.ndarray
    columns: dict
    counts: np.ndarray
    notes: tuple


def prepare(temp, columns, temp_code):
    """Average the samples per distinct int16 temperature t."""
    t = temp_code.to_t(temp, "raise")
    keys, inverse, counts = np.unique(t, return_inverse=True, return_counts=True)
    x = keys / temp_code.units_per_degree
    avg = {n: np.bincount(inverse, weights=np.asarray(y, float)) / counts for n, y in columns.items()}
    notes = []
    if keys.size < t.size:
        unit = "0.01 °C" if temp_code.unit == "c" else "code"
        notes.append(f"{t.size} samples averaged into {keys.size} temperatures (one per distinct {unit}, "
                     f"{counts.min()}..{counts.max()} samples each)")
    if keys.size > MAX_POINTS:
        # a long log at fine resolution: equal-width bins keep CV fast
        edges = np.linspace(x[0], x[-1], MAX_POINTS + 1)
        b = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, MAX_POINTS - 1)
        used = np.unique(b)
        x = np.array([np.mean(x[b == k]) for k in used])
        avg = {n: np.array([np.mean(v[b == k]) for k in used]) for n, v in avg.items()}
        counts = np.array([int(np.sum(counts[b == k])) for k in used])
        notes.append(f"then averaged into {used.size} temperature bins of {edges[1] - edges[0]:.4g} "
                     f"(at most {MAX_POINTS})")
    raw = np.asarray(temp, dtype=float)
    if temp_code.unit == "c" and keys.size > 1 and np.all(raw == np.round(raw)):
        notes.append("temperatures are whole degrees: averaged per distinct temperature "
                     f"({keys.size} of them)")
    return Prepared(x=x, columns=avg, counts=counts, notes=tuple(notes))


@dataclass
class Candidate:
    family: str
    size: int
    cv_rms: float = float("nan")          # pooled over axes
    cv_axis: dict = field(default_factory=dict)
    fold_rms: dict = field(default_factory=dict)
    refused: str = ""

    @property
    def label(self):
        return f"poly:{self.size}" if self.family == "poly" else f"table:{self.size}"

    def cost(self, n_axes):
        c = mcu_cost.cost(self.family, self.size)
        return c.cycles * n_axes, c.data_bytes * n_axes


def candidates(family, size, n_points):
    """Candidate list for a family ('poly', 'table', 'auto') and a size
    (int, or 'auto' for every size the points allow)."""
    fams = ("poly", "table") if family == "auto" else (family,)
    out = []
    for fam in fams:
        sizes = (POLY_ORDERS if fam == "poly" else TABLE_SIZES) if size == "auto" else (size,)
        for s in sizes:
            if fam == "poly" and s + 1 > n_points or fam == "table" and s > n_points:
                continue
            out.append(Candidate(fam, int(s)))
    return out


def cv_possible(prep, groups_count):
    """Blocked CV needs 3 temperature groups and data in an interior block."""
    if groups_count < 3:
        return False
    try:
        blocked_folds(prep.x, N_BLOCKS)
    except InsufficientDataError:
        return False
    return True


def score(prep, cands):
    """Fill cv_rms / cv_axis / fold_rms (or `refused`) of each candidate."""
    for c in cands:
        fitter = poly_fitter(c.size) if c.family == "poly" else pwl_fitter(c.size)
        try:
            for name, y in prep.columns.items():
                rms, folds = cross_validate(fitter, prep.x, y, N_BLOCKS)
                c.cv_axis[name] = rms
                c.fold_rms[name] = folds
        except (InsufficientDataError, np.linalg.LinAlgError, ValueError) as exc:
            c.refused = str(exc)
            continue
        c.cv_rms = float(np.sqrt(np.mean([v ** 2 for v in c.cv_axis.values()])))
    return cands


def eligible(cands, tolerance=TOLERANCE):
    """Scored candidates within `tolerance` of the best pooled CV RMS."""
    ok = [c for c in cands if not c.refused and np.isfinite(c.cv_rms)]
    if not ok:
        return []
    best = min(c.cv_rms for c in ok)
    return [c for c in ok if c.cv_rms <= best * (1 + tolerance)]


def by_cost(cands, n_axes, prefer="cycles"):
    return sorted(cands, key=lambda c: (mcu_cost.cost_key(c.family, c.size, prefer), c.cv_rms))


def block_edges(prep):
    lo, hi = float(prep.x.min()), float(prep.x.max())
    return np.linspace(lo, hi, N_BLOCKS + 1)


def coverage(prep):
    """Warnings (text) about where the calibration is thin: the widest gap
    between calibration temperatures if it exceeds a CV block, and blocks
    holding fewer than MIN_BLOCK_POINTS temperatures."""
    edges = block_edges(prep)
    width = edges[1] - edges[0]
    out = []
    gaps = np.diff(prep.x)
    for i in np.flatnonzero(gaps > width):
        out.append(("gap", float(prep.x[i]), float(prep.x[i + 1]),
                    f"no calibration temperature between {{lo}} and {{hi}}: a gap of {gaps[i]:.4g}, wider "
                    f"than a CV block ({width:.4g}); the model is unvalidated there"))
    block = np.minimum(((prep.x - edges[0]) / width).astype(int), N_BLOCKS - 1)
    for b in range(N_BLOCKS):
        n = int(np.count_nonzero(block == b))
        if 0 < n < MIN_BLOCK_POINTS:
            out.append(("thin", float(edges[b]), float(edges[b + 1]),
                        f"block {{lo}}..{{hi}} holds only {n} calibration temperature(s) "
                        f"(fewer than {MIN_BLOCK_POINTS})"))
    return out


def branches(temp_domain, min_swing):
    """+1 (heating) / -1 (cooling) / 0 (neither) per sample, in sample
    order: runs between turning points of the temperature, a turn counting
    only once the temperature came back by more than `min_swing` from its
    extreme (so noise on a plateau is neither branch)."""
    t = np.asarray(temp_domain, dtype=float)
    label = np.zeros(t.size, dtype=int)
    if t.size < 2:
        return label
    pivots, direction, ext, lo, hi = [], 0, 0, 0, 0
    for i in range(1, t.size):
        v = t[i]
        if direction == 0:
            if v - t[lo] > min_swing:
                pivots, direction, ext = [lo], 1, i
            elif t[hi] - v > min_swing:
                pivots, direction, ext = [hi], -1, i
            lo = i if v < t[lo] else lo
            hi = i if v > t[hi] else hi
        elif direction * (v - t[ext]) >= 0:
            ext = i
        elif direction * (t[ext] - v) > min_swing:
            pivots.append(ext)
            direction, ext = -direction, i
    if direction != 0:
        pivots.append(ext)
    if len(pivots) > 1 and (pivots[-1] - pivots[0]) / (len(pivots) - 1) < MIN_RUN:
        return label          # jumps back and forth (an unordered log): no thermal branches
    for a, b in zip(pivots[:-1], pivots[1:]):
        label[a:b + 1] = 1 if t[b] > t[a] else -1
    return label


def hysteresis(temp_domain, columns, n_bins=N_BLOCKS):
    """Heating and cooling branches in sample order (`branches`, a turn
    needs one CV block of travel): per axis the mean and largest
    |mean(heating) - mean(cooling)| over the temperature bins both branches
    cover, or None when the log does not hold both (each branch needs 10 %
    of the samples, and 2 shared bins)."""
    t = np.asarray(temp_domain, dtype=float)
    n = t.size
    if n < 20 or not np.ptp(t) > 0:
        return None
    edges = np.linspace(t.min(), t.max(), n_bins + 1)
    label = branches(t, edges[1] - edges[0])
    heat, cool = label == 1, label == -1
    if heat.sum() < 0.1 * n or cool.sum() < 0.1 * n:
        return None
    b = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, n_bins - 1)
    shared = [k for k in range(n_bins) if np.any(heat & (b == k)) and np.any(cool & (b == k))]
    if len(shared) < 2:
        return None
    out = {"heating_samples": int(heat.sum()), "cooling_samples": int(cool.sum()),
           "bins": len(shared), "per_axis": {}}
    for name, y in columns.items():
        y = np.asarray(y, dtype=float)
        d = [float(np.mean(y[heat & (b == k)]) - np.mean(y[cool & (b == k)])) for k in shared]
        out["per_axis"][name] = {"mean": float(np.mean(d)), "max_abs": float(np.max(np.abs(d)))}
    return out
