"""What each temperature-model family costs on the MCU, per axis and call:
the figures `bench/model_pareto.py` measured on the MSP430F5510 simulator
(bench/model_pareto/results/model_pareto.json: mspdebug 0.22 `sim`, 8 MHz,
16x16 hardware-multiplier helpers), reduced to a table so that model choice
does not read a bench file at run time.

* Polynomial (sig_tcomp_delta_q, int32 coefficients): the median cycles over
  the bench's datasets and axes for each order 1..8; data bytes
  4 * (order + 1) + 13 (coefficients, q, range and scaling).
* Table (sig_pwl_eval_q16): one index computation and one interpolation
  whatever the size: the median over every measured size 2..184 (the spread
  is 439..446 cycles, the simulator's temperature positions, not the size);
  data bytes 2 * knots + 10.
* Code bytes (.text of the evaluation call tree, without runtime helpers):
  1188 for the polynomial, 442 for the table.

Re-run the bench after changing csrc/tcomp and update these numbers:
tests/test_cost_figures.py holds them against the bench's JSON."""
from dataclasses import dataclass

POLY_CYCLES = {1: 540, 2: 756, 3: 980, 4: 1202, 5: 1421, 6: 1640, 7: 1862, 8: 2090}
TABLE_CYCLES = 443
POLY_TEXT_BYTES = 1188
TABLE_TEXT_BYTES = 442


@dataclass(frozen=True)
class Cost:
    """Per-axis cost of one model size on the MSP430F5510."""
    cycles: int
    data_bytes: int
    text_bytes: int


def cost(family, size):
    """Cost of a polynomial of order `size` or a table of `size` knots."""
    if family == "poly":
        return Cost(POLY_CYCLES[int(size)], 4 * (int(size) + 1) + 13, POLY_TEXT_BYTES)
    if family == "table":
        return Cost(TABLE_CYCLES, 2 * int(size) + 10, TABLE_TEXT_BYTES)
    raise ValueError(f"unknown model family {family!r}")


def cost_key(family, size, prefer="cycles"):
    """Sort key, cheapest first: cycles then data bytes (or bytes first)."""
    c = cost(family, size)
    return (c.cycles, c.data_bytes) if prefer == "cycles" else (c.data_bytes, c.cycles)
