"""Generate calibration.h for the example firmware (examples/firmware/*/).

    python3 examples/firmware/make_calibration.py -o examples/firmware/common/calibration.h

What it writes, all from pysig (the same code `pysig fit` and `pysig export
--format image` run):

* two flash slots of SLOT_BYTES each, const arrays standing for the flash
  regions a firmware reserves for its calibration (erased flash reads 0xFF),
  fitted on the calibration data (by default the simulated thermal chamber,
  pysig.sim._chamber, seeded: a 3-axis magnetometer; or --input recordings
  with 1 to 3 int16 reading columns): slot A the factory calibration
  (order 1, sequence 1), slot B a later recalibration (--order, default 2,
  sequence 2), both in the compact form (sig_tcomp16: 16x16 products, what
  the MCUs multiply fastest).  The firmware's loader (sig_image_select_slot)
  takes the newer valid one: B.  With --torn-b, B holds an image whose
  writing was cut off half way (the rest still erased): the loader falls
  back to A.
* demo inputs standing for the sensors: temperatures and readings of the
  calibration data spread over its range, one more beyond it (the firmware
  clamps and flags it), and raw HX711 load-cell codes from the recording
  bundled with pysig (a read glitch, then a 10-lb step).

The weighing chain needs no calibration: the firmware runs the default
chain (sig_chain_params_auto_q), whose thresholds follow the noise it
measures on the samples.

--json FILE also writes the same data for a host-side check (the example
firmware test compares what the simulators read back with pysig on it).
"""
import argparse
import importlib.resources
import json
import sys

import numpy as np

from pysig.errors import RangeError
from pysig.io import atomic_output, read_csv
from pysig.sim import _chamber as chamber
from pysig.tcomp._sections import compact_image
from pysig.tcomp import _quant as quant
from pysig.tcomp._poly_fit import fit_tcomp

SLOT_BYTES = 128                  # flash reserved per slot: a 3-axis order-5 compact image is 92 bytes
ERASED = 0xFF
DEMO_READINGS = 4                 # readings spread over the calibrated range
BEYOND_RANGE_C = 15.0             # one more reading this far above it: clamped, SIG_WARN_CLAMPED
HX711_FILE = "hx711_steps_10hz.csv"
HX711_COLUMN = "lc1_counts"
HX711_ROWS = slice(66, 186)       # a read glitch (row 73), then a 10-lb step (rows 163-166)


