"""The smoothing of the Arduino HX711 libraries people use, as sliding
windows over a recording (one output per sample), written from their
published sources (what each computes, defaults as shipped):

  hx711_adc   olkal/HX711_ADC src/HX711_ADC.h + config.h: DATA_SET =
              SAMPLES + IGN_HIGH_SAMPLE + IGN_LOW_SAMPLE = 16 + 1 + 1 = 18
              samples in a ring; smoothedData() sums them and removes the
              largest and the smallest; getData() shifts by DIVB = 4 (/ 16)
  median7     RobTillaart/HX711 HX711.cpp read_median(times = 7): the middle
              of the sorted samples
  medavg7     RobTillaart/HX711 read_medavg(times = 7): the mean of sorted
              indices first = (7 + 2) / 4 .. 7 - first - 1
  average10   bogde/HX711 HX711.cpp read_average(times = 10): sum / times

The same functions are the host side of the bench's C versions
(bench/mcu/peers/hx711_peers.c), checked output for output.  numpy only."""
from __future__ import annotations

import numpy as np

HX711_ADC_SAMPLES, HX711_ADC_SET, HX711_ADC_DIVB = 16, 18, 4
MEDIAN_TIMES, AVERAGE_TIMES = 7, 10


def windows(x, n):
    """Sliding windows of the last n samples (the first ones: what is there,
    the first sample repeated - as after the libraries' start-up reads)."""
    x = np.asarray(x, dtype=float)
    pad = np.concatenate([np.full(n - 1, x[0]), x])
    return np.lib.stride_tricks.sliding_window_view(pad, n)


def hx711_adc(x):
    """(sum of the last 18 - largest - smallest) / 16."""
    w = windows(x, HX711_ADC_SET)
    return (w.sum(axis=1) - w.max(axis=1) - w.min(axis=1)) / 2.0 ** HX711_ADC_DIVB


def median7(x):
    return np.median(windows(x, MEDIAN_TIMES), axis=1)


def medavg7(x):
    w = np.sort(windows(x, MEDIAN_TIMES), axis=1)
    first = (MEDIAN_TIMES + 2) // 4
    return w[:, first:MEDIAN_TIMES - first].mean(axis=1)


def average10(x):
    return windows(x, AVERAGE_TIMES).mean(axis=1)


PEERS = {"hx711_adc": hx711_adc, "median7": median7, "medavg7": medavg7, "average10": average10}
