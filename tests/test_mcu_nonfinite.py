"""The float API's non-finite guards hold on the targets: the non-finite rows
of the bad-input matrix (docs/bad-input.md, "C core") run on the host, in
mspdebug (MSP430, clang) and in s51 (8051, sdcc), and every target returns
the documented status and leaves state and outputs as the host does.

sdcc once folded the arithmetic finiteness test (x - x == 0) to true and
compares NaN like a number, so a NaN passed every guard on the 8051: the
guards test the bits now (sig_types.h), and this test proves it in the
simulator.  The cases are bench/mcu/harness/nonfinite_harness.c, in its
order; each runs with five non-finite values (quiet NaN, negative NaN, a
NaN with only the lowest fraction bit set, +inf, -inf)."""
import re
import subprocess

import numpy as np
import pytest

from conftest import ROOT, require_target_tools, require_tool
from lab.mcu import runner
from pysig.status import Status, Warn

HARNESS = ROOT / "bench" / "mcu" / "harness" / "nonfinite_harness.c"
WEIGH_MODULES = ("sig_chain", "sig_scale")
CALIB_MODULES = ("sig_tcomp", "sig_pwl_f", "sig_lag", "sig_hyst", "sig_creep", "sig_gain",
                 "sig_nonlin", "sig_cross")
# the 8051's two programs: the weighing half without sig_scale (the chain
# and its stages nearly fill 64 KB of code), sig_scale's rows in the other
MCS51_WEIGH_MODULES = ("sig_chain",)
MCS51_CALIB_MODULES = CALIB_MODULES + ("sig_scale",)
NONFINITE, ARG = int(Status.ERR_NONFINITE), int(Status.ERR_ARG)
CLAMPED, REJECTED = int(Warn.WARN_CLAMPED), int(Warn.WARN_REJECTED)
N_BAD = 5
NAN_VALUES, INF_VALUES = (0, 1, 2), (3, 4)
N_WEIGH = 15                     # the harness's NF_WEIGH_CASES: its first rows
SCALE_ROWS = [5, 13]             # its NF_SCALE_APPLY_CASE, NF_SCALE_INIT_CASE

# (case, status for every value or {value: status}); nf_kept must be 1
# everywhere: state and outputs untouched on an error, the output finite (or
# the reference) where the sample is replaced or the temperature clamped.
TEMPERATURE = {**dict.fromkeys(NAN_VALUES, NONFINITE), **dict.fromkeys(INF_VALUES, CLAMPED)}
NF_CASES = [
    # the weighing stages (NF_WEIGH_CASES of the harness)
    ("sig_kalman1_step_f fresh", NONFINITE), ("sig_kalman1_step_f seeded", NONFINITE),
    ("sig_limit_step_f fresh", NONFINITE), ("sig_stable_step_f", NONFINITE),
    ("sig_antipulse_step_f", NONFINITE), ("sig_scale_apply_f", NONFINITE),
    ("sig_chain_step_f before the first finite sample", NONFINITE),
    ("sig_limit_step_f seeded: replaced by the reference", REJECTED),
    ("sig_chain_step_f seeded: replaced", REJECTED),
    ("sig_noise_step_f: not an update", REJECTED),
    ("sig_kalman1_init_f", ARG), ("sig_limit_init_f", ARG), ("sig_stable_init_f", ARG),
    ("sig_scale_init_f", NONFINITE), ("sig_chain_init_f", ARG),
    # the calibration models
    ("sig_lag_step_f", NONFINITE), ("sig_hyst_step_f", NONFINITE),
    ("sig_creep_step_f", NONFINITE), ("sig_gain_apply_f x", NONFINITE),
    ("sig_gain_apply_f u", NONFINITE), ("sig_nonlin_apply_f", NONFINITE),
    ("sig_cross_apply_f x", NONFINITE), ("sig_cross_apply_f other axis", NONFINITE),
    ("sig_tcomp_apply_f reading", NONFINITE), ("sig_poly_horner_f", NONFINITE),
    ("sig_tcomp_apply_f temperature", TEMPERATURE), ("sig_pwl_eval_f temperature", TEMPERATURE),
    ("sig_lag_init_f", ARG), ("sig_hyst_init_f", ARG), ("sig_creep_init_f", ARG),
    ("sig_gain_init_f", NONFINITE), ("sig_nonlin_init_f", ARG), ("sig_cross_init_f", NONFINITE),
    ("sig_tcomp_init_f", NONFINITE), ("sig_pwl_init_f", NONFINITE),
]


