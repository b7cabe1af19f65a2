"""Status codes and warning bits of the C core, mirrored from
``csrc/include/sig_status.h`` (a test checks the two agree name by name and
value by value).

Every C function returns an int16 status: 0 success, positive values are
warning bits (the result is valid; bits may be OR-ed), negative values are
errors (nothing produced, the caller's state unchanged).  The C name is the
member name with the ``SIG_`` prefix: ``SIG_ERR_CRC`` is ``Status.ERR_CRC``,
``SIG_CHAIN_TARED`` is ``Warn.CHAIN_TARED``.
"""
from enum import IntEnum, IntFlag

__all__ = ["Status", "Warn", "describe"]


class Status(IntEnum):
    """Success and error codes (``SIG_OK``, ``SIG_ERR_*``).

    Examples
    --------
    >>> Status(-4).name
    'ERR_CRC'
    """

    OK = 0
    ERR_ARG = -1
    ERR_NONFINITE = -2
    ERR_FORMAT = -3
    ERR_CRC = -4
    ERR_EMPTY = -5
    ERR_DEVICE = -6


class Warn(IntFlag):
    """Warning bits (``SIG_WARN_*`` and the stage-specific flags); a
    status may carry several.

    Examples
    --------
    >>> Warn.WARN_REJECTED in Warn(36)
    True
    >>> Warn.CHAIN_MOTION in Warn(36)
    True
    """

    WARN_CLAMPED = 1
    WARN_SATURATED = 2
    WARN_REJECTED = 4
    LIMIT_RESEEDED = 16
    CHAIN_MOTION = 32
    CHAIN_TARED = 64
    CHAIN_NOISE_FLOOR = 128
    CHAIN_RAMP = 256
    LEARN_STALE = 512
    LEARN_SKIPPED = 1024
    LEARN_EXTRAPOLATED = 2048
    LEARN_COMMITTED = 4096


_ERROR_TEXT = {
    Status.ERR_ARG: "NULL pointer or parameter out of range",
    Status.ERR_NONFINITE: "NaN or inf where a finite value is needed",
    Status.ERR_FORMAT: "bad format (magic, version, length, section layout{payload})",
    Status.ERR_CRC: "CRC mismatch (corrupt or partly written)",
    Status.ERR_EMPTY: "{nothing}",
    Status.ERR_DEVICE: "a valid image made for another device",
}

_WARN_TEXT = {
    Warn.WARN_CLAMPED: "input clamped to its valid range",
    Warn.WARN_SATURATED: "output saturated at its rail",
    Warn.WARN_REJECTED: "sample rejected as an impulse or non-finite",
    Warn.LIMIT_RESEEDED: "limit stage re-seeded after a run of rejections",
    Warn.CHAIN_MOTION: "motion detected",
    Warn.CHAIN_TARED: "tare applied",
    Warn.CHAIN_NOISE_FLOOR: "measured noise at its floor (a stuck sensor?)",
    Warn.CHAIN_RAMP: "load moving steadily (a pour), followed",
    Warn.LEARN_STALE: "the model in use is stale (CUSUM of the still residual)",
    Warn.LEARN_SKIPPED: "still sample outside the learner's bins or beyond +-2047: not learned",
    Warn.LEARN_EXTRAPOLATED: "temperature outside the range of the model in use",
    Warn.LEARN_COMMITTED: "a validated model was written into a new image",
}


def describe(code, section=None):
    """A one-line message for a C status code.

    Parameters
    ----------
    code : int
        The sig_status a C function returned.
    section : str, optional
        What an image loader looked for (e.g. ``"compact-polynomial"``): names
        the payload in a format error and the missing section for
        ``ERR_EMPTY``.

    Returns
    -------
    str
        ``"ok"``, the error's meaning, or the warning bits set, joined by ``"; "``.

    Examples
    --------
    >>> describe(-4)
    'CRC mismatch (corrupt or partly written)'
    >>> describe(Status.ERR_EMPTY, "piecewise-linear table")
    'no piecewise-linear table section'
    >>> describe(Warn.WARN_CLAMPED | Warn.CHAIN_TARED)
    'warning: input clamped to its valid range; tare applied'
    """
    code = int(code)
    if code == Status.OK:
        return "ok"
    if code < 0:
        try:
            text = _ERROR_TEXT[Status(code)]
        except ValueError:
            return f"unknown error status {code}"
        return text.format(payload=f" or {section} payload" if section else "",
                           nothing=f"no {section} section" if section else "nothing valid to use")
    names = [text for bit, text in _WARN_TEXT.items() if code & bit]
    unknown = code & ~sum(_WARN_TEXT)
    if unknown:
        names.append(f"unknown bits {unknown:#x}")
    return "warning: " + "; ".join(names)