def slot(image, torn=False):
    """An image in a flash slot of SLOT_BYTES, the rest erased; torn: only
    the first half of the image was written before the power cut."""
    if len(image) > SLOT_BYTES:
        raise RangeError(f"image of {len(image)} bytes does not fit a {SLOT_BYTES}-byte slot")
    written = image[:len(image) // 2] if torn else image
    return written + bytes([ERASED]) * (SLOT_BYTES - len(written))


def chamber_data(seed=0):
    """(temperature °C, {axis: int readings}) of the simulated thermal chamber."""
    data = chamber.simulate(chamber.ChamberParams(seed=seed))
    return data["temp"], {a: data[a] for a in "xyz"}


def recorded_data(paths, temp, columns):
    """(temperature °C, {column: int readings}) from CSV/Parquet recordings:
    readings must be integer sensor codes within int16 (what the firmware
    reads); RangeError naming the column otherwise."""
    parts = [read_csv(str(p), columns=[temp, *columns]) for p in paths]
    t = np.concatenate([np.asarray(d[temp], dtype=float) for d in parts])
    axes = {}
    for c in columns:
        y = np.concatenate([np.asarray(d[c], dtype=float) for d in parts])
        bad = np.flatnonzero((y != np.round(y)) | (y < -32768) | (y > 32767))
        if bad.size:
            raise RangeError(f"column {c!r}, row {int(bad[0]) + 1}: {float(y[bad[0]])!r} is not an int16 "
                             f"sensor code (the firmware compensates raw int16 readings)")
        axes[c] = y.astype(np.int64)
    return t, axes


def calibration(temp, axes, torn_b=False, order=2):
    """Everything calibration.h holds, as a dict of plain Python values:
    slot A an order-1 fit of (temp, axes), slot B an order-`order` fit."""
    if not 1 <= len(axes) <= 3:
        raise RangeError(f"{len(axes)} axes: the compensation takes 1 to 3")
    factory = fit_tcomp(temp, axes, order=1, what="factory calibration")
    recal = fit_tcomp(temp, axes, order=order, what="recalibration")
    lo, hi = float(np.min(temp)), float(np.max(temp))
    rows = [int(np.argmin(np.abs(temp - t))) for t in np.linspace(lo, hi, DEMO_READINGS)]
    temps = [float(temp[r]) for r in rows] + [hi + BEYOND_RANGE_C]
    readings = [[int(y[r]) for y in axes.values()] for r in rows + rows[-1:]]
    counts = read_csv(str(importlib.resources.files("pysig.data") / HX711_FILE), columns=[HX711_COLUMN])
    samples = [int(v) for v in np.asarray(counts[HX711_COLUMN])[HX711_ROWS]]
    return {
        "axes": list(axes),
        "slot_a": slot(compact_image(quant.quantize_compact(factory), sequence=1)).hex(),
        "slot_b": slot(compact_image(quant.quantize_compact(recal), sequence=2), torn=torn_b).hex(),
        "temp_centi": [int(v) for v in quant.to_centi(np.array(temps))],
        "readings": readings,
        "samples": samples,
    }


def _bytes_c(hexstr, indent="    ", per_line=16):
    b = bytes.fromhex(hexstr)
    lines = [", ".join(f"0x{v:02X}" for v in b[i:i + per_line]) for i in range(0, len(b), per_line)]
    return (",\n" + indent).join(lines)


def header(cal):
    """The text of calibration.h."""
    readings = ",\n    ".join("{ " + ", ".join(map(str, r)) + " }" for r in cal["readings"])
    samples = ",\n    ".join(", ".join(f"INT32_C({v})" for v in cal["samples"][i:i + 6])
                             for i in range(0, len(cal["samples"]), 6))
    return f"""/* calibration.h - generated by examples/firmware/make_calibration.py; do not edit.
 *
 * Two flash slots holding the coefficient image (csrc/include/sig_image.h)
 * and demo inputs standing for the sensors (the weighing chain is the
 * default one, sig_chain_params_auto_q: it needs no calibration).
 * Included once, by node.c. */
#ifndef CALIBRATION_H
#define CALIBRATION_H

#include <stdint.h>
#include <stdbool.h>

#define CAL_SLOT_BYTES {SLOT_BYTES}u
#define CAL_N_AXES     {len(cal['axes'])}u
#define CAL_N_READINGS {len(cal['readings'])}u
#define CAL_N_SAMPLES  {len(cal['samples'])}u

/* Flash slot A: factory calibration (sequence 1). */
static const uint8_t cal_slot_a[CAL_SLOT_BYTES] = {{
    {_bytes_c(cal['slot_a'])}
}};

/* Flash slot B: recalibration (sequence 2). */
static const uint8_t cal_slot_b[CAL_SLOT_BYTES] = {{
    {_bytes_c(cal['slot_b'])}
}};

/* Temperatures in 0.01 °C and readings in LSB, as the sensors give them. */
static const int16_t cal_temp_centi[CAL_N_READINGS] = {{ {', '.join(map(str, cal['temp_centi']))} }};
static const int16_t cal_readings[CAL_N_READINGS][CAL_N_AXES] = {{
    {readings}
}};

/* Raw HX711 codes of one load cell at 10 samples/s. */
static const int32_t cal_samples[CAL_N_SAMPLES] = {{
    {samples}
}};

#endif /* CALIBRATION_H */
"""


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-o", "--output", required=True, help="calibration.h to write")
    ap.add_argument("--json", help="also write the same data as JSON (for host-side checks)")
    ap.add_argument("--torn-b", action="store_true",
                    help="slot B holds a half-written image: the loader must fall back to A")
    ap.add_argument("--input", nargs="+", metavar="CSV",
                    help="calibrate from these recordings instead of the simulated chamber")
    ap.add_argument("--temp", default="temp_c", help="temperature column in °C (with --input)")
    ap.add_argument("--columns", default="x,y,z",
                    help="1 to 3 comma-separated int16 reading columns (with --input)")
    ap.add_argument("--order", type=int, default=2, help="order of the slot-B recalibration (default 2)")
    args = ap.parse_args(argv)
    if args.input:
        temp, axes = recorded_data(args.input, args.temp, args.columns.split(","))
    else:
        temp, axes = chamber_data()
    cal = calibration(temp, axes, torn_b=args.torn_b, order=args.order)
    with atomic_output(args.output) as fh:
        fh.write(header(cal))
    if args.json:
        with atomic_output(args.json) as fh:
            json.dump(cal, fh, indent=1)
    print(f"wrote {args.output}" + (f" and {args.json}" if args.json else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
