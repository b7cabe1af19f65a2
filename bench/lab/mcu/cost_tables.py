"""The MCU cost rows: the csrc/ temperature compensation and weighing chain
built for the MSP430F5510 and the 8051, run in the instruction-set
simulators, their outputs read back and checked against the host C
(Cython) before a row is returned: a wrong build cannot produce a number.

Each row function returns a JSON-ready dict: code bytes (the function's call
tree, helpers apart), RAM (state + stack high-water), cycles per call and in
a batch, time and energy (MSP430F5510 at MCLK_HZ, I_ACTIVE_A), and next to
it an operation-count model read off the algorithm (tcomp_ops, chain_ops).
Beside the portable C, the port-layer paths of csrc/port/: the "fixed16_asm"
rows (sig_tcomp16_apply_msp430), the uniform-table lookup of Table 1b
(pwl_row: sig_pwl_eval_q16 against sig_pwl_eval_msp430 and the per-image
sig_pwl_eval_axes_msp430) and the 8051 chain of csrc/port/mcs51
(chain_row_mcs51_port: steady-state and motion-restart steps).
bench/mcu_cost.py prints them as its tables.  Images built here are kept
in IMAGES for profiling.
"""
from __future__ import annotations

import re

import numpy as np

from lab.mcu import pwl_vectors, runner, tcomp16_vectors, vectors

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
TARGETS = {"tcomp_q2_hw_cycles": 300, "tcomp_float_over_fixed": 10.0, "chain_q_8051_clocks": 3000,
           "table_lookup_cycles_per_axis": 100}
TCOMP16_ASM = CSRC / "port" / "msp430" / "sig_tcomp16_msp430.S"
PWL_ASM = CSRC / "port" / "msp430" / "sig_pwl_msp430.S"
CHAIN_MCS51 = CSRC / "port" / "mcs51" / "sig_chain_mcs51.c"
ASM_DEFINES = {"MPY_BASE": runner.MSP430_MPY_BASE_SIM}


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


def check_tcomp(case, form, reads):
    """SystemExit unless the firmware's outputs and statuses of a
    compensation batch equal the host C (float: within 2e-6 relative)."""
    n, a = case.in_q.shape
    fw_st = _i16(reads["vec_status"])
    from pysig.tcomp._tcomp import TcompF, TcompQ
    if form == "float":
        fw = np.frombuffer(reads["vec_out"], "<f4").reshape(n, a).astype(float)
        host = TcompF(case.coef_f.astype(float), float(np.float32(case.t_lo / 100)),
                      float(np.float32(case.t_hi / 100)), float(case.center_f),
                      float(case.inv_scale_f))
        h_out, h_st = host.apply(case.t_f.astype(float), case.in_f.astype(float))
        ok = np.array_equal(fw_st, h_st) and np.all(np.abs(fw - h_out) <= 2e-6 * np.maximum(1, np.abs(h_out)))
    else:
        fw = _i16(reads["vec_out"]).reshape(n, a)
        host = TcompQ.from_fields(case.coef_q, case.q, case.t_lo, case.t_hi, case.t_center,
                                  case.t0, case.u_mul, case.u_shift)
        h_out, h_st = host.apply(case.t_q, case.in_q)
        ok = np.array_equal(fw, h_out) and np.array_equal(fw_st, h_st)
    if not ok:
        raise SystemExit(f"tcomp order {case.order} {form}: firmware results differ from the host C")


def check_tcomp16(case, form, reads):
    """SystemExit unless a compact-form batch equals the host C bit for bit."""
    n, a = case.base.in_q.shape
    from pysig.tcomp._tcomp16 import Tcomp16Q
    h_out, h_st = Tcomp16Q.from_compact(case.compact).apply(case.base.t_q, case.base.in_q)
    if not (np.array_equal(_i16(reads["vec_out"]).reshape(n, a), h_out)
            and np.array_equal(_i16(reads["vec_status"]), h_st)):
        raise SystemExit(f"tcomp16 order {case.base.order} {form}: firmware results differ from the host C")


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
    check_tcomp(case, form, r["reads"])
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


