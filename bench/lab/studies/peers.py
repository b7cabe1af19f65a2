"""What HX711 users run today, each as its library ships it, for the weighing benches.

Each peer follows its library's source and default (the commit read is
named; none of their code is copied here):

  hx711_adc      olkal/HX711_ADC (7762bc4), src/config.h: SAMPLES 16,
                 IGN_HIGH_SAMPLE 1, IGN_LOW_SAMPLE 1 (the defaults);
                 src/HX711_ADC.cpp smoothedData(): the sum of the last
                 16 + 1 + 1 = 18 samples minus the largest and the smallest,
                 then `>> divBit` (divBit = 4 for SAMPLES 16).
  median7        RobTillaart/HX711 (fac13f0), HX711.cpp read_median(7): the
                 middle of the 7 sorted samples (float).
  medavg7        RobTillaart/HX711 (fac13f0), HX711.cpp read_medavg(7): the
                 7 samples sorted, the mean of indices first = (7 + 2) / 4
                 to 7 - first - 1 inclusive (float).
  average10      bogde/HX711 (be5e3d2), src/HX711.cpp read_average(10), as
                 get_units(10) in its README: `sum / times` on `long`
                 (C integer division, truncating toward zero).
  simple_kalman  denyssene/SimpleKalmanFilter (fc29b51), src/SimpleKalmanFilter
                 .cpp updateEstimate() in float; src/SimpleKalmanFilter.h
                 starts _last_estimate at 0.  Its README: e_est "can be
                 initialized with the same value as e_mea", q "usually between
                 0.001 and 1 ... Recommended 0.01" (both examples use 0.01).
                 q multiplies |change of the estimate| into the estimate error,
                 which has e_mea's unit: q itself has none.  So e_mea = e_est =
                 the measurement noise in the signal's unit (here given the
                 true sigma) and q = 0.01 whatever the unit.

The Arduino libraries' block reads (read_average, read_median) run as
sliding windows, one output per sample (a block read is only slower to
follow a step).  HX711_ADC's start(t) fills its data set with conversions
before the first reading (its examples wait 2 s = 20 samples at 10 SPS, more
than the 18-sample set): the windows start filled with the first sample.

Integer arithmetic: the Arduino libraries see HX711 codes (`long`); their
`>> 4` and `/ 10` round to a whole code.  On integer input (codes) the peers
do exactly that.  On input in another unit (kg, mV, lb: the code divided by
a scale, as get_units() does after the average) there is no code to round
to, and the same windows are averaged without rounding (what the library
returns, divided by its scale, up to less than one code).
"""
import numpy as np

HX711_ADC_SAMPLES = 16          # config.h SAMPLES (default)
HX711_ADC_IGNORED = 1 + 1       # config.h IGN_HIGH_SAMPLE + IGN_LOW_SAMPLE (defaults)
HX711_ADC_DIV_BITS = 4          # divBit: log2(SAMPLES)
BOGDE_TIMES = 10                # get_units(10), the library README's call
ROB_TIMES = 7
SIMPLE_KALMAN_Q = 0.01          # the library README's recommended q (unit-free)

PEERS = ("hx711_adc", "median7", "medavg7", "average10", "simple_kalman")


def is_integer_codes(x):
    """True when every sample is a whole number (HX711 codes)."""
    return bool(np.all(np.isfinite(x)) and np.all(x == np.rint(x)))


def windows(x, n):
    """Sliding windows of the last n samples, started filled with the first."""
    pad = np.concatenate([np.full(n - 1, x[0]), x])
    return np.lib.stride_tricks.sliding_window_view(pad, n)


def hx711_adc(x):
    """olkal/HX711_ADC smoothedData(): 18-sample set without its largest and
    smallest sample, `>> 4` (floor division by 16 on codes)."""
    w = windows(x, HX711_ADC_SAMPLES + HX711_ADC_IGNORED)
    kept = w.sum(axis=1) - w.max(axis=1) - w.min(axis=1)
    if is_integer_codes(x):
        # the library shifts a non-negative sum (codes are offset binary there):
        # an arithmetic shift is floor division, for any sign here
        return np.floor_divide(kept.astype(np.int64), 1 << HX711_ADC_DIV_BITS).astype(float)
    return kept / float(1 << HX711_ADC_DIV_BITS)


def median7(x):
    """RobTillaart/HX711 read_median(7): the median of the last 7 samples."""
    return np.median(windows(x, ROB_TIMES), axis=1)


def medavg7(x):
    """RobTillaart/HX711 read_medavg(7): the middle of the 7 sorted samples."""
    w = np.sort(windows(x, ROB_TIMES), axis=1)
    first = (ROB_TIMES + 2) // 4
    return w[:, first:ROB_TIMES - first].mean(axis=1)


def average10(x):
    """bogde/HX711 read_average(10): `sum / times` on long (truncation toward
    zero on codes)."""
    s = windows(x, BOGDE_TIMES).sum(axis=1)
    if is_integer_codes(x):
        return np.trunc(s / BOGDE_TIMES)   # exact: |sum| < 2^53
    return s / BOGDE_TIMES


def simple_kalman(x, e_mea, q=SIMPLE_KALMAN_Q):
    """denyssene/SimpleKalmanFilter(e_mea, e_mea, q).updateEstimate() per
    sample, in float32 as the library computes, starting from 0."""
    f = np.float32
    err_measure, err_estimate, q = f(e_mea), f(e_mea), f(q)
    last = f(0.0)
    one = f(1.0)
    out = np.empty(x.size)
    for i, mea in enumerate(x.astype(np.float32)):
        gain = err_estimate / (err_estimate + err_measure)
        cur = last + gain * (mea - last)
        err_estimate = (one - gain) * err_estimate + abs(last - cur) * q
        last = cur
        out[i] = cur
    return out


def run_peer(name, x, sigma):
    """One peer on x; sigma: the measurement noise (SimpleKalmanFilter's e_mea)."""
    if name == "simple_kalman":
        return simple_kalman(x, sigma)
    return {"hx711_adc": hx711_adc, "median7": median7, "medavg7": medavg7,
            "average10": average10}[name](x)
