"""Impulses and motion told apart, from the chain's status per sample.

A sample the limit stage replaces (status WARN_REJECTED) is an impulse only
when the load did not move on: a run of replaced samples that ends in a
re-seed (LIMIT_RESEEDED: the lock-out accepted the new level, or a ramp
began) was the first samples of a load change, and counts as motion.
Motion also counts every motion restart, re-seed and ramp sample
(CHAIN_MOTION, LIMIT_RESEEDED, CHAIN_RAMP), a sample held inside a pour
among them (the load is moving: a glitch there is not told from the pour's
end).

EventCounter works on a stream: a run of replaced samples at the end of one
block is decided by the first sample of the next (or counted as impulses by
finish()).
"""
import numpy as np

from ..status import Warn

_MOVING = int(Warn.CHAIN_MOTION | Warn.LIMIT_RESEEDED | Warn.CHAIN_RAMP)


class EventCounter:
    """Counts impulses and samples of motion over blocks of chain status.

    Examples
    --------
    >>> counter = EventCounter()
    >>> counter.update([0, 4, 0, 4, 4, 16, 0, 256, 256])    # a glitch, then a step, then a pour
    >>> counter.finish()
    {'impulses': 1, 'motion_samples': 5}
    """

    def __init__(self):
        self.impulses = 0
        self.motion = 0
        self._pending = 0           # replaced samples at the end of the last block, not yet decided

    def update(self, status):
        s = np.asarray(status, dtype=np.int64)
        if s.size == 0:
            return
        ok = s >= 0
        moving = ok & ((s & _MOVING) != 0)
        rejected = ok & ((s & int(Warn.WARN_REJECTED)) != 0) & ~moving
        reseeded = ok & ((s & int(Warn.LIMIT_RESEEDED)) != 0)
        self.motion += int(np.count_nonzero(moving))
        edges = np.diff(np.r_[0, rejected.astype(np.int8), 0])
        starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
        lengths = ends - starts
        if self._pending:
            if starts.size and starts[0] == 0:
                lengths[0] += self._pending          # the run goes on into this block
            else:
                self._decide(self._pending, bool(reseeded[0]))
            self._pending = 0
        if ends.size and ends[-1] == s.size:         # a run open at the end: decided later
            self._pending = int(lengths[-1])
            ends, lengths = ends[:-1], lengths[:-1]
        into_load = reseeded[ends]
        self.motion += int(lengths[into_load].sum())
        self.impulses += int(lengths[~into_load].sum())

    def _decide(self, n, into_load):
        if into_load:
            self.motion += n
        else:
            self.impulses += n

    def finish(self):
        """The counts, a run still open at the end counted as impulses."""
        self._decide(self._pending, False)
        self._pending = 0
        return {"impulses": self.impulses, "motion_samples": self.motion}