def tcomp16_row(order: int, hwmult: bool, vdd: float, inline: bool = False,
                asm: bool = False) -> dict:
    """The compact form (csrc/tcomp/sig_tcomp16.c) on the same temperatures and
    readings as tcomp_row, the same polynomial quantised by
    pysig.tcomp._quant.quantize_compact (lab.mcu.tcomp16_vectors), checked
    against the host C before the row is returned.  inline: the same C with
    the sig_port.h hooks of csrc/port/msp430/sig_port_msp430.h (multiplier
    MAC/MACS as volatile accesses, hw only).  asm: the port layer's assembly
    form csrc/port/msp430/sig_tcomp16_msp430.S (hw only)."""
    case = tcomp16_vectors.tcomp16_case(order)
    gen = runner.BUILD_DIR / "gen" / f"tcomp16-o{order}"
    tcomp16_vectors.write_tcomp16_header(case, gen / "tcomp16_vectors.h")
    func = "sig_tcomp16_apply_msp430" if asm else "sig_tcomp16_apply_q"
    form = "fixed16_asm" if asm else "fixed16_inline" if inline else "fixed16"
    defines = (dict(ASM_DEFINES, TC16_PORT_HEADER='"sig_tcomp16_msp430.h"', TC16_APPLY=func)
               if asm else INLINE_DEFINES if inline else [])
    img = runner.build_msp430(TCOMP16_SRC + ([TCOMP16_ASM] if asm else []),
                              HARNESS / "tcomp16_harness.c", defines, hwmult=hwmult,
                              include_dirs=[gen, PORT_MSP430] if (inline or asm) else [gen],
                              name=f"tcomp16-o{order}" + ("-asm" if asm else "-inline" if inline else ""))
    n, a = case.base.in_q.shape
    r = runner.measure(img, funcs=[func], regions=["bench_start:bench_stop"],
                       reads={"vec_out": 2 * n * a, "vec_status": 2 * n})
    check_tcomp16(case, form, r["reads"])
    IMAGES[(form, order, hwmult)] = (img, r["funcs"][func]["instructions"])
    clos = runner.code_closure(img, func)
    if (inline or asm) and any(runner.is_helper(k) for k in clos):
        raise SystemExit(f"tcomp16 order {order} {form}: the port hooks did not take effect ({clos})")
    one = r["funcs"][func]
    model_bytes = runner.symbol_size(img, "model")
    t_us = one["cycles"] / MCLK_HZ * 1e6
    return {"target": "msp430f5510", "form": form, "order": order,
            "multiplier": ("hw, assembly MAC/MACS (csrc/port/msp430/sig_tcomp16_msp430.S, "
                           "16x16 MPY at 0x0130 in the simulator)" if asm else
                           "hw inline MAC/MACS (sig_port_msp430.h, 16x16 MPY at 0x0130 in the "
                           "simulator)" if inline else
                           "hw (16x16 MPY at 0x0130 in the simulator)" if hwmult else "none"),
            "text_bytes": sum(v for k, v in clos.items() if not runner.is_helper(k)),
            "helper_bytes": sum(v for k, v in clos.items() if runner.is_helper(k)),
            "ram_bytes": model_bytes + one["stack_bytes"], "model_bytes": model_bytes,
            "coef_bytes": a * (2 + 4 * order), "stack_bytes": one["stack_bytes"],
            "cycles": one["cycles"], "instructions": one["instructions"],
            "cycles_avg_batch": round(r["regions"]["bench_start:bench_stop"]["cycles"] / n, 1),
            "time_us": round(t_us, 2), "energy_uj": round(I_ACTIVE_A * vdd * t_us, 4),
            "ops": tcomp_ops("fixed16_inline" if asm else form, order), "checked_vectors": n,
            "drift_amplitude_lsb": round(case.amplitude, 1),
            "compact_error_lsb": round(max(case.compact.error_lsb), 4)}


def _chain_tag(case):
    """build names per preset ("" for the table's reference preset)"""
    return "" if case.preset == vectors.CHAIN_PRESET else f"-{case.preset}"


