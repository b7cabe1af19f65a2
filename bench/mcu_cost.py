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

Port-layer paths beside the portable C (csrc/port/): "fixed16_asm" rows
(sig_tcomp16_apply_msp430, assembly on the 16x16 multiplier), Table 1b the
uniform-table lookup (sig_pwl_eval_q16 against sig_pwl_eval_msp430 and the
per-image sig_pwl_eval_axes_msp430), and the 8051 chain of
csrc/port/mcs51 in Table 2 (steady-state and motion-restart steps; for the
fixed presets and for the default `auto` chain).  Each
target's status is printed and written; a missed one comes with its
profile.

The ATmega328P (Arduino Uno, 16 MHz; gcc-avr -Os, simavr; cycles counted
by the harness with Timer 1 at clk/1): the chain step for every preset in
Table 2, Table 3 the compensation families and the image loader, Table 4
the HX711 libraries' smoothing beside the chain (cycles and RAM per sample
from the same run, settle / steady noise / glitch figures from
bench/weighing_defaults.py on one HX711-like cell).

Every row is built from source, run in mspdebug 0.22 `sim` / ucsim s51 / simavr, and
its outputs are read back and checked against the host C (Cython) before the
row is printed: a wrong build cannot produce a number here.  The rows are
built by lab.mcu.cost_tables; this script prints them and writes the JSON.
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

