"""Replay a field log through the device learner (the C code, as firmware
runs it): the model in use corrects every sample, still samples teach the
learner, a solve runs every `solve_every` samples and what it commits is
loaded as the new model."""
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputFileError, ModelFileError, RangeError
from ..status import Warn
from ._config import LearnConfig
from ._learn import OUTCOMES, DeviceLearner


@dataclass
class ReplayResult:
    """What the device did over the log.

    Attributes
    ----------
    t : ndarray of int64
        The int16 temperature the learner saw per sample.
    comp : ndarray of int16, shape (n, n_axes)
        The readings corrected by the model in use at that sample.
    status : ndarray of int16
        sig_learn_step's status per sample (`Warn.LEARN_*` bits).
    sequence : ndarray of uint32
        Sequence number of the image in use (0: none).
    commits : list of dict
        Per commit: sample index, sequence, validation sums, range, knots.
    solves : list of dict
        Every solve's report (outcome names from sig_learn.h).
    image : bytes or None
        The last committed image (None when nothing was committed).
    """
    t: np.ndarray
    comp: np.ndarray
    status: np.ndarray
    sequence: np.ndarray
    commits: list = field(default_factory=list)
    solves: list = field(default_factory=list)
    image: bytes = None
    config: LearnConfig = None

    @property
    def stale(self):
        return (self.status & int(Warn.LEARN_STALE)) != 0

    @property
    def extrapolated(self):
        return (self.status & int(Warn.LEARN_EXTRAPOLATED)) != 0


def _report(index, rep, seq=None):
    out = dict(index=int(index), outcome=OUTCOMES[rep["outcome"]], covered=rep["covered"],
               validated=rep["validated"], sse_new=rep["sse_new"], sse_stored=rep["sse_stored"])
    if seq is not None:
        out.update(sequence=seq, t_lo=rep["t_lo"], t_hi=rep["t_hi"], n_knots=rep["n_knots"])
    return out


def replay(t, readings, still, config, start_image=None, solve_every=60):
    """Run the device learner over a log.

    Parameters
    ----------
    t : array_like of int
        int16 temperatures in the image unit (see pysig.tcomp.tempcode).
    readings : array_like, shape (n, n_axes)
        int16 raw readings.
    still : array_like of bool
        The stillness gate per sample.
    config : LearnConfig
    start_image : bytes, optional
        The image in use at the start (a chamber model); None: none.
    solve_every : int
        Samples between two solves.

    Returns
    -------
    ReplayResult

    Raises
    ------
    RangeError
        Temperatures or readings that do not fit int16, or a configuration
        the C learner refuses.
    InputFileError
        Arrays of different lengths, or another number of reading columns
        than the configuration's axes.
    ModelFileError
        A start image the C loader refuses or with another number of axes.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.repeat(np.arange(0, 2000, 100), 50)
    >>> x = np.rint(20 + t / 100).astype(int)[:, None]
    >>> r = replay(t, x, np.ones(t.size, bool), LearnConfig.for_range(0, 2000, min_count=20))
    >>> [c["outcome"] for c in r.commits][:1]
    ['commit']
    """
    t = np.asarray(t, dtype=np.int64)
    x = np.asarray(readings, dtype=np.int64)
    if x.ndim == 1:
        x = x[:, None]
    g = np.asarray(still, dtype=bool)
    if not (len(t) == len(x) == len(g)):
        raise InputFileError(f"learn: {len(t)} temperatures, {len(x)} readings, {len(g)} still flags")
    for name, v in (("temperature", t), ("reading", x)):
        bad = np.flatnonzero((v < -32768) | (v > 32767))
        if bad.size:
            i = int(bad[0]) // (1 if v.ndim == 1 else v.shape[1])
            raise RangeError(f"learn: {name} at index {i} does not fit int16")
    if x.shape[1] != config.n_axes:
        raise InputFileError(f"learn: {x.shape[1]} reading columns for a {config.n_axes}-axis learner")
    dev = DeviceLearner(config.as_dict())
    if dev.status != 0:
        raise RangeError(f"learn: the C learner refuses the configuration {config}")
    if start_image is not None and dev.use_image(start_image) != 0:
        raise ModelFileError("learn: the start model's image is refused by the C loader (corrupt, CRC) or has "
                             f"another number of axes than the {config.n_axes} columns")
    codes = (t + 32768) if config.code_kind == 1 else (t & 0xFFFF)
    comp, status, seq, commits, solves = dev.replay(codes.astype(np.uint16), x.astype(np.int16), g,
                                                    int(solve_every))
    return ReplayResult(
        t=t, comp=comp, status=status, sequence=seq,
        commits=[_report(i, rep, int.from_bytes(img[8:12], "little")) for i, rep, img in commits],
        solves=[_report(i, rep) for i, rep in solves],
        image=commits[-1][2] if commits else None, config=config)