def chain_rows_msp430(form: str, hwmult: bool, case, vdd: float) -> dict:
    gen = runner.BUILD_DIR / "gen" / f"chain{_chain_tag(case)}"
    vectors.write_chain_header(case, gen / "chain_vectors.h")
    fl = form == "float"
    func = "sig_chain_step_f" if fl else "sig_chain_step_q"
    img = runner.build_msp430(CHAIN_SRC, HARNESS / "chain_harness.c", ["BENCH_FLOAT"] if fl else [],
                              hwmult=hwmult, include_dirs=[gen], name=f"chain{_chain_tag(case)}-{form}")
    n = len(case.x)
    r = runner.measure(img, funcs=[func], regions=["bench_start:bench_stop"], reads=chain_reads(n))
    check_chain(case, form, r["reads"])
    IMAGES[("chain" + _chain_tag(case), form, hwmult)] = (img, r["funcs"][func]["instructions"])
    clos = runner.code_closure(img, func)
    one = r["funcs"][func]
    state = runner.symbol_size(img, "chain")
    t_us = one["cycles"] / MCLK_HZ * 1e6
    return {"target": "msp430f5510", "form": form, "preset": case.preset,
            "multiplier": "hw (16x16 MPY at 0x0130 in the simulator)" if hwmult else "none",
            "cycles": one["cycles"], "instructions": one["instructions"],
            "cycles_avg_batch": round(r["regions"]["bench_start:bench_stop"]["cycles"] / n, 1),
            "time_us": round(t_us, 1), "energy_uj": round(I_ACTIVE_A * vdd * t_us, 3),
            "text_bytes": sum(v for k, v in clos.items() if not runner.is_helper(k)),
            "helper_bytes": sum(v for k, v in clos.items() if runner.is_helper(k)),
            "ram_bytes": state + one["stack_bytes"], "state_bytes": state,
            "stack_bytes": one["stack_bytes"], "ops": chain_ops(form), "checked_samples": n}


def _same_outputs(form, fw_bytes, host_out):
    """firmware outputs (raw bytes: fixed Q7 int32, float f32) == host C's"""
    if form == "fixed":
        return np.array_equal(np.frombuffer(fw_bytes, "<i4"), np.round(host_out * 128).astype(np.int64))
    fw = np.frombuffer(fw_bytes, "<f4").astype(float)
    return bool(np.all(np.abs(fw - host_out) <= 1e-5 * np.maximum(1, np.abs(host_out))))


def check_chain(case, form, reads, timed=(("one", 0),)):
    """Every batch output and status, and every timed single step's output,
    status (and stable flag where the harness keeps it) against the host C
    chain run on the same input.  timed: (name, k): the harness's name_out /
    name_status after the batch, one_x and then k more samples of the
    restart plan."""
    from pysig.weigh import Chain
    n = len(case.x)
    seq = [case.x.astype(float), [float(case.one_x)]]
    if any(k for _, k in timed):
        rx, pre = vectors.chain_restart_plan(case)
        seq.append(np.full(pre + 1, float(rx)))
    out, stable, st = Chain(case.preset, fixed=form == "fixed").process(np.concatenate(seq), flags=True)
    ok = _same_outputs(form, reads["vec_out"], out[:n]) and np.array_equal(_i16(reads["vec_status"]), st[:n])
    if not ok:
        raise SystemExit(f"chain {form}: firmware results differ from the host C ({n} samples)")
    for name, k in timed:
        i = n + k
        step_ok = (_same_outputs(form, reads[f"{name}_out"], out[i:i + 1])
                   and int(_i16(reads[f"{name}_status"])[0]) == int(st[i])
                   and (f"{name}_stable" not in reads or bool(reads[f"{name}_stable"][0]) == bool(stable[i])))
        if not step_ok:
            raise SystemExit(f"chain {form}: the timed step '{name}' (sample {i}) differs from the host C")


