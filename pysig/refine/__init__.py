"""Refine: close the loop on measured data.  Fit the base model, find in its
residual the effect it lacks (a thermal lag, hysteresis, creep, warm-up, a
gain drift, a nonlinearity, cross-axis coupling; two at once when they only
help together), add it while the blocked cross-validated error drops
significantly, report the error before and after and each effect's share,
and say when structure is left that no candidate explains.  A slow drift in
time is fitted under the physics as a nuisance: reported on its own line,
never part of the device correction.  Each effect also
runs on the device (csrc/refine), from the NVM image written here.

===================  ==========================================================
refine               the loop: base model, candidates, stopping test; a Result
Options              folds, guard band, significance, smallest gain, families, progress bar
FitData              one measured column with its times, temperature, reference
plateau_reference    a reference from the held plateaus of a log without one
stop_test            the stopping rule in words (for reports)
DEFAULT_FOLDS,       the loop's defaults
DEFAULT_ALPHA,
DEFAULT_MIN_GAIN,
DEFAULT_REPORT_S
device_model         the refined model as the firmware runs it (fixed point)
refined_image,       its NVM image, and back
read_refined_image
correct_float,       the correction of the device model, float64 and through
correct_c            the firmware's C code
write_plots          residual and effect plots (matplotlib, loaded on use)
===================  ==========================================================
"""
from ._device import correct_c, correct_float, device_model, read_refined_image, refined_image
from ._effect_models import FitData
from ._loop import refine
from ._options import DEFAULT_ALPHA, DEFAULT_FOLDS, DEFAULT_MIN_GAIN, DEFAULT_REPORT_S, Options
from ._plateaus import plateau_reference
from ._stopping import stop_test

__all__ = ["refine", "Options", "FitData", "plateau_reference", "stop_test", "DEFAULT_FOLDS", "DEFAULT_ALPHA",
           "DEFAULT_MIN_GAIN", "DEFAULT_REPORT_S", "device_model", "refined_image", "read_refined_image",
           "correct_float", "correct_c", "write_plots"]


def __getattr__(name):
    # matplotlib is loaded only by the command that draws.
    if name == "write_plots":
        from ._plots import write_plots
        return write_plots
    raise AttributeError(f"module 'pysig.refine' has no attribute {name!r}")
