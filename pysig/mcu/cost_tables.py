"""The MCU cost rows: the csrc/ temperature compensation and weighing chain
built for the MSP430F5510 and the 8051, run in the instruction-set
simulators, their outputs read back and checked against the host C
(Cython) before a row is returned: a wrong build cannot produce a number.

Each row function returns a JSON-ready dict: code bytes (the function's call
tree, helpers apart), RAM (state + stack high-water), cycles per call and in
a batch, time and energy (MSP430F5510 at MCLK_HZ, I_ACTIVE_A), and next to
it an operation-count model read off the algorithm (tcomp_ops, chain_ops).
bench/mcu_cost.py prints them as its two tables.  Images built here are kept
in IMAGES for profiling.
"""
from __future__ import annotations

import numpy as np

from . import runner, tcomp16_vectors, vectors

CSRC = runner.CSRC
HARNESS = runner.MCU_DIR / "harness"
TCOMP_SRC = runner.csrc_sources("sig_tcomp")     # + sig_poly, sig_image, sig_crc16
TCOMP16_SRC = runner.csrc_sources("sig_tcomp16")  # the compact form (int16 multiplicands)
PORT_MSP430 = runner.PORT_MSP430   # sig_port_msp430.h: the fixed16_inline build
INLINE_DEFINES = {"SIG_PORT_HEADER": '"sig_port_msp430.h"', "MPY_BASE": runner.MSP430_MPY_BASE_SIM}
CHAIN_SRC = runner.csrc_sources("sig_chain")     # + limit, antipulse, kalman1, stable, ...
MCLK_HZ = 8_000_000          # MSP430F5510 as in the magnetometer paper
I_ACTIVE_A = 1.56e-3         # active current at 8 MHz (the magnetometer paper's figure)
MCS51_HZ = 12_000_000
AXES = 3

IMAGES = {}                  # (what, form, hwmult) -> (image, instructions): for profiles
TARGETS = {"tcomp_q2_hw_cycles": 300, "tcomp_float_over_fixed": 10.0, "chain_q_8051_clocks": 3000}


# ------------------------------------------------------ operation models ---
def tcomp_ops(form: str, order: int, axes: int = AXES) -> dict:
    """Operations of one sig_tcomp_apply_q/_f call, read off the algorithm in
    csrc/tcomp/sig_tcomp.c + sig_poly.c (in-range temperature, no saturation).
    fixed: scale u = (d*u_mul + r) >> s (one 16x16 product); per axis `order`
    Horner steps of floor(acc*u/2^15) = 2*hi*u + lo*u>>15 (two 16x16
    products, a 32-bit add with saturation test), then a rounding shift by q
    and a saturating subtract.  float: u = (T-c)*k; per axis `order` fmul +
    fadd, finiteness tests (x - x == 0) on u, acc and every input."""
    if form in ("fixed16", "fixed16_inline"):
        # sig_tcomp16_apply_q: v = t - t_lo, w = v << s (one shift loop); per
        # axis and level the high word of constant + 16x16 product (unsigned
        # for the inner levels, signed for the last), a 16-bit subtract of
        # w/2 per inner level, a 16-bit saturating subtract per axis.
        # fixed16: the product is a helper call and the 32-bit add is C;
        # fixed16_inline: one MAC/MACS with the constant preloaded = 5
        # multiplier-register accesses (RESLO, RESHI, MAC(S), OP2 written;
        # RESHI read) and no 32-bit add in software.
        ops = {"sub16": (order - 1) * axes + axes, "shift16_loop": 1, "compare": 4 + 2 * axes,
               "load16": 5 + axes * (2 * order + 2), "store16": axes}
        if form == "fixed16":
            return {"mul16x16": order * axes, "add32": order * axes, **ops}
        return {"mac16x16": order * axes, "mpy_reg_access": 5 * order * axes, **ops}
    if form == "fixed":
        return {"mul16x16": 1 + 2 * order * axes,
                "add32": 2 + axes * (2 * order + 3),
                "shift32": 1 + 2 * axes,
                "compare": 2 + axes * (2 * order + 2),
                "load16": 6 + axes * (2 * (order + 1) + 2),
                "store16": axes}
    return {"fmul": 1 + order * axes, "fadd_fsub": 1 + axes * (order + 1) + axes + 2 * axes,
            "fcmp": 4 + axes + 2 * axes, "load32": 4 + axes * (order + 2), "store32": axes}


