"""What a drift model costs on the MSP430F5510: cycles per evaluation, code
bytes of its call tree and energy, with every output read back from the
simulator and compared with the host C bit for bit.

  text_bytes  .text bytes of the evaluation code from csrc (the call tree of
              the entry point, runtime helpers such as __mspabi_mpyl_f5hw
              counted separately in helper_bytes);
  cycles      MSP430F5510 MCLK cycles per call, mspdebug 0.22 `sim` (classic
              MSP430 timing), hardware-multiplier helpers on the simulated
              16x16 MPY: mean over N_TEMPS temperatures spread over the range,
              loop overhead removed (the same loop around a no-op function);
  energy_uj   cycles / 8 MHz x 1.56 mA x 3.3 V.

The harnesses are bench/model_pareto/harness_*.c; each case writes its data
as a header (pareto_case.h) into its own build directory.
"""
from __future__ import annotations

import re
import subprocess

import numpy as np

from lab.mcu import pwl_vectors, runner

HARNESS_DIR = runner.ROOT / "bench" / "model_pareto"
N_TEMPS = 16
MCLK_HZ = 8e6
SUPPLY_A = 1.56e-3
SUPPLY_V = 3.3


class ModelMismatchError(runner.McuError):
    """The MSP430 computed other bits than the host C."""


def energy_uj(cycles):
    """Energy of `cycles` at MCLK_HZ, SUPPLY_A and SUPPLY_V, in µJ.

    Examples
    --------
    >>> round(energy_uj(8000), 3)          # 1 ms at 8 MHz, 1.56 mA, 3.3 V
    5.148
    """
    return cycles / MCLK_HZ * SUPPLY_A * SUPPLY_V * 1e6


def c_array(values):
    """A C initialiser of integers: ``{1, 2, 3}``.

    Examples
    --------
    >>> c_array([1, -2, 3])
    '{1, -2, 3}'
    """
    return "{" + ", ".join(str(int(v)) for v in values) + "}"


def case_dir(tag):
    """The build directory of one case (created)."""
    d = runner.BUILD_DIR / "model_pareto" / tag
    d.mkdir(parents=True, exist_ok=True)
    return d


def mcu_temps(t_lo, t_hi):
    """N_TEMPS int16 temperatures spread over [t_lo, t_hi]."""
    return np.round(np.linspace(t_lo, t_hi, N_TEMPS)).astype(np.int16)


_DIS_CACHE = {}


def call_tree_bytes(img, entry):
    """(csrc bytes, runtime-helper bytes, function names) of the functions
    reachable from `entry` by direct calls (MSP430 disassembly)."""
    key = str(img.path)
    if key not in _DIS_CACHE:
        dis = subprocess.run([runner.tool("llvm-objdump-14", "llvm-objdump"), "-d", str(img.path)],
                             capture_output=True, text=True, check=True).stdout
        calls, cur = {}, None
        for line in dis.splitlines():
            m = re.match(r"^([0-9a-f]+) <(.+)>:$", line)
            if m:
                cur = m.group(2)
                calls[cur] = set()
                continue
            m = re.search(r"\tcall\t#(\d+)", line)
            if m and cur:
                calls[cur].add(int(m.group(1)))
        _DIS_CACHE[key] = calls
    calls = _DIS_CACHE[key]
    by_addr = {a: n for n, a in img.symbols.items() if n in img.sizes and img.sizes[n] > 0}
    seen, todo = set(), [entry]
    while todo:
        f = todo.pop()
        if f in seen:
            continue
        seen.add(f)
        todo.extend(by_addr[a] for a in calls.get(f, ()) if a in by_addr)
    helpers = {f for f in seen if f.startswith("__") or f in ("memcpy", "memset", "memmove")}
    return (sum(img.sizes[f] for f in seen - helpers), sum(img.sizes[f] for f in helpers),
            sorted(seen))