def chain_reads(n):
    """what a chain harness leaves to check: the batch and the timed step"""
    return {"vec_out": 4 * n, "vec_status": 2 * n, "one_out": 4, "one_status": 2, "one_stable": 1}


MCS51_CHAIN_FLAGS = ["--stack-auto"]
WHAT_3000_TAKES = (
    "3000 12T clocks are 250 machine cycles, ~170 instructions.  The port's steady step "
    "is sdcc C: every 32-bit operation on the indirect-RAM state (sample - base, the "
    "window sum, m*128 + base, the innovation, x += inc, the zero-tracking offset and "
    "x - offset) costs 20-40 instructions, and its three 16x16 products (trimmed-mean "
    "reciprocal, Kalman gain low and high word) 52 machine cycles each in assembly "
    "(4 MUL AB + carries).  An estimate for the same algorithm in hand-written 8051 "
    "assembly with the hot state in direct RAM: ~460 machine cycles (~5500 clocks), of "
    "which the products ~160.  Under 3000 needs fewer products as well: the Kalman "
    "update as one 16x8 product (a steady gain rounded to 8 bits is not bit-exact with "
    "the portable chain, so the reference would have to change), the trimmed mean kept "
    "as quotient and remainder updated by the window's change (no division), and the "
    "output side (zero tracking, x - offset) in 16 bits around a base like the window.")


def chain_row_mcs51(form: str, case) -> dict:
    """The 8051 build: sdcc --model-large --stack-auto (state and vectors in
    xdata; locals and spill temporaries on the stack in internal RAM, which
    plain --model-large cannot hold: bench/mcu/README.md), sdcc's assembly
    __mullong (runner.mcs51_runtime).  12T clocks from s51; 1T estimate =
    opcode histogram x STC-Y5 table.  Code: the functions reachable from the
    step (.rst call graph); RAM: chain state (xdata) + internal-RAM stack
    high-water of the call."""
    n = len(case.x)
    tag = _chain_tag(case) + ("" if n == len(vectors.chain_case().x) else f"-n{n}")
    gen = runner.BUILD_DIR / "gen" / f"chain{tag}"
    vectors.write_chain_header(case, gen / "chain_vectors.h")
    fl = form == "float"
    func = "sig_chain_step_f" if fl else "sig_chain_step_q"
    row = {"target": "8051 (s51 -t C52, sdcc --model-large --stack-auto)", "form": form,
           "preset": case.preset, "samples_before_timed_step": n, "ops": chain_ops(form)}
    try:
        # the fixed form as a fixed-only firmware builds it (no float code linked: the
        # whole sig_chain.c module and the 700-sample vectors do not fit 64 KB together)
        img = runner.build_mcs51(CHAIN_SRC, HARNESS / "chain_harness.c",
                                 ["BENCH_FLOAT"] if fl else ["SIG_NO_FLOAT"], include_dirs=[gen],
                                 name=f"chain{tag}-{form}", extra_flags=MCS51_CHAIN_FLAGS)
    except runner.McuError as e:
        row.update(status="does not build", error=[ln for ln in str(e).splitlines()
                                                    if "ASlink-Error" in ln or "warning" in ln])
        return row
    r = runner.measure(img, funcs=[func], regions=["bench_start:bench_stop"], reads=chain_reads(n))
    if r["total"].get("stack_overflow"):
        raise SystemExit(f"chain {form} on the 8051: the stack passed 0xFF (s51)")
    check_chain(case, form, r["reads"])
    IMAGES[("chain" + tag, form, "mcs51")] = (img, r["funcs"][func]["instructions"])
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


def _mcs51_ds_size(img, module: str, name: str) -> int:
    """bytes sdcc reserved for a variable (.ds in the module's .asm)."""
    m = re.search(r"^_%s::\s*\n\s*\.ds (\d+)" % re.escape(name),
                  (img.path.parent / f"{module}.asm").read_text(), re.M)
    if not m:
        raise SystemExit(f"{name}: no .ds in {module}.asm")
    return int(m.group(1))