def chain_ops(form: str, window: int = 12) -> dict:
    """One sig_chain_step in steady state (window full, no min/max rescan,
    Kalman gain converged: no Newton iteration), read off csrc/weigh/sig_limit.c,
    sig_antipulse.c, sig_kalman1.c, sig_stable.c, sig_chain.c.
    fixed: limit |x-Dc| > A0; window insert, running min/max, sum - old + x,
    trimmed sum / (N-2) by a reciprocal (sig_mulhi_u32: 4 16x16 products, one
    32-bit multiply-back); Kalman x += K*(z-x) with a Q30 gain (4 16x16
    products); motion, stability and zero-tracking tests.  The rescan case
    adds 2N compares."""
    if form == "fixed":
        return {"mul16x16": 8, "mul32": 1, "add32": 22, "compare": 24, "shift_const": 14,
                "load32": 18, "store32": 10, "div": 0}
    return {"fmul": 2, "fadd_fsub": 12, "fdiv": 1, "fcmp": 20, "load32": 18, "store32": 10}


# --------------------------------------------------------------- helpers ---
def _i16(b):
    return np.frombuffer(b, "<i2")


def tcomp_row(order: int, form: str, hwmult: bool, vdd: float) -> dict:
    case = vectors.tcomp_case(order)
    gen = runner.BUILD_DIR / "gen" / f"tcomp-o{order}"
    vectors.write_tcomp_header(case, gen / "tcomp_vectors.h")
    fl = form == "float"
    func = "sig_tcomp_apply_f" if fl else "sig_tcomp_apply_q"
    img = runner.build_msp430(TCOMP_SRC, HARNESS / "tcomp_harness.c",
                              ["BENCH_FLOAT"] if fl else [], hwmult=hwmult, include_dirs=[gen],
                              name=f"tcomp-o{order}-{form}")
    n, a = case.in_q.shape
    esize = 4 if fl else 2
    r = runner.measure(img, funcs=[func], regions=["bench_start:bench_stop"],
                       reads={"vec_out": esize * n * a, "vec_status": 2 * n})
    fw_st = _i16(r["reads"]["vec_status"])
    from ..tcomp._tcomp import TcompF, TcompQ
    if fl:
        fw = np.frombuffer(r["reads"]["vec_out"], "<f4").reshape(n, a).astype(float)
        host = TcompF(case.coef_f.astype(float), float(np.float32(case.t_lo / 100)),
                      float(np.float32(case.t_hi / 100)), float(case.center_f),
                      float(case.inv_scale_f))
        h_out, h_st = host.apply(case.t_f.astype(float), case.in_f.astype(float))
        ok = np.array_equal(fw_st, h_st) and np.all(np.abs(fw - h_out) <= 2e-6 * np.maximum(1, np.abs(h_out)))
    else:
        fw = _i16(r["reads"]["vec_out"]).reshape(n, a)
        host = TcompQ.from_fields(case.coef_q, case.q, case.t_lo, case.t_hi, case.t_center,
                                  case.t0, case.u_mul, case.u_shift)
        h_out, h_st = host.apply(case.t_q, case.in_q)
        ok = np.array_equal(fw, h_out) and np.array_equal(fw_st, h_st)
    if not ok:
        raise SystemExit(f"tcomp order {order} {form}: firmware results differ from the host C")
    clos = runner.code_closure(img, func)
    text = sum(v for k, v in clos.items() if not runner.is_helper(k))
    helpers = sum(v for k, v in clos.items() if runner.is_helper(k))
    one = r["funcs"][func]
    model_bytes = runner.symbol_size(img, "model")
    cycles = one["cycles"]
    t_us = cycles / MCLK_HZ * 1e6
    return {"target": "msp430f5510", "form": form, "order": order,
            "multiplier": "hw (16x16 MPY at 0x0130 in the simulator)" if hwmult else "none",
            "text_bytes": text, "helper_bytes": helpers,
            "ram_bytes": model_bytes + one["stack_bytes"], "model_bytes": model_bytes,
            "coef_bytes": a * (order + 1) * 4, "stack_bytes": one["stack_bytes"],
            "cycles": cycles, "instructions": one["instructions"],
            "cycles_avg_batch": round(r["regions"]["bench_start:bench_stop"]["cycles"] / n, 1),
            "time_us": round(t_us, 2), "energy_uj": round(I_ACTIVE_A * vdd * t_us, 4),
            "ops": tcomp_ops(form, order), "checked_vectors": n}


