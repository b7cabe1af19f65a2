"""Temperature compensation: fit a drift model from a chamber or field log,
check it, and hand the firmware the very same model.

A model is a polynomial f(T) or a table (piecewise linear over uniform
knots) per axis; the correction is delta = f(T) - f(T0).  Every model
carries its temperature source (°C or the sensor's raw codes) and the
reading's value scale, so the file, the image and the C header agree.
``fixed=True`` runs the firmware's C path (int16 readings, int32 / Q
coefficients) instead of float64.

=======================  ======================================================
fit_model                fit one model per axis; family and size chosen by
                         blocked cross-validation over temperature (``auto``),
                         or given (``poly:N``, ``table:K``, ``table:auto``)
parse_spec               the model spelling of ``fit_model`` and the CLI
load                     a model file (JSON) back as a model
apply                    correct readings with a model (float64 or ``fixed``)
load_image               an NVM image as the firmware's C loader reads it
apply_image              correct readings with an NVM image, through the
                         firmware's C loader and evaluator
image_bytes              the CRC-protected NVM image of a model
c_header                 the C header of a model (const arrays + init call)
TempCode, CELSIUS,       the temperature source: °C or int16 / uint16 raw codes
raw_code
MAX_FIT_ORDER            the highest polynomial order ``fit_model`` tries
first_saturated,         readings at an int16 rail (never fitted)
saturated_reading
=======================  ======================================================
"""
from ._c_header import c_header
from ._calibration import apply, apply_image, fit_model, image_bytes, load, load_image, parse_spec
from ._poly_fit import MAX_FIT_ORDER, first_saturated, saturated_reading
from ._tempcode import CELSIUS, TempCode, raw_code

__all__ = ["fit_model", "parse_spec", "load", "apply", "apply_image", "load_image", "image_bytes", "c_header",
           "TempCode", "CELSIUS", "raw_code", "MAX_FIT_ORDER", "first_saturated", "saturated_reading"]
