"""The ATmega328P target: the harness's own Timer 1 cycle clock against
code of known length, and the weighing chain built with gcc-avr, run in
simavr, every output and status equal to the host C (fixed: bit for bit)."""
import pytest

from conftest import ROOT, require_target_tools
from lab.mcu import cost_avr, runner, vectors

SELFTEST = ROOT / "bench" / "mcu" / "selftest"


def test_timer1_clock_counts_known_delays_exactly():
    require_target_tools("avr")
    img = runner.build_avr([], SELFTEST / "avr_clock_harness.c", name="avr-clock",
                           include_dirs=[ROOT / "bench" / "mcu" / "harness"])
    r = runner.measure(img, funcs=["delay_short", "delay_long"], regions=["bench_start:bench_stop"])
    short, long_ = r["funcs"]["delay_short"]["cycles"], r["funcs"]["delay_long"]["cycles"]
    assert long_ - short == 200000 - 1000          # overflows of the 16-bit counter subtracted exactly
    assert short == 1000 + 4 + 4                   # + call and ret: the measuring code subtracted
    assert r["regions"]["bench_start:bench_stop"]["cycles"] - 200000 in range(8, 24)   # + call, ret, marker calls
    assert r["overhead"]["overflow_isr_cycles"] > 0
    assert r["funcs"]["delay_short"]["stack_bytes"] < 24     # the measuring code's own frames: a floor


@pytest.mark.parametrize("preset", ["auto", "recommended"])
@pytest.mark.parametrize("form", ["fixed", "float"])
def test_chain_on_the_avr_equals_the_host(preset, form):
    require_target_tools("avr")
    row = cost_avr.chain_row_avr(form, vectors.chain_case(n=cost_avr.AVR_CHAIN_N, preset=preset))
    assert row["checked_samples"] == cost_avr.AVR_CHAIN_N and row["cycles"] > 0