def expected_status():
    want = np.empty((len(NF_CASES), N_BAD), dtype=int)
    for c, (_, st) in enumerate(NF_CASES):
        want[c] = [st[v] if isinstance(st, dict) else st for v in range(N_BAD)]
    return want


def check(status, kept, where):
    want = expected_status()
    bad = [f"{NF_CASES[c][0]} value {v}: status {status[c, v]} (want {want[c, v]}), "
           f"kept {kept[c, v]}"
           for c in range(len(NF_CASES)) for v in range(N_BAD)
           if status[c, v] != want[c, v] or kept[c, v] != 1]
    assert not bad, f"{where}: " + "; ".join(bad)


def sources(modules=WEIGH_MODULES + CALIB_MODULES):
    """The csrc files the harness needs (sdcc links every module it is given)."""
    return runner.csrc_sources(*modules)


def test_host_float_build(tmp_path):
    """The same harness on the host (gcc, float sig_real): the reference the
    targets are compared with, itself checked against the table."""
    gcc = require_tool("gcc")
    exe = tmp_path / "nonfinite"
    build = subprocess.run([gcc, "-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-DNF_HOST_PRINT",
                            f"-I{runner.CSRC_INCLUDE}", f"-I{HARNESS.parent}", HARNESS, *sources(),
                            "-o", exe], capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    out = subprocess.run([exe], check=True, capture_output=True, text=True).stdout
    assert re.search(r"^init 0$", out, re.M), out[:200]
    status = np.zeros((len(NF_CASES), N_BAD), dtype=int)
    kept = np.zeros_like(status)
    rows = re.findall(r"^(\d+) (\d+) (-?\d+) (\d+)$", out, re.M)
    assert len(rows) == status.size
    for c, v, s, k in rows:
        status[int(c), int(v)], kept[int(c), int(v)] = int(s), int(k)
    check(status, kept, "host")


def run_target(target, defines, modules=WEIGH_MODULES + CALIB_MODULES):
    if target == "msp430":
        img = runner.build_msp430(sources(modules), HARNESS, defines, hwmult=True)
    else:
        img = runner.build_mcs51(sources(modules), HARNESS, defines, extra_flags=["--stack-auto"])
    n = len(NF_CASES) * N_BAD
    r = runner.measure(img, reads={"nf_status": 2 * n, "nf_kept": n, "init_status": 2},
                       stack=False)["reads"]
    assert np.frombuffer(r["init_status"], "<i2")[0] == 0
    return (np.frombuffer(r["nf_status"], "<i2").reshape(len(NF_CASES), N_BAD).astype(int),
            np.frombuffer(r["nf_kept"], "u1").reshape(len(NF_CASES), N_BAD).astype(int))


@pytest.mark.parametrize("target", ["msp430", "mcs51"])
def test_target_guards_equal_the_host(target):
    """MSP430: one program; 8051: the weighing half and the calibration half
    as two programs (the whole is over 64 KB of 8051 code), sig_scale's rows
    in the calibration half's."""
    require_target_tools(target)
    if target == "msp430":
        status, kept = run_target(target, [])
    else:
        status, kept = run_target(target, ["NF_ONLY_WEIGH"], MCS51_WEIGH_MODULES)
        calib_status, calib_kept = run_target(target, ["NF_ONLY_CALIB"], MCS51_CALIB_MODULES)
        rows = SCALE_ROWS + list(range(N_WEIGH, len(NF_CASES)))
        status[rows], kept[rows] = calib_status[rows], calib_kept[rows]
    check(status, kept, target)
