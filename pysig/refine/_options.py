"""The loop's settings and defaults: folds, guard band, significance,
smallest gain, the length of a reported reading, the families to try,
whether to show progress."""
from dataclasses import dataclass

from . import _effect_models as fx
from . import _robust as robust

DEFAULT_FOLDS = 10
DEFAULT_TEST_BLOCKS = 20
DEFAULT_HAC_BLOCKS = 5         # the test's longest HAC window: a fifth of the record
DEFAULT_ALPHA = 0.05
DEFAULT_MIN_GAIN = 0.02
DEFAULT_REPORT_S = 10.0        # a reported reading averages this long
DEFAULT_MATERIAL = 0.5         # removed systematic error, in units of a reported reading's noise


@dataclass
class Options:
    folds: int = DEFAULT_FOLDS
    gap: int = None              # guard band (samples); default n // (4 * folds)
    test_blocks: int = DEFAULT_TEST_BLOCKS  # time blocks of the residual diagnostics
    hac_blocks: int = DEFAULT_HAC_BLOCKS    # the test's HAC window: at most n / hac_blocks samples
    alpha: float = DEFAULT_ALPHA
    min_gain: float = DEFAULT_MIN_GAIN
    max_steps: int = 6
    families: tuple = tuple(fx.FAMILIES)
    report_s: float = DEFAULT_REPORT_S      # time a reported reading averages over
    material: float = DEFAULT_MATERIAL
    impulse_k: float = robust.HAMPEL_K      # None: no impulse screening
    shape: bool = True                      # try a larger polynomial or a table for the offset
    random_walk_check: bool = True          # a hysteresis or warm-up must also stand under a
                                            # random-walk zero (pysig.refine._random_walk)
    base: tuple = None                      # the starting model ("poly", order) or ("table", knots),
                                            # e.g. the one `pysig fit` chose; None: the order by CV
    progress: bool = False                  # a progress bar (tqdm) on stderr: True, False, or None
                                            # for one only when stderr is a terminal
    label: str = "refine"                   # the progress bar's name (e.g. the column)
