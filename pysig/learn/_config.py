"""The learner's configuration (sig_learn_config) and how a bin grid is
chosen for a temperature range."""
from dataclasses import asdict, dataclass, replace

from ..errors import RangeError

MAX_BINS, SUM_SLOTS, MAX_SHIFT = 32, 48, 10     # n_bins * n_axes <= SUM_SLOTS


@dataclass(frozen=True)
class LearnConfig:
    """sig_learn_config: the fields in the units of sig_learn.h.

    Defaults are for one sample a minute: a bin counts as covered after 30
    still minutes, a commit at most every 24 h, the CUSUM allowance 2 sigma
    and threshold 12 sigma (sigma floor 0.5 LSB), the margin 1/4.
    """
    t_base: int = 0
    bin_shift: int = 8
    n_bins: int = 16
    n_axes: int = 1
    code_kind: int = 0
    period: int = 24 * 60
    min_count: int = 30
    min_bins: int = 4
    margin_shift: int = 2
    sigma_floor: int = 8
    k_sigma: int = 32
    h_sigma: int = 192

    def as_dict(self):
        return asdict(self)

    def with_(self, **changes):
        return replace(self, **changes)

    @staticmethod
    def for_range(t_lo, t_hi, **fields):
        """The finest grid (width a power of two) of at most 48 / n_axes bins
        (32 for one axis, 16 for three: the sums of the axes share one pool)
        that covers the int16 temperatures [t_lo, t_hi]; other fields as given.

        Examples
        --------
        >>> c = LearnConfig.for_range(-1000, 4000, n_axes=3)
        >>> (c.t_base, c.bin_shift, c.n_bins)
        (-1024, 9, 10)
        """
        t_lo, t_hi = int(t_lo), int(t_hi)
        max_bins = min(MAX_BINS, SUM_SLOTS // int(fields.get("n_axes", 1)))
        if t_hi < t_lo:
            raise RangeError(f"learn: temperature range {t_lo}..{t_hi} is empty")
        for shift in range(1, MAX_SHIFT + 1):
            w = 1 << shift
            base = (t_lo // w) * w
            n = t_hi // w - t_lo // w + 1
            if max(n, 3) <= max_bins and base + max(n, 3) * w <= 32767:
                return LearnConfig(t_base=base, bin_shift=shift, n_bins=max(n, 3), **fields)
        raise RangeError(f"learn: temperatures {t_lo}..{t_hi} span more than {max_bins} bins of "
                         f"{1 << MAX_SHIFT} (the learner's widest grid)")

    @staticmethod
    def for_log(t, n_axes, start_image=None, **fields):
        """`for_range` over the log's int16 temperatures and the start
        model's range (so a committed table can carry the whole stored
        range); RangeError when together they need a wider grid."""
        from ._learn import DeviceLearner
        lo, hi = int(min(t)), int(max(t))
        if start_image is not None:
            probe = DeviceLearner(LearnConfig(n_axes=n_axes).as_dict())
            if probe.use_image(start_image) == 0:
                m_lo, m_hi = probe.model_range
                lo, hi = min(lo, m_lo), max(hi, m_hi)
        return LearnConfig.for_range(lo, hi, n_axes=n_axes, **fields)