def tcomp16_row(order: int, hwmult: bool, vdd: float, inline: bool = False) -> dict:
    """The compact form (csrc/tcomp/sig_tcomp16.c) on the same temperatures and
    readings as tcomp_row, the same polynomial quantised by
    pysig.tcomp.quant.quantize_compact (bench/mcu/tcomp16_vectors.py), checked
    against the host C before the row is returned.  inline: the same C with
    the sig_port.h hooks of csrc/port/msp430/sig_port_msp430.h (multiplier
    MAC/MACS as volatile accesses, hw only)."""
    case = tcomp16_vectors.tcomp16_case(order)
    gen = runner.BUILD_DIR / "gen" / f"tcomp16-o{order}"
    tcomp16_vectors.write_tcomp16_header(case, gen / "tcomp16_vectors.h")
    func = "sig_tcomp16_apply_q"
    form = "fixed16_inline" if inline else "fixed16"
    img = runner.build_msp430(TCOMP16_SRC, HARNESS / "tcomp16_harness.c",
                              INLINE_DEFINES if inline else [], hwmult=hwmult,
                              include_dirs=[gen, PORT_MSP430] if inline else [gen],
                              name=f"tcomp16-o{order}" + ("-inline" if inline else ""))
    n, a = case.base.in_q.shape
    r = runner.measure(img, funcs=[func], regions=["bench_start:bench_stop"],
                       reads={"vec_out": 2 * n * a, "vec_status": 2 * n})
    from ..tcomp._tcomp16 import Tcomp16Q
    h_out, h_st = Tcomp16Q.from_compact(case.compact).apply(case.base.t_q, case.base.in_q)
    if not (np.array_equal(_i16(r["reads"]["vec_out"]).reshape(n, a), h_out)
            and np.array_equal(_i16(r["reads"]["vec_status"]), h_st)):
        raise SystemExit(f"tcomp16 order {order} {form}: firmware results differ from the host C")
    IMAGES[(form, order, hwmult)] = (img, r["funcs"][func]["instructions"])
    clos = runner.code_closure(img, func)
    if inline and any(runner.is_helper(k) for k in clos):
        raise SystemExit(f"tcomp16 order {order} {form}: the port hooks did not take effect ({clos})")
    one = r["funcs"][func]
    model_bytes = runner.symbol_size(img, "model")
    t_us = one["cycles"] / MCLK_HZ * 1e6
    return {"target": "msp430f5510", "form": form, "order": order,
            "multiplier": ("hw inline MAC/MACS (sig_port_msp430.h, 16x16 MPY at 0x0130 in the "
                           "simulator)" if inline else
                           "hw (16x16 MPY at 0x0130 in the simulator)" if hwmult else "none"),
            "text_bytes": sum(v for k, v in clos.items() if not runner.is_helper(k)),
            "helper_bytes": sum(v for k, v in clos.items() if runner.is_helper(k)),
            "ram_bytes": model_bytes + one["stack_bytes"], "model_bytes": model_bytes,
            "coef_bytes": a * (2 + 4 * order), "stack_bytes": one["stack_bytes"],
            "cycles": one["cycles"], "instructions": one["instructions"],
            "cycles_avg_batch": round(r["regions"]["bench_start:bench_stop"]["cycles"] / n, 1),
            "time_us": round(t_us, 2), "energy_uj": round(I_ACTIVE_A * vdd * t_us, 4),
            "ops": tcomp_ops(form, order), "checked_vectors": n,
            "drift_amplitude_lsb": round(case.amplitude, 1),
            "compact_error_lsb": round(max(case.compact.error_lsb), 4)}


def chain_rows_msp430(form: str, hwmult: bool, case, vdd: float) -> dict:
    gen = runner.BUILD_DIR / "gen" / "chain"
    vectors.write_chain_header(case, gen / "chain_vectors.h")
    fl = form == "float"
    func = "sig_chain_step_f" if fl else "sig_chain_step_q"
    img = runner.build_msp430(CHAIN_SRC, HARNESS / "chain_harness.c", ["BENCH_FLOAT"] if fl else [],
                              hwmult=hwmult, include_dirs=[gen], name=f"chain-{form}")
    n = len(case.x)
    r = runner.measure(img, funcs=[func], regions=["bench_start:bench_stop"],
                       reads={"vec_out": 4 * n, "vec_status": 2 * n})
    _check_chain(case, form, r["reads"])
    IMAGES[("chain", form, hwmult)] = (img, r["funcs"][func]["instructions"])
    clos = runner.code_closure(img, func)
    one = r["funcs"][func]
    state = runner.symbol_size(img, "chain")
    t_us = one["cycles"] / MCLK_HZ * 1e6
    return {"target": "msp430f5510", "form": form,
            "multiplier": "hw (16x16 MPY at 0x0130 in the simulator)" if hwmult else "none",
            "cycles": one["cycles"], "instructions": one["instructions"],
            "cycles_avg_batch": round(r["regions"]["bench_start:bench_stop"]["cycles"] / n, 1),
            "time_us": round(t_us, 1), "energy_uj": round(I_ACTIVE_A * vdd * t_us, 3),
            "text_bytes": sum(v for k, v in clos.items() if not runner.is_helper(k)),
            "helper_bytes": sum(v for k, v in clos.items() if runner.is_helper(k)),
            "ram_bytes": state + one["stack_bytes"], "state_bytes": state,
            "stack_bytes": one["stack_bytes"], "ops": chain_ops(form), "checked_samples": n}


