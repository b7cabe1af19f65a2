"""The example firmware of examples/firmware/ (MSP430F5510 with clang, 8051
with sdcc) builds warning-free, both through lab.mcu.runner and through
its own Makefile (the recipe a user copies), runs in the simulators
(mspdebug sim, s51), and leaves in its globals exactly what pysig computes
on the host from the same calibration: the slot the A/B loader picks (the
newer one; the older one when the newer was cut off half-written), the
compensated readings and their status (one beyond the calibrated range:
clamped and flagged), and the weighing chain's fixed-point outputs, stable
flags and statuses of the default chain (sig_chain_params_auto_q, noise
measured on the fly) on raw HX711 codes with a read glitch and a step.

The 8051 firmware runs with its timer interrupt firing every 256 machine
cycles (the results must still be exact), its internal stack is measured in
s51 (the deepest point of the demo plus what the interrupt handler puts on
it must leave at least ISR_HEADROOM bytes free), its pdata stack too, and
its image holds no float code."""
import json
import re
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT, require_shared_data, require_tool

from lab.mcu import runner
from pysig.status import Status, Warn
from pysig.store._image_c import image_select_slot
from pysig.tcomp._tcomp16 import Tcomp16Q
from pysig.weigh import Chain

FIRMWARE = ROOT / "examples" / "firmware"
COMMON = FIRMWARE / "common"
TARGETS = {"msp430": FIRMWARE / "msp430f5510", "mcs51": FIRMWARE / "mcs51"}
MCS51_FLAGS = ["--stack-auto", "-DSIG_NO_FLOAT"]   # call depth; fixed only, as the Makefile (which adds --xstack)
ISR_HEADROOM = 48       # bytes of the 8051's internal RAM left free with the handler at the deepest point
FLOAT_LIBRARY = re.compile(r"^\s*C:\s+[0-9A-F]+\s+\S+\s+_(fs\w+|\w+2fs|fs2\w+)\s*$", re.M)


def tools(target):
    if target == "msp430":
        require_tool("clang-14", "clang")
        require_tool("ld.lld-14", "ld.lld")
        require_tool("mspdebug")
    else:
        require_tool("sdcc")
        require_tool("s51")


MPU6000 = "mpu6000_gyro_offset_vs_temp/mpu6000_sn102_gyro_offset.csv"