def _mcs51_xdata_size(img, name: str) -> int:
    """bytes of an xdata variable: distance to the next xdata symbol (.map)."""
    xs = sorted(a for sp, a in img.symbols.values() if sp == "xram")
    a = img.symbols["_" + name][1]
    return next(x for x in xs if x > a) - a


# ------------------------------------------------------ table lookup (1b) ---
PWL_FORMS = (
    # (form, entry, port header define, value_frac of the three tables)
    ("portable", "sig_pwl_eval_q16", None, (9, 4, 1)),
    ("asm", "sig_pwl_eval_msp430", "PW_EVAL", (9, 4, 1)),
    ("asm_axes", "sig_pwl_eval_axes_msp430", "PW_EVAL_AXES", (9, 4, 1)),
    ("asm_axes", "sig_pwl_eval_axes_msp430", "PW_EVAL_AXES", (4, 4, 4)),
)


def pwl_row(form, entry, macro, vfs, vdd, spacing_shift=8):
    """One uniform-table lookup build: three tables over the compensation's
    range with knots 2^spacing_shift units (2.56 degC) apart, one per output
    scaling (value_frac > 4, 4, < 4) or all value_frac 4 (no output shift).
    Every output and status of the batch is checked against the host C
    sig_pwl_eval_q16.  cycles_per_axis: one call (entry to return) / axes
    it evaluates; batch: region cycles / (temperatures x axes), loop
    included."""
    case = pwl_vectors.pwl_case(spacing_shift=spacing_shift, value_frac=vfs)
    tag = f"pwl-{form}-{''.join(map(str, vfs))}"
    gen = runner.BUILD_DIR / "gen" / tag
    pwl_vectors.write_pwl_header(case, gen / "pwl_vectors.h")
    src = [runner.c_source("sig_pwl")] + ([PWL_ASM] if macro else [])
    defines = dict(ASM_DEFINES, PW_PORT_HEADER='"sig_pwl_msp430.h"', **{macro: entry}) if macro else {}
    img = runner.build_msp430(src, HARNESS / "pwl_harness.c", defines, hwmult=True,
                              include_dirs=[gen, PORT_MSP430], name=tag)
    n = len(case.temps)
    axes_call = macro == "PW_EVAL_AXES"
    reads = ({"vec_out3": 12 * n, "vec_status3": 2 * n} if axes_call
             else {"vec_out": 12 * n, "vec_status": 6 * n})
    r = runner.measure(img, funcs=[entry], regions=["bench_start:bench_stop"], reads=reads)
    h_out, h_st = pwl_vectors.host_eval(case)
    if axes_call:
        fw = np.frombuffer(r["reads"]["vec_out3"], "<i4").reshape(n, 3).T
        ok = np.array_equal(fw, h_out) and np.array_equal(_i16(r["reads"]["vec_status3"]), h_st[0])
    else:
        fw = np.frombuffer(r["reads"]["vec_out"], "<i4").reshape(3, n)
        ok = np.array_equal(fw, h_out) and np.array_equal(_i16(r["reads"]["vec_status"]).reshape(3, n), h_st)
    if not ok:
        raise SystemExit(f"table lookup {form} {vfs}: firmware results differ from the host C")
    one = r["funcs"][entry]
    per_call_axes = 3 if axes_call else 1
    clos = runner.code_closure(img, entry)
    cyc = one["cycles"] / per_call_axes
    return {"target": "msp430f5510", "form": form, "entry": entry, "value_frac": list(vfs),
            "n_knots": case.n_knots, "knot_spacing": 1 << spacing_shift,
            "multiplier": "hw (16x16 MPY at 0x0130 in the simulator)",
            "cycles_call": one["cycles"], "axes_per_call": per_call_axes,
            "cycles_per_axis": round(cyc, 1), "instructions": one["instructions"],
            "cycles_per_axis_avg_batch": round(r["regions"]["bench_start:bench_stop"]["cycles"] / (3 * n), 1),
            "time_us_per_axis": round(cyc / MCLK_HZ * 1e6, 2),
            "energy_uj_per_axis": round(I_ACTIVE_A * vdd * cyc / MCLK_HZ * 1e6, 4),
            "text_bytes": sum(v for k, v in clos.items() if not runner.is_helper(k)),
            "stack_bytes": one["stack_bytes"], "checked_values": 3 * n}


