"""MCU cost tables, measured in instruction-set simulators from the csrc/ code.

    python bench/mcu_cost.py [--json FILE] [--vdd 3.3] [--orders 1-5]

Table 1 (the magnetometer paper's Table 2): temperature compensation of 3 axes
(sig_tcomp_apply_q / _f) per polynomial order, fixed and float, and the
compact fixed form (sig_tcomp16_apply_q): "fixed16" as portable C (clang
calls the multiply helper per product) and "fixed16_inline" with the
csrc/include/sig_port.h hooks mapped onto the multiplier's MAC/MACS by
csrc/port/msp430/sig_port_msp430.h (plain C volatile accesses), on the
MSP430F5510 at 8 MHz: .text bytes of the compensation code, RAM (model +
stack high-water), cycles per call, time, energy per call at 1.56 mA and VDD.
Table 2: one weighing-chain step (sig_chain_step_q / _f) on the MSP430 and
the 8051 (12T clocks from s51, 1T estimate for the STC12C5A60S2).
Next to every figure: an operation-count model from the algorithm.

Every row is built from source, run in mspdebug 0.22 `sim` / ucsim s51, and
its outputs are read back and checked against the host C (Cython) before the
row is printed: a wrong build cannot produce a number here.
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from pysig.mcu import runner
from pysig.mcu import tcomp16_vectors
from pysig.mcu import vectors

ROOT = Path(__file__).resolve().parent.parent

CSRC = runner.CSRC
HARNESS = ROOT / "bench" / "mcu" / "harness"
TCOMP_SRC = runner.csrc_sources("sig_tcomp")     # + sig_poly, sig_image, sig_crc16
TCOMP16_SRC = runner.csrc_sources("sig_tcomp16")  # the compact form (int16 multiplicands)
PORT_MSP430 = runner.PORT_MSP430   # sig_port_msp430.h: the fixed16_inline build
INLINE_DEFINES = {"SIG_PORT_HEADER": '"sig_port_msp430.h"', "MPY_BASE": runner.MSP430_MPY_BASE_SIM}
CHAIN_SRC = runner.csrc_sources("sig_chain")     # + limit, antipulse, kalman1, stable, ...
MCLK_HZ = 8_000_000          # MSP430F5510 as in the magnetometer paper
I_ACTIVE_A = 1.56e-3         # active current at 8 MHz (the magnetometer paper's figure)
MCS51_HZ = 12_000_000
AXES = 3

_IMAGES = {}                 # (what, form, hwmult) -> (image, instructions): for profiles
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
    from pysig.tcomp._tcomp import TcompF, TcompQ
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
    from pysig.tcomp._tcomp16 import Tcomp16Q
    h_out, h_st = Tcomp16Q.from_compact(case.compact).apply(case.base.t_q, case.base.in_q)
    if not (np.array_equal(_i16(r["reads"]["vec_out"]).reshape(n, a), h_out)
            and np.array_equal(_i16(r["reads"]["vec_status"]), h_st)):
        raise SystemExit(f"tcomp16 order {order} {form}: firmware results differ from the host C")
    _IMAGES[(form, order, hwmult)] = (img, r["funcs"][func]["instructions"])
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
    _IMAGES[("chain", form, hwmult)] = (img, r["funcs"][func]["instructions"])
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
    from pysig.weigh.chain import Chain
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
    _IMAGES[("chain", form, "mcs51")] = (img, r["funcs"][func]["instructions"])
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
    exp = ROOT / "bench" / "mcu" / "experiments"
    img = runner.build_msp430(TCOMP_SRC + [exp / "tcomp_fast.c"], exp / "tcomp_fast_harness.c",
                              {"TCOMP_FAST_MPY_BASE": runner.MSP430_MPY_BASE_SIM}, hwmult=True,
                              include_dirs=[gen], name=f"tcomp-fast-o{order}")
    n, a = case.in_q.shape
    r = runner.measure(img, funcs=["tcomp_fast_apply_q"], regions=["bench_start:bench_stop"],
                       reads={"vec_out": 2 * n * a, "vec_status": 2 * n})
    from pysig.tcomp._tcomp import TcompQ
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
    from pysig.tcomp._tcomp import TcompQ
    host = TcompQ.from_fields(case.coef_q, case.q, case.t_lo, case.t_hi, case.t_center,
                              case.t0, case.u_mul, case.u_shift)
    if not np.array_equal(_i16(r["reads"]["vec_out"]).reshape(n, a), host.apply(case.t_q, case.in_q)[0]):
        raise SystemExit("tcomp on the 8051: firmware results differ from the host C")
    one = r["funcs"]["sig_tcomp_apply_q"]
    return {"target": "8051 (s51 -t C52, sdcc --model-large --stack-auto)", "form": "fixed",
            "order": order, "clocks_12T": one["cycles"], "instructions": one["instructions"],
            "clocks_1T_estimate": one["clocks_1t_stc_y5"], "stack_bytes": one["stack_bytes"]}


# ----------------------------------------------------------------- output ---
def _table(rows, cols):
    w = [max(len(c), *(len(str(r.get(c, ""))) for r in rows)) for c in cols]
    lines = ["  ".join(c.rjust(x) for c, x in zip(cols, w))]
    lines += ["  ".join(str(r.get(c, "")).rjust(x) for c, x in zip(cols, w)) for r in rows]
    return "\n".join(lines)


def _orders(s):
    if "-" in s:
        a, b = s.split("-")
        return list(range(int(a), int(b) + 1))
    return [int(v) for v in s.split(",")]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", type=Path, help="write all rows here")
    ap.add_argument("--vdd", type=float, default=3.3, help="supply voltage for the energy column (V)")
    ap.add_argument("--orders", default="1-5", help="polynomial orders, e.g. 1-5 or 2,4")
    ap.add_argument("--no-8051", action="store_true", help="skip the 8051 rows")
    ap.add_argument("--table", choices=["1", "2", "all"], default="all", help="which table(s)")
    a = ap.parse_args(argv)

    t1, t2, t3 = [], [], []
    for hw in (True, False) if a.table in ("1", "all") else ():
        for form in ("fixed", "fixed16", "fixed16_inline", "float"):
            if form == "fixed16_inline" and not hw:
                continue                    # the hooks are the multiplier's
            for order in _orders(a.orders):
                t1.append(tcomp16_row(order, hw, a.vdd, inline=form == "fixed16_inline")
                          if form.startswith("fixed16") else tcomp_row(order, form, hw, a.vdd))
    if t1:
        print_table1(t1, a)
    if a.table in ("2", "all"):
        t2, t3 = table2(a)
    checks, profiles, experiment = targets(t1, t2, a)
    if a.json:
        a.json.parent.mkdir(parents=True, exist_ok=True)
        a.json.write_text(json.dumps({
            "meta": {"mclk_hz": MCLK_HZ, "i_active_a": I_ACTIVE_A, "vdd_v": a.vdd,
                     "msp430_sim": "mspdebug 0.22 sim, classic MSP430 cycle table",
                     "msp430_helpers": "bench/mcu/msp430 (rt_hwmul.c with MPY_BASE=0x0130 for hw)",
                     "mcs51_sim": "ucsim s51 0.6.4 -t C52 (12T); 1T estimate = opcode histogram "
                                  "x STC-Y5 published clocks (bench/mcu/mcs51/timing.py)"},
            "table1": t1, "table2": t2, "mcs51_tcomp": t3, "targets": checks,
            "experiment_tcomp_fast": experiment, "profiles": profiles}, indent=1))
        print(f"\nwrote {a.json}")


def print_table1(t1, a):
    print(f"Table 1 - temperature compensation, 3 axes, MSP430F5510 @ 8 MHz "
          f"(mspdebug 0.22 sim, classic MSP430 timing), energy at {I_ACTIVE_A * 1e3:.2f} mA, "
          f"{a.vdd} V")
    cols = ["multiplier", "form", "order", "text_bytes", "helper_bytes", "ram_bytes", "stack_bytes",
            "cycles", "cycles_avg_batch", "time_us", "energy_uj", "compact_error_lsb",
            "drift_amplitude_lsb"]
    print(_table([dict(r, multiplier="hw" if r["multiplier"] != "none" else "none") for r in t1], cols))
    print("fixed = sig_tcomp (int32 coefficients, Q15 abscissa); fixed16 = sig_tcomp16 (int16 "
          "multiplicands, 16x16 multiply-accumulates; compact_error_lsb: its measured quantisation "
          "error over every 0.01 degC of the range, on top of the 0.5 LSB output rounding); "
          "fixed16_inline = the same C with the csrc/include/sig_port.h hooks of "
          "csrc/port/msp430/sig_port_msp430.h (MAC/MACS on the multiplier, no helper calls; "
          "assumes no ISR uses the multiplier)")
    print("ops model per call (fixed | fixed16 | fixed16_inline | float):")
    for order in _orders(a.orders):
        print(f"  order {order}: {tcomp_ops('fixed', order)} | {tcomp_ops('fixed16', order)} | "
              f"{tcomp_ops('fixed16_inline', order)} | {tcomp_ops('float', order)}")


def table2(a):
    case = vectors.chain_case()
    t2 = [chain_rows_msp430(f, hw, case, a.vdd) for hw in (True, False) for f in ("fixed", "float")]
    if not a.no_8051:
        t2 += [chain_row_mcs51(f, case) for f in ("fixed", "float")]
    print("\nTable 2 - one weighing-chain step (limit + anti-pulse + Kalman + stability), "
          f"preset {case.preset!r}, {len(case.x)} samples")
    cols = ["target", "multiplier", "form", "cycles", "cycles_avg_batch", "time_us", "text_bytes",
            "helper_bytes", "ram_bytes", "stack_bytes", "clocks_12T", "clocks_12T_avg_batch",
            "clocks_1T_estimate", "status"]
    print(_table(t2, cols))
    for r in t2:
        if r.get("status") == "does not build":
            print(f"  {r['target']} {r['form']}: does not build - {'; '.join(r['error'])}")
        elif r["target"].startswith("8051"):
            print(f"  {r['target']} {r['form']}: {r['ms_12MHz_12T']} ms at 12 MHz (12T), "
                  f"~{r['us_1T_estimate_12MHz']} us 1T estimate; state {r['state_bytes']} B xdata, "
                  f"stack {r['stack_bytes']} B internal RAM (batch SP max {r['max_sp_batch']} "
                  f"of 0xFF)")
    print("ops model per step:", {f: chain_ops(f) for f in ("fixed", "float")})

    t3 = [] if a.no_8051 else [tcomp_row_mcs51(2)]
    if t3:
        print("\n8051 compensation, order 2, 3 axes:", json.dumps(t3[0]))
    return t2, t3


def targets(t1, t2, a):
    def pick(form, order, hw=True):
        return next(r for r in t1 if r["form"] == form and r["order"] == order
                    and (r["multiplier"] != "none") == hw)
    checks = []
    if t1 and 2 in _orders(a.orders):
        f2 = pick("float", 2)
        for form, label in (("fixed", "fixed"), ("fixed16", "fixed16 (compact)"),
                            ("fixed16_inline", "fixed16_inline (compact, port hooks)")):
            r2 = pick(form, 2)
            checks.append({"target": f"{label} order-2, 3 axes, MSP430 hw <= 300 cycles",
                           "measured": r2["cycles"], "met": r2["cycles"] <= 300})
            checks.append({"target": f"float/{form} cycles >= 10x (order 2, hw)",
                           "measured": round(f2["cycles"] / r2["cycles"], 2),
                           "met": f2["cycles"] >= 10 * r2["cycles"]})
    c51 = next((r for r in t2 if r["target"].startswith("8051") and r["form"] == "fixed"), None)
    if c51:
        checks.append({"target": "fixed chain step on the 8051 <= 3000 12T clocks",
                       "measured": c51.get("clocks_12T", c51.get("status")),
                       "met": c51.get("status") == "ok" and c51["clocks_12T"] <= 3000})
    print("\nTargets:")
    for c in checks:
        print(f"  {'MET ' if c['met'] else 'MISS'} {c['target']}: {c['measured']}")
    profiles, experiment = {}, None
    if t1 and checks and not checks[0]["met"]:
        experiment = tcomp_fast_row(2, a.vdd)
        print(f"  what it would take - bench/mcu/experiments/tcomp_fast.c (bit-exact, inline "
              f"multiplier, word-wise shifts): {experiment['cycles']} cycles, "
              f"{experiment['text_bytes']} B; float/this = "
              f"{pick('float', 2)['cycles'] / experiment['cycles']:.1f}x")
        img = runner.build_msp430(TCOMP_SRC, HARNESS / "tcomp_harness.c", [], hwmult=True,
                                  include_dirs=[runner.BUILD_DIR / "gen" / "tcomp-o2"],
                                  name="tcomp-o2-fixed")
        prof = runner.profile(img, "sig_tcomp_apply_q", pick("fixed", 2)["instructions"])
        profiles["sig_tcomp_apply_q order 2 hw"] = prof
        print("  profile of sig_tcomp_apply_q (order 2, hw), instructions per function:")
        for p in prof:
            print(f"    {p['function']:<24} {p['instructions']:>6} instr  {p['calls']:>3} calls")
        lines = runner.profile_lines(img, "sig_tcomp_apply_q", pick("fixed", 2)["instructions"])
        profiles["sig_tcomp_apply_q order 2 hw, by source line"] = lines
        print("  ... by source line (csrc/ as built; inlined code at its own line):")
        for p in lines[:12]:
            print(f"    {p['line']:<24} {p['instructions']:>6} instr")
    if t1 and 2 in _orders(a.orders) and not checks[2]["met"] and ("fixed16", 2, True) in _IMAGES:
        img, n = _IMAGES[("fixed16", 2, True)]
        prof = runner.profile(img, "sig_tcomp16_apply_q", n)
        profiles["sig_tcomp16_apply_q order 2 hw"] = prof
        print("  profile of sig_tcomp16_apply_q (order 2, hw), instructions per function:")
        for p in prof:
            print(f"    {p['function']:<24} {p['instructions']:>6} instr  {p['calls']:>3} calls")
    if t1 and 2 in _orders(a.orders) and not checks[4]["met"] \
            and ("fixed16_inline", 2, True) in _IMAGES:
        img, n = _IMAGES[("fixed16_inline", 2, True)]
        lines = runner.profile_lines(img, "sig_tcomp16_apply_q", n)
        profiles["sig_tcomp16_apply_q order 2 hw inline, by source line"] = lines
        print("  profile of sig_tcomp16_apply_q (order 2, inline hooks), instructions by source "
              "line (hooks inlined at their own lines):")
        for p in lines[:12]:
            print(f"    {p['line']:<28} {p['instructions']:>6} instr")
    if c51 and not checks[-1]["met"] and ("chain", "fixed", "mcs51") in _IMAGES:
        img, n = _IMAGES[("chain", "fixed", "mcs51")]
        prof = runner.profile(img, "sig_chain_step_q", n)
        profiles["sig_chain_step_q 8051"] = prof
        print("  where a fixed chain step's 12T clocks go on the 8051 (s51 history, exclusive "
              "per function; _mullong = sdcc's 32x32 multiply, _gptrget/_gptrput = generic-"
              "pointer access):")
        for p in prof:
            print(f"    {p['function']:<24} {p['clocks_12T']:>7} clk12T {p['clocks_1t_stc_y5']:>6} "
                  f"clk1T {p['instructions']:>6} instr {p['calls']:>3} calls")
    return checks, profiles, experiment


if __name__ == "__main__":
    main()
