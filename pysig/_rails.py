"""Converter rails: a reading at the lowest or highest code its converter
can give was beyond full scale, so its true value is unknown and it must not
be fitted or filtered as if it were a measurement."""
import numpy as np

INT16_RAILS = (-32768.0, 32767.0)        # a sensor's 16-bit output register
ADC24_RAILS = (-8388608.0, 8388607.0)    # a 24-bit load-cell converter (HX711, ADS1232)


def at_rail(values, rails):
    """Boolean mask of the values equal to either rail."""
    values = np.asarray(values)
    return (values == rails[0]) | (values == rails[1])


def first_at_rail(values, rails):
    """Index of the first value at a rail, or None."""
    hit = np.flatnonzero(at_rail(values, rails))
    return int(hit[0]) if hit.size else None


def saturated_message(value, rail_name):
    """What a reading at a rail means, for an error message."""
    return f"{value:.0f} is {rail_name} rail: the reading saturated (its true value is unknown)"
