"""Firmware == Python: the very csrc/ code, built for the MSP430F5510 (clang,
hardware-multiplier helpers on mspdebug's simulated multiplier, and the
no-multiplier build) and for the 8051 (sdcc --model-large --stack-auto), runs
a batch of test vectors inside the simulators; the outputs read back must equal the host
C (through Cython) and the pure-Python reference bit for bit on the
fixed-point path.  Float path: the MCUs compute in IEEE single, the host in
double, so outputs agree within a stated tolerance and the status flags are
identical.  Both targets build with warnings as errors."""
import struct

import numpy as np
import pytest

from conftest import ROOT, require_target_tools
from lab.mcu import runner
from lab.mcu import vectors

HARNESS = ROOT / "bench" / "mcu" / "harness"
TCOMP_SRC = runner.csrc_sources("sig_tcomp")     # + sig_poly, sig_image, sig_crc16
CHAIN_SRC = runner.csrc_sources("sig_chain")     # + limit, antipulse, kalman1, stable, ...

# float32 firmware vs float64 host: |difference| <= REL * max(1, |value|)
TCOMP_F_REL = 2e-6       # a few float32 ulps of a reading of up to 32768 LSB
CHAIN_F_REL = 1e-5       # Kalman/trimmed mean in float32 over 200 samples


# sdcc --model-large alone links neither csrc/tcomp/sig_tcomp.c + sig_poly.c nor the
# chain: sdcc keeps the spill temporaries of every non-reentrant function in
# the 8051's 128-byte direct RAM (chain modules: ~390 bytes).  With
# --stack-auto they live on the stack in internal RAM instead, and the runner
# links sdcc's assembly __mullong (bench/mcu/README.md, "8051 memory").
MCS51_TCOMP_FLAGS = ["--stack-auto"]
MCS51_CHAIN_FLAGS = ["--stack-auto"]


def _build_chain_mcs51(defines, gen):
    return runner.build_mcs51(CHAIN_SRC, HARNESS / "chain_harness.c", defines,
                              include_dirs=[gen], extra_flags=MCS51_CHAIN_FLAGS)


def _build(target, sources, harness, defines, gen, hwmult=True, mcs51_flags=()):
    if target == "msp430":
        return runner.build_msp430(sources, harness, defines, hwmult=hwmult, include_dirs=[gen])
    return runner.build_mcs51(sources, harness, defines, include_dirs=[gen],
                              extra_flags=mcs51_flags)


def _run(img, reads):
    return runner.measure(img, reads=reads, stack=False)["reads"]


# ------------------------------------------------------------------ tcomp ---
def _tcomp_model_dicts(case):
    fixed = dict(coef=[list(map(int, r)) for r in case.coef_q], q=list(map(int, case.q)),
                 t_lo=case.t_lo, t_hi=case.t_hi, t_center=case.t_center,
                 u_mul=case.u_mul, u_shift=case.u_shift)
    flt = dict(coef=[list(map(float, r)) for r in case.coef_f], t_lo=float(np.float32(case.t_lo / 100)),
               t_hi=float(np.float32(case.t_hi / 100)), center=float(case.center_f),
               inv_scale=float(case.inv_scale_f))
    return fixed, flt


@pytest.mark.parametrize("target,hwmult,order", [
    ("msp430", True, 2), ("msp430", True, 5), ("msp430", False, 2), ("mcs51", None, 2)],
    ids=["msp430-hw-o2", "msp430-hw-o5", "msp430-sw-o2", "mcs51-o2"])
def test_tcomp_fixed_firmware_equals_host_and_reference(target, hwmult, order, tmp_path):
    require_target_tools(target)
    from pysig.tcomp._tcomp import TcompQ
    from spec import tcomp as ref
    case = vectors.tcomp_case(order)
    vectors.write_tcomp_header(case, tmp_path / "tcomp_vectors.h")
    img = _build(target, TCOMP_SRC, HARNESS / "tcomp_harness.c", [], tmp_path, hwmult,
                 MCS51_TCOMP_FLAGS)
    n, a = case.in_q.shape
    r = _run(img, {"vec_out": 2 * n * a, "vec_status": 2 * n, "init_status": 2})
    assert struct.unpack("<h", r["init_status"])[0] == 0
    fw_out = np.frombuffer(r["vec_out"], "<i2").reshape(n, a)
    fw_st = np.frombuffer(r["vec_status"], "<i2")

    host = TcompQ.from_fields(case.coef_q, case.q, case.t_lo, case.t_hi, case.t_center, case.t0,
                              case.u_mul, case.u_shift)
    h_out, h_st = host.apply(case.t_q, case.in_q)
    np.testing.assert_array_equal(fw_out, h_out)
    np.testing.assert_array_equal(fw_st, h_st)

    model, _ = _tcomp_model_dicts(case)
    for i in range(n):
        out, st = ref.apply_q(model, int(case.t_q[i]), [int(v) for v in case.in_q[i]])
        assert list(fw_out[i]) == out and fw_st[i] == st, f"vector {i}"
    # the batch exercises clamping and saturation, not only the easy path
    assert (fw_st & 1).any() and (fw_st & 2).any() and (fw_st == 0).any()