def _check_chain(case, form, reads):
    from ..weigh.chain import Chain
    n = len(case.x)
    out, _, st = Chain(case.preset, fixed=form == "fixed").process(case.x.astype(float), flags=True)
    fw_st = _i16(reads["vec_status"])
    if form == "fixed":
        fw = np.frombuffer(reads["vec_out"], "<i4")
        ok = np.array_equal(fw, np.round(out * 128).astype(np.int64))
    else:
        fw = np.frombuffer(reads["vec_out"], "<f4").astype(float)
        ok = np.all(np.abs(fw - out) <= 1e-5 * np.maximum(1, np.abs(out)))
    if not (ok and np.array_equal(fw_st, st)):
        raise SystemExit(f"chain {form}: firmware results differ from the host C ({n} samples)")


MCS51_CHAIN_FLAGS = ["--stack-auto"]


def chain_row_mcs51(form: str, case) -> dict:
    """The 8051 build: sdcc --model-large --stack-auto (state and vectors in
    xdata; locals and spill temporaries on the stack in internal RAM, which
    plain --model-large cannot hold: bench/mcu/README.md), sdcc's assembly
    __mullong (runner.mcs51_runtime).  12T clocks from s51; 1T estimate =
    opcode histogram x STC-Y5 table.  Code: the functions reachable from the
    step (.rst call graph); RAM: chain state (xdata) + internal-RAM stack
    high-water of the call."""
    gen = runner.BUILD_DIR / "gen" / "chain"
    vectors.write_chain_header(case, gen / "chain_vectors.h")
    fl = form == "float"
    func = "sig_chain_step_f" if fl else "sig_chain_step_q"
    row = {"target": "8051 (s51 -t C52, sdcc --model-large --stack-auto)", "form": form,
           "ops": chain_ops(form)}
    try:
        img = runner.build_mcs51(CHAIN_SRC, HARNESS / "chain_harness.c",
                                 ["BENCH_FLOAT"] if fl else [], include_dirs=[gen],
                                 name=f"chain-{form}", extra_flags=MCS51_CHAIN_FLAGS)
    except runner.McuError as e:
        row.update(status="does not build", error=[ln for ln in str(e).splitlines()
                                                    if "ASlink-Error" in ln or "warning" in ln])
        return row
    n = len(case.x)
    r = runner.measure(img, funcs=[func], regions=["bench_start:bench_stop"],
                       reads={"vec_out": 4 * n, "vec_status": 2 * n})
    if r["total"].get("stack_overflow"):
        raise SystemExit(f"chain {form} on the 8051: the stack passed 0xFF (s51)")
    _check_chain(case, form, r["reads"])
    IMAGES[("chain", form, "mcs51")] = (img, r["funcs"][func]["instructions"])
    one = r["funcs"][func]
    clos = runner.code_closure(img, func)
    state = _mcs51_xdata_size(img, "chain")
    row.update(status="ok", clocks_12T=one["cycles"], instructions=one["instructions"],
               clocks_12T_avg_batch=round(r["regions"]["bench_start:bench_stop"]["cycles"] / n, 1),
               ms_12MHz_12T=round(one["cycles"] / MCS51_HZ * 1e3, 3),
               clocks_1T_estimate=one["clocks_1t_stc_y5"],
               us_1T_estimate_12MHz=round(one["clocks_1t_stc_y5"] / MCS51_HZ * 1e6, 1),
               code_bytes_fetched=one["code_bytes_fetched"],
               text_bytes=sum(v for k, v in clos.items() if not runner.is_helper(k)),
               helper_bytes=sum(v for k, v in clos.items() if runner.is_helper(k)),
               state_bytes=state, stack_bytes=one["stack_bytes"],
               ram_bytes=state + one["stack_bytes"],
               max_sp_batch=hex(r["total"]["max_sp"]) if "max_sp" in r["total"] else None,
               checked_samples=n)
    return row