def measure_case(tag, harness, source_files, header_text, entry, target="msp430"):
    """Build a harness with its case header for the MSP430F5510 (target
    "msp430") or the ATmega328P ("avr"), run it, read back: per-axis
    cycles, outputs, statuses, code bytes."""
    d = case_dir(tag)
    (d / "pareto_case.h").write_text(header_text)
    if target == "avr":
        img = runner.build_avr(source_files, HARNESS_DIR / harness, include_dirs=[d],
                               name=f"pareto-{tag}")
    else:
        img = runner.build_msp430(source_files, HARNESS_DIR / harness, include_dirs=[d], hwmult=True,
                                  name=f"pareto-{tag}")
    regions = ["bench_start:bench_axis1", "bench_axis1:bench_axis2", "bench_axis2:bench_stop",
               "bench_null_start:bench_null_stop"]
    res = runner.measure(img, funcs=[] if target == "avr" else [entry], regions=regions,
                         reads={"out": 3 * N_TEMPS * 4, "status": 3 * N_TEMPS * 2}, stack=False)
    null = res["regions"][regions[3]]["cycles"]
    cycles = [(res["regions"][r]["cycles"] - null) / N_TEMPS for r in regions[:3]]
    out = np.frombuffer(res["reads"]["out"], "<i4").reshape(3, N_TEMPS)
    status = np.frombuffer(res["reads"]["status"], "<i2").reshape(3, N_TEMPS)
    if target == "avr":
        tree = runner.code_closure(img, entry)
        text = sum(v for k, v in tree.items() if not runner.is_helper(k))
        helper = sum(v for k, v in tree.items() if runner.is_helper(k))
        return {"cycles": cycles, "single_call_cycles": None, "out": out, "status": status,
                "text_bytes": text, "helper_bytes": helper, "call_tree": sorted(tree)}
    text, helper, tree = call_tree_bytes(img, entry)
    return {"cycles": cycles, "single_call_cycles": res["funcs"][entry]["cycles"],
            "out": out, "status": status, "text_bytes": text, "helper_bytes": helper,
            "call_tree": tree}


def poly_eval_host(pm, axis, temp_int):
    """(raw Q-format deltas, deltas in the data's unit) of one axis of a
    poly_models() model at int16 centi-degree temperatures, by the host C."""
    d, _ = pm["model"].delta(axis, np.asarray(temp_int, dtype=np.int16))
    return d, d / float(1 << pm["axes"][axis].q)



def mcu_poly(tag, pm, order, target="msp430"):
    """Measure a lab.studies.pareto.poly_models() model (three axes) with
    sig_tcomp_delta_q; raises ModelMismatchError unless every output equals
    the host C's."""
    sc = pm["scaling"]
    temps = mcu_temps(sc.t_lo, sc.t_hi)
    coef = [c for a in pm["axes"] for c in a.coef]
    h = (f"#define N_AXES 3\n#define ORDER {order}\n#define N_TEMPS {N_TEMPS}\n"
         f"#define POLY_COEF {{{', '.join(f'INT32_C({c})' for c in coef)}}}\n"
         f"#define POLY_Q {c_array([a.q for a in pm['axes']])}\n"
         f"#define POLY_T_LO {sc.t_lo}\n#define POLY_T_HI {sc.t_hi}\n"
         f"#define POLY_T_CENTER {sc.t_center}\n#define POLY_U_MUL {sc.u_mul}\n"
         f"#define POLY_U_SHIFT {sc.u_shift}\n#define TEMPS {c_array(temps)}\n")
    m = measure_case(tag, "harness_poly.c",
                     [runner.c_source("sig_tcomp"), runner.c_source("sig_poly"),
                      runner.c_source("sig_image"), runner.c_source("sig_crc16")],
                     h, "sig_tcomp_delta_q", target)
    for a in range(3):
        host, _ = poly_eval_host(pm, a, temps)
        if not np.array_equal(host, m["out"][a]):
            raise ModelMismatchError(f"{tag}: {target} result differs from the host C on axis {a}: "
                                     f"{m['out'][a]} vs {host}")
    return m