@pytest.mark.parametrize("target", ["msp430", "mcs51"])
def test_tcomp_float_firmware_within_tolerance(target, tmp_path):
    require_target_tools(target)
    from pysig.tcomp._tcomp import TcompF
    from spec import tcomp as ref
    case = vectors.tcomp_case(2)
    vectors.write_tcomp_header(case, tmp_path / "tcomp_vectors.h")
    img = _build(target, TCOMP_SRC, HARNESS / "tcomp_harness.c", ["BENCH_FLOAT"], tmp_path,
                 mcs51_flags=MCS51_TCOMP_FLAGS)
    n, a = case.in_q.shape
    r = _run(img, {"vec_out": 4 * n * a, "vec_status": 2 * n, "init_status": 2})
    assert struct.unpack("<h", r["init_status"])[0] == 0
    fw_out = np.frombuffer(r["vec_out"], "<f4").reshape(n, a).astype(float)
    fw_st = np.frombuffer(r["vec_status"], "<i2")
    _, model = _tcomp_model_dicts(case)
    host = TcompF(model["coef"], model["t_lo"], model["t_hi"], model["center"], model["inv_scale"])
    h_out, h_st = host.apply(case.t_f.astype(float), case.in_f.astype(float))
    np.testing.assert_array_equal(fw_st, h_st)
    assert np.all(np.abs(fw_out - h_out) <= TCOMP_F_REL * np.maximum(1, np.abs(h_out)))
    for i in range(n):
        out, st = ref.apply_f(model, float(case.t_f[i]), [float(v) for v in case.in_f[i]])
        assert st == fw_st[i]
        assert np.allclose(fw_out[i], out, rtol=TCOMP_F_REL, atol=TCOMP_F_REL)


# ------------------------------------------------------------------ chain ---
def _chain_reads(img, n, real):
    r = _run(img, {"vec_out": 4 * n, "vec_stable": n, "vec_status": 2 * n, "init_status": 2})
    assert struct.unpack("<h", r["init_status"])[0] == 0
    out = np.frombuffer(r["vec_out"], "<f4" if real else "<i4")
    return out, np.frombuffer(r["vec_stable"], np.uint8).astype(bool), \
        np.frombuffer(r["vec_status"], "<i2")


@pytest.mark.parametrize("target,hwmult", [("msp430", True), ("msp430", False), ("mcs51", None)],
                         ids=["msp430-hw", "msp430-sw", "mcs51"])
def test_chain_fixed_firmware_equals_host_and_reference(target, hwmult, tmp_path):
    require_target_tools(target)
    from pysig.weigh import Chain
    from spec.chain import Chain as RefChain
    case = vectors.chain_case()
    vectors.write_chain_header(case, tmp_path / "chain_vectors.h")
    img = (_build_chain_mcs51([], tmp_path) if target == "mcs51" else
           _build(target, CHAIN_SRC, HARNESS / "chain_harness.c", [], tmp_path, hwmult))
    fw_q7, fw_stable, fw_st = _chain_reads(img, len(case.x), real=False)
    for chain in (Chain(case.preset, fixed=True), RefChain(case.preset, fixed=True)):
        out, stable, st = chain.process(case.x.astype(float), flags=True)
        np.testing.assert_array_equal(fw_q7, np.round(out * 128).astype(np.int64))
        np.testing.assert_array_equal(fw_stable, stable)
        np.testing.assert_array_equal(fw_st, st)
    assert fw_stable.any() and (fw_st != 0).any()    # settles, and rejects the impulses


@pytest.mark.parametrize("target", ["msp430", "mcs51"])
def test_chain_float_firmware_within_tolerance(target, tmp_path):
    require_target_tools(target)
    from pysig.weigh import Chain
    case = vectors.chain_case()
    vectors.write_chain_header(case, tmp_path / "chain_vectors.h")
    img = (_build_chain_mcs51(["BENCH_FLOAT"], tmp_path) if target == "mcs51" else
           _build(target, CHAIN_SRC, HARNESS / "chain_harness.c", ["BENCH_FLOAT"], tmp_path))
    fw, fw_stable, fw_st = _chain_reads(img, len(case.x), real=True)
    out, stable, st = Chain(case.preset).process(case.x.astype(float), flags=True)
    np.testing.assert_array_equal(fw_st, st)
    assert np.all(np.abs(fw - out) <= CHAIN_F_REL * np.maximum(1, np.abs(out)))
    # the stability flag is a threshold decision on the output: allow a flip
    # only where the host output sits within float32 reach of the threshold
    assert (fw_stable != stable).sum() <= 2


@pytest.mark.parametrize("order,amplitude", [(2, 300.0), (3, 2e4)])
def test_tcomp_fast_experiment_is_bit_exact(order, amplitude, tmp_path):
    """bench/mcu/experiments/tcomp_fast.c (the 'what it would take' figure of
    bench/mcu_cost.py) computes exactly sig_tcomp_apply_q."""
    require_target_tools("msp430")
    from pysig.tcomp._tcomp import TcompQ
    case = vectors.tcomp_case(order, seed=3, amplitude=amplitude)   # 2e4: q < 16 path
    vectors.write_tcomp_header(case, tmp_path / "tcomp_vectors.h")
    exp = ROOT / "bench" / "mcu" / "experiments"
    img = runner.build_msp430(TCOMP_SRC + [exp / "tcomp_fast.c"], exp / "tcomp_fast_harness.c",
                              {"TCOMP_FAST_MPY_BASE": runner.MSP430_MPY_BASE_SIM}, hwmult=True,
                              include_dirs=[tmp_path])
    n, a = case.in_q.shape
    r = _run(img, {"vec_out": 2 * n * a, "vec_status": 2 * n})
    host = TcompQ.from_fields(case.coef_q, case.q, case.t_lo, case.t_hi, case.t_center, case.t0,
                              case.u_mul, case.u_shift)
    h_out, h_st = host.apply(case.t_q, case.in_q)
    np.testing.assert_array_equal(np.frombuffer(r["vec_out"], "<i2").reshape(n, a), h_out)
    np.testing.assert_array_equal(np.frombuffer(r["vec_status"], "<i2"), h_st)