def table1b(vdd):
    """Table 1b: the rows of every PWL_FORMS build (pwl_row)."""
    return [pwl_row(f, e, m, v, vdd) for f, e, m, v in PWL_FORMS]


# ------------------------------------------------------ 8051 chain port ---
MCS51_PORT_FLAGS = []      # plain --model-large: the port's state is placed by hand
# the default chain on the port: its non-steady steps are the portable chain
# (csrc/weigh, also for the shared stage header); a fixed-only build
MCS51_PORT_AUTO_DEFINES = {"SIG_CHAIN_MCS51_AUTO": "1", "SIG_NO_FLOAT": "1"}
MCS51_PORT_AUTO_FLAGS = ["--stack-auto", "--xstack"]   # the portable chain's frames, in the pdata page (the port's state holds the internal RAM)


def chain_mcs51_port_build(case, gains, gen, name):
    """The port's harness build for a case: with the default chain's code
    (MCS51_PORT_AUTO_DEFINES) when the case's preset measures its noise."""
    auto = bool(case.fixed["noise_auto"])
    vectors.write_chain_mcs51_header(case, gains, gen / "chain_vectors.h")
    return runner.build_mcs51([CHAIN_MCS51] + (CHAIN_SRC if auto else []), HARNESS / "chain_mcs51_harness.c",
                              MCS51_PORT_AUTO_DEFINES if auto else [],
                              include_dirs=[gen, CHAIN_MCS51.parent] + ([CSRC / "weigh"] if auto else []),
                              name=name, extra_flags=MCS51_PORT_AUTO_FLAGS if auto else MCS51_PORT_FLAGS)
CHAIN_PORT_N = 700         # long enough for the Kalman gain to settle after the last restart