def _mcs51_xdata_size(img, name: str) -> int:
    """bytes of an xdata variable: distance to the next xdata symbol (.map)."""
    xs = sorted(a for sp, a in img.symbols.values() if sp == "xram")
    a = img.symbols["_" + name][1]
    return next(x for x in xs if x > a) - a


def tcomp_fast_row(order: int, vdd: float) -> dict:
    """EXPERIMENT (bench/mcu/experiments/tcomp_fast.c): the same compensation,
    bit-exact, spelt for the MSP430 (inline 16x16 multiplier access, word-wise
    shifts).  Shows what a csrc/ change along these lines buys."""
    case = vectors.tcomp_case(order)
    gen = runner.BUILD_DIR / "gen" / f"tcomp-o{order}"
    vectors.write_tcomp_header(case, gen / "tcomp_vectors.h")
    exp = runner.MCU_DIR / "experiments"
    img = runner.build_msp430(TCOMP_SRC + [exp / "tcomp_fast.c"], exp / "tcomp_fast_harness.c",
                              {"TCOMP_FAST_MPY_BASE": runner.MSP430_MPY_BASE_SIM}, hwmult=True,
                              include_dirs=[gen], name=f"tcomp-fast-o{order}")
    n, a = case.in_q.shape
    r = runner.measure(img, funcs=["tcomp_fast_apply_q"], regions=["bench_start:bench_stop"],
                       reads={"vec_out": 2 * n * a, "vec_status": 2 * n})
    from ..tcomp._tcomp import TcompQ
    host = TcompQ.from_fields(case.coef_q, case.q, case.t_lo, case.t_hi, case.t_center,
                              case.t0, case.u_mul, case.u_shift)
    h_out, h_st = host.apply(case.t_q, case.in_q)
    if not (np.array_equal(_i16(r["reads"]["vec_out"]).reshape(n, a), h_out)
            and np.array_equal(_i16(r["reads"]["vec_status"]), h_st)):
        raise SystemExit("tcomp_fast: results differ from the host C")
    one = r["funcs"]["tcomp_fast_apply_q"]
    clos = runner.code_closure(img, "tcomp_fast_apply_q")
    t_us = one["cycles"] / MCLK_HZ * 1e6
    return {"target": "msp430f5510", "form": "fixed (experiment: tcomp_fast.c)", "order": order,
            "multiplier": "hw inline (16x16 MPY at 0x0130 in the simulator)",
            "text_bytes": sum(v for k, v in clos.items() if not runner.is_helper(k)),
            "stack_bytes": one["stack_bytes"], "cycles": one["cycles"],
            "instructions": one["instructions"],
            "cycles_avg_batch": round(r["regions"]["bench_start:bench_stop"]["cycles"] / n, 1),
            "time_us": round(t_us, 2), "energy_uj": round(I_ACTIVE_A * vdd * t_us, 4),
            "checked_vectors": n}


def tcomp_row_mcs51(order: int) -> dict:
    """Compensation on the 8051 for reference: --model-large does not link
    (internal RAM), so this build adds --stack-auto (locals on the stack)."""
    case = vectors.tcomp_case(order)
    gen = runner.BUILD_DIR / "gen" / f"tcomp-o{order}"
    vectors.write_tcomp_header(case, gen / "tcomp_vectors.h")
    img = runner.build_mcs51(TCOMP_SRC, HARNESS / "tcomp_harness.c", [], include_dirs=[gen],
                             name=f"tcomp-o{order}", extra_flags=["--stack-auto"])
    n, a = case.in_q.shape
    r = runner.measure(img, funcs=["sig_tcomp_apply_q"], reads={"vec_out": 2 * n * a})
    from ..tcomp._tcomp import TcompQ
    host = TcompQ.from_fields(case.coef_q, case.q, case.t_lo, case.t_hi, case.t_center,
                              case.t0, case.u_mul, case.u_shift)
    if not np.array_equal(_i16(r["reads"]["vec_out"]).reshape(n, a), host.apply(case.t_q, case.in_q)[0]):
        raise SystemExit("tcomp on the 8051: firmware results differ from the host C")
    one = r["funcs"]["sig_tcomp_apply_q"]
    return {"target": "8051 (s51 -t C52, sdcc --model-large --stack-auto)", "form": "fixed",
            "order": order, "clocks_12T": one["cycles"], "instructions": one["instructions"],
            "clocks_1T_estimate": one["clocks_1t_stc_y5"], "stack_bytes": one["stack_bytes"]}