def mcu_pwl(tag, tabs, n_knots, target="msp430"):
    """Measure three pysig.tcomp._table_fit tables of `n_knots` with
    sig_pwl_eval_q16; raises ModelMismatchError unless every output and
    status equals the host C's."""
    temps = mcu_temps(min(t.t_lo for t in tabs), max(t.t_hi for t in tabs))
    h = (f"#define N_AXES 3\n#define N_KNOTS {n_knots}\n#define N_TEMPS {N_TEMPS}\n"
         f"#define PWL_TABLES {{{', '.join(c_array(t.table) for t in tabs)}}}\n"
         f"#define PWL_RANGES {{{', '.join(c_array([t.t_lo, t.t_hi]) for t in tabs)}}}\n"
         f"#define PWL_RECIPS {{{', '.join(f'UINT32_C({t.recip})' for t in tabs)}}}\n"
         f"#define PWL_VFS {c_array([t.value_frac for t in tabs])}\n"
         f"#define TEMPS {c_array(temps)}\n")
    m = measure_case(tag, "harness_pwl.c", [runner.c_source("sig_pwl")], h, "sig_pwl_eval_q16",
                     target)
    for a, t in enumerate(tabs):
        host, hstat = t.eval_c(temps)
        if not (np.array_equal(host, m["out"][a]) and np.array_equal(hstat, m["status"][a])):
            raise ModelMismatchError(f"{tag}: {target} result differs from the host C on axis {a}: "
                                     f"{m['out'][a]} vs {host}")
    return m


def mcu_pwl2(tag, tabs):
    """sig_pwl_eval_axes_msp430 (MSP430 assembly, csrc/port/msp430) on three
    power-of-two tables of lab.studies.pareto.pwl2_models(): cycles of one
    call / 3 (the assembly's cost hardly depends on the temperature: one
    index product, no search); raises ModelMismatchError unless every output
    of N_TEMPS temperatures equals the host C's."""
    temps = mcu_temps(tabs[0].t_lo, tabs[0].t_hi)
    case = pwl_vectors.PwlCase(np.array([t.table for t in tabs]), tuple(t.value_frac for t in tabs),
                               tabs[0].t_lo, tabs[0].t_hi, tabs[0].recip,
                               np.asarray(temps, dtype=np.int16), int(temps[len(temps) // 2]))
    d = case_dir(tag)
    pwl_vectors.write_pwl_header(case, d / "pwl_vectors.h")
    harness = runner.ROOT / "bench" / "mcu" / "harness" / "pwl_harness.c"
    asm = runner.CSRC / "port" / "msp430" / "sig_pwl_msp430.S"
    entry = "sig_pwl_eval_axes_msp430"
    img = runner.build_msp430([runner.c_source("sig_pwl"), asm], harness,
                              {"MPY_BASE": runner.MSP430_MPY_BASE_SIM,
                               "PW_PORT_HEADER": '"sig_pwl_msp430.h"', "PW_EVAL_AXES": entry},
                              include_dirs=[d, runner.PORT_MSP430], hwmult=True,
                              name=f"pareto-{tag}")
    n = len(temps)
    res = runner.measure(img, funcs=[entry], reads={"vec_out3": 12 * n, "vec_status3": 2 * n},
                         stack=False)
    out = np.frombuffer(res["reads"]["vec_out3"], "<i4").reshape(n, 3).T
    host, hst = pwl_vectors.host_eval(case)
    if not (np.array_equal(out, host)
            and np.array_equal(np.frombuffer(res["reads"]["vec_status3"], "<i2"), hst[0])):
        raise ModelMismatchError(f"{tag}: MSP430 assembly result differs from the host C")
    one = res["funcs"][entry]["cycles"]
    text, helper, tree = call_tree_bytes(img, entry)
    return {"cycles": [one / 3] * 3, "single_call_cycles": one, "text_bytes": text,
            "helper_bytes": helper, "call_tree": tree}