def chain_row_mcs51_port(case=None) -> tuple:
    """The 8051 chain of csrc/port/mcs51 (sdcc --model-large, no
    --stack-auto: hot state in indirect RAM, window and configuration in
    xdata, the gain table in code memory; the default chain's build adds
    --stack-auto --xstack for the portable step it runs off the steady
    state, and its text_bytes include that portable chain).  Bit for bit against the host C
    of the portable chain on CHAIN_PORT_N samples (two load changes, impulses,
    a lock-out re-seed), then: the steady-state step (sample N+1, gain
    settled) and the motion-restart step, each counted entry to return."""
    from lab.mcu.host_port import gain_table
    case = case or vectors.chain_case(n=CHAIN_PORT_N)
    n = len(case.x)
    gains = gain_table(case.fixed["q_q30"], case.fixed["p0_q16"])
    tag = ("" if case.preset == vectors.CHAIN_PRESET else f"-{case.preset}") + ("" if n == CHAIN_PORT_N else f"-n{n}")
    gen = runner.BUILD_DIR / "gen" / f"chain-mcs51{tag}"
    img = chain_mcs51_port_build(case, gains, gen, f"chain-mcs51{tag}")
    steady, restart = "sig_chain_mcs51_step", "sig_chain_mcs51_step@restart_step"
    _, pre = vectors.chain_restart_plan(case)
    r = runner.measure(img, funcs=[steady, restart], regions=["bench_start:bench_stop"],
                       reads=dict(chain_reads(n), vec_stable=n, restart_out=4, restart_status=2))
    if r["total"].get("stack_overflow"):
        raise SystemExit("8051 chain port: the stack passed 0xFF (s51)")
    check_chain(case, "fixed", r["reads"], timed=(("one", 0), ("restart", pre + 1)))
    if not (_i16(r["reads"]["restart_status"])[0] & 32):
        raise SystemExit("8051 chain port: the restart step did not restart (no SIG_CHAIN_MOTION)")
    IMAGES[("chain", "fixed", "mcs51-port" + tag)] = (img, r["funcs"][steady]["instructions"])
    one, rs = r["funcs"][steady], r["funcs"][restart]
    clos = runner.code_closure(img, "sig_chain_mcs51_step")
    auto = bool(case.fixed["noise_auto"])
    state = {v: _mcs51_ds_size(img, "sig_chain_mcs51", v) for v in
             ("sig_chain_mcs51", "sig_chain_mcs51_cfg", "sig_chain_mcs51_window")
             + (("sig_chain_mcs51_auto",) if auto else ())}
    flags = " ".join(["--model-large", *(MCS51_PORT_AUTO_FLAGS if auto else MCS51_PORT_FLAGS)])
    row = {"target": f"8051 (s51 -t C52, sdcc {flags}, csrc/port/mcs51)", "form": "fixed_port",
           "preset": case.preset, "samples_before_timed_step": n,
           "status": "ok", "clocks_12T": one["cycles"], "instructions": one["instructions"],
           "clocks_12T_restart": rs["cycles"], "clocks_1T_estimate_restart": rs["clocks_1t_stc_y5"],
           "clocks_12T_avg_batch": round(r["regions"]["bench_start:bench_stop"]["cycles"] / n, 1),
           "ms_12MHz_12T": round(one["cycles"] / MCS51_HZ * 1e3, 3),
           "clocks_1T_estimate": one["clocks_1t_stc_y5"],
           "us_1T_estimate_12MHz": round(one["clocks_1t_stc_y5"] / MCS51_HZ * 1e6, 1),
           "code_bytes_fetched": one["code_bytes_fetched"],
           "text_bytes": sum(v for k, v in clos.items() if not runner.is_helper(k)),
           "helper_bytes": sum(v for k, v in clos.items() if runner.is_helper(k)),
           "gain_table_bytes": 4 * len(gains), "gain_steps": len(gains),
           "state_bytes_idata": state["sig_chain_mcs51"],
           "state_bytes_xdata": sum(v for k, v in state.items() if k != "sig_chain_mcs51"),
           "portable_fallback_bytes_xdata": state.get("sig_chain_mcs51_auto", 0),
           "stack_bytes": one["stack_bytes"],
           "max_sp_batch": hex(r["total"]["max_sp"]) if "max_sp" in r["total"] else None,
           "checked_samples": n, "ops": chain_ops("fixed")}
    return row, img


def port_speedup(t2):
    """port rows: the portable fixed step (same preset, same input, the same
    number of samples before the timed step) over the port's, for the single
    timed step and the batch average; set in place."""
    portable = {(r["preset"], r["samples_before_timed_step"]): r for r in t2
                if r["target"].startswith("8051") and r["form"] == "fixed" and r.get("status") == "ok"}
    for r in t2:
        base = portable.get((r.get("preset"), r.get("samples_before_timed_step")))
        if r["form"] == "fixed_port" and base:
            r["portable_over_port_step"] = round(base["clocks_12T"] / r["clocks_12T"], 2)
            r["portable_over_port_batch"] = round(base["clocks_12T_avg_batch"] / r["clocks_12T_avg_batch"], 2)


def estimator_cost(t2):
    """auto rows: their step (one call on the settled chain, and the batch
    average) over the same target's and form's recommended step - 1, set in
    place as auto_over_recommended and auto_over_recommended_batch."""
    def key(r):     # the port's auto build adds flags to its target: the target up to them
        return (r["target"].split(" (")[0] + ("port" if r["form"] == "fixed_port" else ""),
                r.get("multiplier"), r["form"], r.get("samples_before_timed_step"))
    ref = {key(r): r for r in t2 if r.get("preset") == vectors.CHAIN_PRESET and r.get("status", "ok") == "ok"}
    for r in t2:
        base = ref.get(key(r))
        if r.get("preset") == "auto" and base and r.get("status", "ok") == "ok":
            c = "clocks_12T" if "clocks_12T" in r else "cycles"
            r["auto_over_recommended"] = round(r[c] / base[c] - 1.0, 3)
            r["auto_over_recommended_batch"] = round(r[c + "_avg_batch"] / base[c + "_avg_batch"] - 1.0, 3)


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
