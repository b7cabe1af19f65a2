"""The device learner (csrc/learn) in the MCU simulators, built as firmware
builds it (the 8051 with --stack-auto --xstack, fixed only): every step's
status, the committed image and the second solve's outcome read back from
the MSP430F5510 and the 8051 equal the host C (through Cython), which
tests/test_learn.py holds equal to the spec.  The runner raises McuError on
any difference; no timing is asserted."""
import pytest

from conftest import require_target_tools
from lab.mcu import learn_cost


@pytest.mark.parametrize("target", ["msp430", "mcs51"])
def test_learner_on_mcu_equals_host(target):
    require_target_tools(target)
    row = learn_cost.learn_row(target)
    assert row["checked_against_host"]
    assert row["validate_only_outcome"] == 3        # SIG_LEARN_NOT_BETTER: the validation-only solve
    assert row["image_bytes"] > 0