from lab.mcu import runner, vectors
from lab.mcu.cost_avr import AVR_CHAIN_N, AVR_HZ, chain_rows_avr, tcomp_rows_avr
from lab.mcu.cost_peers import peer_rows
from lab.mcu.cost_tables import (CHAIN_PORT_N, HARNESS, I_ACTIVE_A, IMAGES, MCLK_HZ, TCOMP_SRC,
                                   WHAT_3000_TAKES, chain_ops, chain_row_mcs51, chain_row_mcs51_port,
                                   chain_rows_msp430, estimator_cost, port_speedup, table1b, tcomp16_row,
                                   tcomp_fast_row, tcomp_ops, tcomp_row, tcomp_row_mcs51)


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
    ap.add_argument("--no-avr", action="store_true", help="skip the ATmega328P rows")
    ap.add_argument("--table", choices=["1", "2", "all"], default="all", help="which table(s)")
    a = ap.parse_args(argv)

    t1, t2, t3 = [], [], []
    for hw in (True, False) if a.table in ("1", "all") else ():
        for form in ("fixed", "fixed16", "fixed16_inline", "fixed16_asm", "float"):
            if form in ("fixed16_inline", "fixed16_asm") and not hw:
                continue                    # the hooks and the assembly are the multiplier's
            for order in _orders(a.orders):
                t1.append(tcomp16_row(order, hw, a.vdd, inline=form == "fixed16_inline",
                                      asm=form == "fixed16_asm")
                          if form.startswith("fixed16") else tcomp_row(order, form, hw, a.vdd))
    if t1:
        print_table1(t1, a)
    t1b = print_table1b(table1b(a.vdd)) if a.table in ("1", "all") else []
    if a.table in ("2", "all"):
        t2, t3 = table2(a)
    avr_tcomp, peers, sketches = (([], None, []) if a.no_avr or a.table != "all"
                                  else (table3(a), table4(t2), arduino_examples()))
    checks, profiles, experiment = targets(t1, t2, a, t1b)
    if a.json:
        a.json.parent.mkdir(parents=True, exist_ok=True)
        a.json.write_text(json.dumps({
            "meta": {"mclk_hz": MCLK_HZ, "i_active_a": I_ACTIVE_A, "vdd_v": a.vdd,
                     "msp430_sim": "mspdebug 0.22 sim, classic MSP430 cycle table",
                     "msp430_helpers": "bench/mcu/msp430 (rt_hwmul.c with MPY_BASE=0x0130 for hw)",
                     "mcs51_sim": "ucsim s51 0.6.4 -t C52 (12T); 1T estimate = opcode histogram "
                                  "x STC-Y5 published clocks (bench/lab/mcu/mcs51_timing.py)",
                     "avr_sim": "simavr 1.6 -m atmega328p -f 16000000; cycles: the harness's Timer 1 "
                                "at clk/1 (bench/mcu/avr/bench_avr.h), gcc-avr 5.4 -Os, avr-libc 2.0",
                     "avr_hz": AVR_HZ},
            "table1": t1, "table1b_table_lookup": t1b, "table2": t2, "mcs51_tcomp": t3,
            "avr_tcomp": avr_tcomp, "avr_peers": peers, "arduino_examples": sketches,
            "targets": checks,
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



def print_table1b(rows):
    print("\nTable 1b - uniform-table lookup (Q16.16 out), MSP430F5510 @ 8 MHz, knots 256 units "
          "(2.56 degC) apart: the index is one 16x16 product (a shift), cycles per axis")
    cols = ["form", "entry", "value_frac", "n_knots", "cycles_call", "axes_per_call",
            "cycles_per_axis", "cycles_per_axis_avg_batch", "time_us_per_axis", "text_bytes",
            "stack_bytes"]
    print(_table([dict(r, value_frac=",".join(map(str, r["value_frac"]))) for r in rows], cols))
    print("portable = csrc/tcomp/sig_pwl.c; asm = csrc/port/msp430/sig_pwl_msp430.S one table per "
          "call; asm_axes = the three tables of one image per call (shared clamp, segment and "
          "fraction); value_frac 4 needs no output shift")
    return rows


def table2(a):
    t2 = []
    for case in (vectors.chain_case(), vectors.chain_case(preset="auto")):
        t2 += [chain_rows_msp430(f, hw, case, a.vdd) for hw in (True, False) for f in ("fixed", "float")]
        if not a.no_8051:
            t2 += [chain_row_mcs51(f, case) for f in ("fixed", "float")]
    if not a.no_8051:
        # the port against the portable C at the same step of the same input:
        # after the table's 200 samples (gain still by Newton iterations in the
        # portable step) and after CHAIN_PORT_N (gain settled)
        # the same for the default chain (its steady state on the port, every
        # other step the portable chain inside the port's build)
        for preset in (vectors.CHAIN_PRESET, "auto"):
            t2.append(chain_row_mcs51("fixed", vectors.chain_case(n=CHAIN_PORT_N, preset=preset)))
            for n in (len(vectors.chain_case().x), CHAIN_PORT_N):
                t2.append(chain_row_mcs51_port(vectors.chain_case(n=n, preset=preset))[0])
        port_speedup(t2)
    estimator_cost(t2)
    print("\nTable 2 - one weighing-chain step (limit + anti-pulse + Kalman + stability), "
          f"presets {vectors.CHAIN_PRESET!r} and 'auto' (the default: + noise estimator), "
          f"{len(vectors.chain_case().x)} samples")
    cols = ["target", "multiplier", "form", "preset", "samples_before_timed_step", "cycles", "cycles_avg_batch",
            "time_us", "text_bytes", "helper_bytes", "ram_bytes", "stack_bytes", "clocks_12T",
            "clocks_12T_restart", "clocks_12T_avg_batch", "clocks_1T_estimate", "auto_over_recommended",
            "portable_over_port_step", "portable_over_port_batch", "status"]
    print(_table(t2, cols))
    for r in t2:
        if r.get("status") == "does not build":
            print(f"  {r['target']} {r['form']}: does not build - {'; '.join(r['error'])}")
        elif r["form"] == "fixed_port":
            print(f"  {r['target']}, after {r['samples_before_timed_step']} samples: "
                  f"step {r['ms_12MHz_12T']} ms at 12 MHz (12T), "
                  f"{r.get('portable_over_port_step')}x faster than the portable C at the same step "
                  f"({r.get('portable_over_port_batch')}x over the same batch), "
                  f"~{r['us_1T_estimate_12MHz']} us 1T estimate; motion-restart step "
                  f"{r['clocks_12T_restart']} 12T clocks; state {r['state_bytes_idata']} B "
                  f"indirect RAM, gain table {r['gain_table_bytes']} B code "
                  f"({r['gain_steps']} steps); {r['checked_samples']} samples checked")
        elif r["target"].startswith("8051"):
            print(f"  {r['target']} {r['form']}: {r['ms_12MHz_12T']} ms at 12 MHz (12T), "
                  f"~{r['us_1T_estimate_12MHz']} us 1T estimate; state {r['state_bytes']} B xdata, "
                  f"stack {r['stack_bytes']} B internal RAM (batch SP max {r['max_sp_batch']} "
                  f"of 0xFF)")
    print("ops model per step:", {f: chain_ops(f) for f in ("fixed", "float")})

    if not a.no_avr:
        avr = chain_rows_avr()
        estimator_cost(avr)
        t2 += avr
        print(f"\nTable 2, ATmega328P @ 16 MHz (simavr, gcc-avr -Os; every preset, {AVR_CHAIN_N} "
              "samples checked each; cycles = Timer 1 at clk/1 around the call):")
        print(_table(avr, ["preset", "form", "cycles", "cycles_avg_batch", "time_us", "text_bytes",
                           "helper_bytes", "state_bytes", "stack_bytes", "ram_bytes",
                           "auto_over_recommended"]))
    t3 = [] if a.no_8051 else [tcomp_row_mcs51(2)]
    if t3:
        print("\n8051 compensation, order 2, 3 axes:", json.dumps(t3[0]))
    return t2, t3


def table3(a):
    rows = tcomp_rows_avr(_orders(a.orders))
    print("\nTable 3 - compensation on the ATmega328P @ 16 MHz (simavr, gcc-avr -Os), 3 axes per "
          "call (table: one axis); image load = sig_tmodel_load_image (CRC, sections, model set "
          "up) of a fitted image, then sig_tmodel_apply per vector")
    print(_table(rows, ["family", "form", "order", "cycles", "cycles_avg_batch", "cycles_apply_avg_batch",
                        "time_us", "text_bytes", "helper_bytes", "model_bytes", "stack_bytes",
                        "image_bytes"]))
    return rows


def arduino_examples():
    """The Arduino library's examples (arduino/make_library.py) built as the
    IDE builds them for the Uno: flash and static RAM of each sketch."""
    import os
    import subprocess
    import sys
    import pysig
    from lab.mcu.build_arduino import build_sketch
    out = runner.BUILD_DIR / "arduino-library"
    env = dict(os.environ, PYTHONPATH=str(Path(pysig.__file__).resolve().parents[1]))
    subprocess.run([sys.executable, str(runner.ROOT / "arduino" / "make_library.py"), str(out)],
                   check=True, capture_output=True, env=env)
    rows = []
    for ex in ("HX711Scale", "CompensatedSensor"):
        r = build_sketch(out / "SigCore", ex)
        rows.append({"example": ex, "board": "Arduino Uno (ATmega328P)", "flash_bytes": r["flash_bytes"],
                     "static_ram_bytes": r["ram_bytes"]})
    print("\nArduino library examples (gcc-avr -Os with Debian's Arduino core; flash of 32256, "
          "static RAM of 2048):")
    print(_table(rows, ["example", "flash_bytes", "static_ram_bytes"]))
    return rows


# two HX711-like cells of bench/weighing_defaults.py's grid: integer counts,
# noise step/200; clean, and with 1 % read glitches and a hand-placed swing
PEER_CELLS = {"clean": {"unit": "counts", "sigma_rel": 1 / 200, "glitch_rate": 0.0, "swing": False},
              "glitches_swing": {"unit": "counts", "sigma_rel": 1 / 200, "glitch_rate": 0.01,
                                 "swing": True}}
PEER_FIGURES = ("settle_s", "settle_s_median", "steps_settled", "steps", "steady_std_rel",
                "glitch_excursion_rel")


def table4(t2):
    """The HX711 libraries' smoothing beside the chain: cost on the AVR from
    this run, behaviour from weighing_defaults on PEER_CELLS."""
    import weighing_defaults as wd
    ours = {r["preset"]: r for r in t2 if r["target"].startswith("atmega") and r["form"] == "fixed"}
    rows = [{"config": "default" if p == "auto" else p, "library": f"pysig chain, preset {p!r} (fixed)",
             "cycles_per_output": ours[p]["cycles"], "samples_per_call": 1,
             "cycles_per_sample": ours[p]["cycles"], "ram_bytes": ours[p]["ram_bytes"],
             "state_bytes": ours[p]["state_bytes"], "stack_bytes": ours[p]["stack_bytes"],
             "text_bytes": ours[p]["text_bytes"] + ours[p]["helper_bytes"]}
            for p in ("auto", "recommended") if p in ours]
    rows += [dict(r, text_bytes=r["text_bytes"] + r["helper_bytes"]) for r in peer_rows()]
    for cell, c in PEER_CELLS.items():
        figs = {f["config"]: f for f in wd.cell_rows(c["unit"], c["sigma_rel"], c["glitch_rate"],
                                                     c["swing"], configs=[r["config"] for r in rows])}
        for r in rows:
            f = figs[r["config"]]
            r[cell] = {k: (round(f[k], 3) if isinstance(f[k], float) else f[k]) for k in PEER_FIGURES}
    print("\nTable 4 - the HX711 libraries' smoothing beside the chain, ATmega328P @ 16 MHz, same "
          "run (block reads: one call consumes `samples_per_call` samples); behaviour from "
          "bench/weighing_defaults.py (settle: s from the change to within +-sigma for good, worst "
          "step / median, None = a step never settles; steady std and glitch excursion / sigma):")
    for cell, c in PEER_CELLS.items():
        print(f"  {cell}: {c}")
    flat = [dict(r, **{f"{cell}_{k}": r[cell][k] for cell in PEER_CELLS for k in PEER_FIGURES})
            for r in rows]
    print(_table(flat, ["config", "cycles_per_output", "samples_per_call", "cycles_per_sample",
                        "ram_bytes", "text_bytes"]
                 + [f"{cell}_{k}" for cell in PEER_CELLS for k in PEER_FIGURES]))
    for r in rows:
        print(f"  {r['config']}: {r['library']}")
    return {"cells": PEER_CELLS, "rows": rows}


def targets(t1, t2, a, t1b=()):
    def pick(form, order, hw=True):
        return next(r for r in t1 if r["form"] == form and r["order"] == order
                    and (r["multiplier"] != "none") == hw)
    def under_300(label, r):
        return {"target": f"{label} order-2, 3 axes, MSP430 hw <= 300 cycles",
                "measured": r["cycles"], "met": r["cycles"] <= 300}
    checks = []
    if t1 and 2 in _orders(a.orders):
        f2 = pick("float", 2)
        for form, label in (("fixed", "fixed"), ("fixed16", "fixed16 (compact)"),
                            ("fixed16_inline", "fixed16_inline (compact, port hooks)")):
            r = pick(form, 2)
            checks.append(under_300(label, r))
            checks.append({"target": f"float/{form} cycles >= 10x (order 2, hw)",
                           "measured": round(f2["cycles"] / r["cycles"], 2),
                           "met": f2["cycles"] >= 10 * r["cycles"]})
    for r in t2:                      # the default's noise estimator on today's fixed step
        if r.get("preset") == "auto" and r["form"] == "fixed" and "auto_over_recommended" in r:
            where = r["target"].split()[0] + (f", {r['multiplier'].split()[0]} multiplier"
                                              if "multiplier" in r else "")
            checks.append({"target": f"auto (noise measured) adds <= 15 % to the fixed chain step ({where})",
                           "measured": r["auto_over_recommended"], "met": r["auto_over_recommended"] <= 0.15})
    if t1 and 2 in _orders(a.orders) and any(r["form"] == "fixed16_asm" for r in t1):
        checks.append(under_300("fixed16_asm (compact, csrc/port/msp430 assembly)", pick("fixed16_asm", 2)))
    for r in t1b:
        if r["form"] == "asm_axes":
            vf = ",".join(map(str, r["value_frac"]))
            checks.append({"target": f"uniform-table lookup <= 100 cycles per axis "
                                     f"(sig_pwl_eval_axes_msp430, value_frac {vf})",
                           "measured": r["cycles_per_axis"], "met": r["cycles_per_axis"] <= 100})
    c51 = next((r for r in t2 if r["target"].startswith("8051") and r["form"] == "fixed"), None)
    if c51:
        checks.append({"target": "fixed chain step on the 8051 <= 3000 12T clocks (portable C)",
                       "measured": c51.get("clocks_12T", c51.get("status")),
                       "met": c51.get("status") == "ok" and c51["clocks_12T"] <= 3000})
    for r in t2:
        if r["target"].startswith("atmega") and r["preset"] == "auto":
            checks.append({"target": f"default chain step ({r['form']}) on the ATmega328P <= 20000 "
                                     "cycles (80 SPS HX711 at 16 MHz: 10 % of the CPU)",
                           "measured": r["cycles"], "met": r["cycles"] <= 20000,
                           "batch_avg": r["cycles_avg_batch"]})
    p51 = max((r for r in t2 if r["form"] == "fixed_port" and r["preset"] == vectors.CHAIN_PRESET),
              key=lambda r: r["samples_before_timed_step"], default=None)
    if p51:
        checks.append({"target": "fixed chain steady-state step on the 8051 <= 3000 12T clocks "
                                 "(csrc/port/mcs51)",
                       "measured": p51["clocks_12T"], "met": p51["clocks_12T"] <= 3000,
                       "restart_step_12T": p51["clocks_12T_restart"]})
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
    if t1 and 2 in _orders(a.orders) and not checks[2]["met"] and ("fixed16", 2, True) in IMAGES:
        img, n = IMAGES[("fixed16", 2, True)]
        prof = runner.profile(img, "sig_tcomp16_apply_q", n)
        profiles["sig_tcomp16_apply_q order 2 hw"] = prof
        print("  profile of sig_tcomp16_apply_q (order 2, hw), instructions per function:")
        for p in prof:
            print(f"    {p['function']:<24} {p['instructions']:>6} instr  {p['calls']:>3} calls")
    if t1 and 2 in _orders(a.orders) and not checks[4]["met"] \
            and ("fixed16_inline", 2, True) in IMAGES:
        img, n = IMAGES[("fixed16_inline", 2, True)]
        lines = runner.profile_lines(img, "sig_tcomp16_apply_q", n)
        profiles["sig_tcomp16_apply_q order 2 hw inline, by source line"] = lines
        print("  profile of sig_tcomp16_apply_q (order 2, inline hooks), instructions by source "
              "line (hooks inlined at their own lines):")
        for p in lines[:12]:
            print(f"    {p['line']:<28} {p['instructions']:>6} instr")
    if p51 and not checks[-1]["met"] and ("chain", "fixed", "mcs51-port") in IMAGES:
        img, n = IMAGES[("chain", "fixed", "mcs51-port")]
        prof = runner.profile(img, "sig_chain_mcs51_step", n)
        profiles["sig_chain_mcs51_step 8051 steady state"] = prof
        lines = runner.profile_lines_mcs51(img, "sig_chain_mcs51_step", n)
        profiles["sig_chain_mcs51_step 8051 steady state, by source line"] = lines
        profiles["sig_chain_mcs51_step what remains"] = WHAT_3000_TAKES
        print("  where the port's steady-state step's 12T clocks go (s51 history, exclusive per "
              "function; mul16 = the MUL AB 16x16 product):")
        for p in prof:
            print(f"    {p['function']:<24} {p['clocks_12T']:>7} clk12T {p['clocks_1t_stc_y5']:>6} "
                  f"clk1T {p['instructions']:>6} instr {p['calls']:>3} calls")
        print("  ... by C source line (csrc/port/mcs51/sig_chain_mcs51.c as built):")
        for p in lines[:15]:
            print(f"    {p['line']:<26} {p['clocks_12T']:>6} clk12T {p['instructions']:>5} instr")
        print("  what 3000 would take: " + WHAT_3000_TAKES)
    if c51 and not any(c["target"].endswith("(portable C)") and c["met"] for c in checks) \
            and ("chain", "fixed", "mcs51") in IMAGES:
        img, n = IMAGES[("chain", "fixed", "mcs51")]
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