@pytest.fixture(scope="module", params=["newest", "torn-b", "mpu6000"])
def calibration(request, tmp_path_factory):
    """calibration.h and its JSON twin from make_calibration.py: the
    simulated chamber with slot B newest and whole, or slot B cut off
    half-written; and the real MPU-6000 gyro offsets (3 axes, 6.7..41 °C)."""
    out = tmp_path_factory.mktemp(f"cal-{request.param}")
    cmd = [sys.executable, str(FIRMWARE / "make_calibration.py"), "-o", str(out / "calibration.h"),
           "--json", str(out / "calibration.json")]
    if request.param == "torn-b":
        cmd.append("--torn-b")
    if request.param == "mpu6000":
        cmd += ["--input", str(require_shared_data(MPU6000)), "--columns", "gyro_x,gyro_y,gyro_z"]
    res = subprocess.run(cmd, capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    return out, json.loads((out / "calibration.json").read_text()), request.param


def host(cal):
    """What the firmware must compute, through pysig (the C core via Cython)."""
    slots = [bytes.fromhex(cal["slot_a"]), bytes.fromhex(cal["slot_b"])]
    st, which = image_select_slot(*slots)
    assert st == Status.OK
    comp, comp_st = Tcomp16Q.from_image(slots[which]).apply(cal["temp_centi"], cal["readings"])
    chain = Chain(fixed=True)                           # the default, as node.c builds it in C
    y, stable, chain_st = chain.process(np.array(cal["samples"], dtype=float), flags=True)
    q7 = np.round(y * 128).astype(np.int64)
    assert np.array_equal(q7 / 128, y)                  # the fixed chain's output is exact Q24.7
    return {"slot": which, "start": Status.OK, "comp": comp.astype(int).tolist(),
            "comp_status": comp_st.astype(int).tolist(), "q7": q7.tolist(),
            "stable": stable.astype(int).tolist(), "chain_status": chain_st.astype(int).tolist()}


def reads(cal):
    n, m, axes = len(cal["readings"]), len(cal["samples"]), len(cal["axes"])
    return {"node_slot": 1, "node_start_status": 2, "node_comp_out": 2 * axes * n, "node_comp_status": 2 * n,
            "node_weight_q7": 4 * m, "node_stable": m, "node_weight_status": 2 * m}


def decode(raw, cal):
    def ints(name, fmt):
        return np.frombuffer(raw[name], dtype=fmt).astype(int).tolist()
    n = len(cal["readings"])
    return {"slot": raw["node_slot"][0], "start": ints("node_start_status", "<i2")[0],
            "comp": np.array(ints("node_comp_out", "<i2")).reshape(n, len(cal["axes"])).tolist(),
            "comp_status": ints("node_comp_status", "<i2"), "q7": ints("node_weight_q7", "<i4"),
            "stable": ints("node_stable", "u1"), "chain_status": ints("node_weight_status", "<i2")}


def check(got, want, variant):
    assert got == want
    assert got["slot"] == (0 if variant == "torn-b" else 1)     # newest valid slot; A after a torn write
    assert got["comp_status"][-1] & Warn.WARN_CLAMPED               # the out-of-range reading
    assert any(s & Warn.WARN_REJECTED for s in got["chain_status"])  # the HX711 read glitch
    assert any(got["stable"])


def build_with_runner(target, gen):
    sources = [COMMON / "node.c"] + runner.csrc_sources("sig_chain", "sig_chain_auto", "sig_tcomp16", "sig_image")
    main = TARGETS[target] / "main.c"
    if target == "msp430":
        return runner.build_msp430(sources, main, hwmult=True, include_dirs=[gen, COMMON])
    return runner.build_mcs51(sources, main, include_dirs=[gen, COMMON], extra_flags=MCS51_FLAGS)


@pytest.mark.parametrize("target", sorted(TARGETS))
def test_runner_build_runs_in_simulator_and_equals_host(target, calibration):
    tools(target)
    gen, cal, variant = calibration
    img = build_with_runner(target, gen)
    raw = runner.run_until(img, "results_ready", reads(cal))
    check(decode(raw, cal), host(cal), variant)


@pytest.mark.parametrize("target", sorted(TARGETS))
def test_makefile_recipe_builds_and_runs(target, calibration, tmp_path):
    tools(target)
    make = require_tool("make")
    gen, cal, variant = calibration
    build = tmp_path / "build"
    args = [make, "-C", str(TARGETS[target]), f"CAL_DIR={gen}", f"BUILD={build}"]
    if target == "msp430":
        args.append("MPY_BASE=0x0130")              # mspdebug simulates the multiplier there
    res = subprocess.run(args, capture_output=True, text=True, timeout=900)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "warning" not in (res.stdout + res.stderr).lower(), res.stdout + res.stderr
    image = build / ("firmware.elf" if target == "msp430" else "firmware.ihx")
    img = runner.image_from_file(image, hwmult=target == "msp430")
    raw = runner.run_until(img, "results_ready", reads(cal))
    check(decode(raw, cal), host(cal), variant)
    if target == "mcs51":
        memory_budget(img, image)


def memory_budget(img, image):
    """The 8051 firmware's stacks and code, printed (the README's figures)."""
    stack = runner.mcs51_stack_peak(img, isr="timer0_isr")
    ticks = int.from_bytes(runner.run_until(img, "results_ready", {"node_ticks": 4})["node_ticks"],
                           "little")
    code = int(re.search(r"^CSEG\s+\S+\s+\S+\s+=\s+(\d+)\. bytes", image.with_suffix(".map").read_text(),
                         re.M).group(1))
    print(f"\n8051 example: internal stack from {stack['start_sp']:#04x}, peak {stack['peak']:#04x} "
          f"({stack['headroom']} B free), interrupt handler {stack['isr_bytes']} B -> "
          f"{stack['worst_case_headroom']} B free at worst; pdata stack peak "
          f"{stack['xstack_peak']:#04x} ({stack['xstack_headroom']} B free); {ticks} interrupts "
          f"during the demo; code {code} B")
    assert ticks > 100                                  # the handler ran throughout the demo
    assert stack["worst_case_headroom"] >= ISR_HEADROOM, stack
    assert stack["xstack_headroom"] >= ISR_HEADROOM, stack
    floats = FLOAT_LIBRARY.findall(image.with_suffix(".map").read_text())
    assert not floats, f"float code in the fixed-only firmware: {sorted(set(floats))}"
