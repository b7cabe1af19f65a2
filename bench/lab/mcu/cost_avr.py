"""The ATmega328P rows of the MCU cost tables: the same csrc/ code and the
same harnesses as the MSP430 and 8051 rows (lab.mcu.cost_tables), built
with gcc-avr -Os for the Arduino Uno's chip, run in simavr, every output
read back and checked against the host C before a row is returned.

Cycles: the harness's own Timer 1 count at clk/1 (sim_avr): one call with
its argument set-up, and the batch between bench_start/bench_stop (loop
included) per vector.  RAM: the state's ELF size + the call's stack
high-water (painted).  Flash: the call tree from the disassembly, libgcc's
and avr-libc's helpers apart.  The 328P's 2 KB of RAM holds the vectors of
AVR_CHAIN_N chain samples beside the program (the other targets run 200).
"""
from __future__ import annotations

import numpy as np

from lab.mcu import pwl_vectors, runner, tcomp16_vectors, vectors
from lab.mcu.cost_tables import (CHAIN_SRC, HARNESS, TCOMP16_SRC, TCOMP_SRC, _i16, chain_ops,
                                 chain_reads, check_chain, check_tcomp, check_tcomp16, tcomp_ops)
from lab.mcu.tmodel_vectors import tmodel_case, write_tmodel_header

AVR_HZ = runner.AVR_F_CPU
AVR_TARGET = "atmega328p (simavr, gcc-avr -Os)"
AVR_CHAIN_N = 120
BATCH = "bench_start:bench_stop"


def _cost(img, func, r, n_batch, per_call=1):
    """The figures every AVR row shares, from one measure() result."""
    one = r["funcs"][func]
    clos = runner.code_closure(img, func)
    row = {"target": AVR_TARGET, "cycles": one["cycles"],
           "time_us": round(one["cycles"] / per_call / AVR_HZ * 1e6, 2),
           "text_bytes": sum(v for k, v in clos.items() if not runner.is_helper(k)),
           "helper_bytes": sum(v for k, v in clos.items() if runner.is_helper(k)),
           "stack_bytes": one["stack_bytes"], "program_flash_bytes": None,
           "measurement_overhead": r["overhead"]}
    if BATCH in r["regions"]:
        row["cycles_avg_batch"] = round(r["regions"][BATCH]["cycles"] / n_batch, 1)
    sec = runner.avr_section_sizes(img)
    row["program_flash_bytes"] = sec["text"] + sec["data"]
    return row


def chain_row_avr(form: str, case) -> dict:
    """One chain step (the settled chain's extra step) and the batch, for one
    preset and numeric form, every output and status - the timed step's and
    its stable flag too - checked against the host chain (fixed: bit for
    bit; float: 1e-5 relative)."""
    tag = "" if case.preset == vectors.CHAIN_PRESET else f"-{case.preset}"
    gen = runner.BUILD_DIR / "gen" / f"chain-avr{tag}"
    vectors.write_chain_header(case, gen / "chain_vectors.h")
    fl = form == "float"
    func = "sig_chain_step_f" if fl else "sig_chain_step_q"
    img = runner.build_avr(CHAIN_SRC, HARNESS / "chain_harness.c", ["BENCH_FLOAT"] if fl else [],
                           include_dirs=[gen], name=f"chain{tag}-{form}")
    n = len(case.x)
    r = runner.measure(img, funcs=[func], regions=[BATCH], reads=chain_reads(n))
    check_chain(case, form, r["reads"])
    state = runner.symbol_size(img, "chain")
    row = _cost(img, func, r, n)
    row.update(form=form, preset=case.preset, state_bytes=state,
               ram_bytes=state + row["stack_bytes"], ops=chain_ops(form), checked_samples=n)
    return row


def chain_rows_avr():
    """Every preset (the default `auto` included), fixed and float."""
    from pysig.weigh._presets import PRESETS
    return [chain_row_avr(form, vectors.chain_case(n=AVR_CHAIN_N, preset=p))
            for p in PRESETS for form in ("fixed", "float")]


def tcomp_row_avr(order: int, form: str) -> dict:
    """The polynomial family, 3 axes: sig_tcomp_apply_q/_f (form fixed or
    float) or the compact sig_tcomp16_apply_q (form fixed16)."""
    compact = form == "fixed16"
    if compact:
        case = tcomp16_vectors.tcomp16_case(order)
        base = case.base
        gen = runner.BUILD_DIR / "gen" / f"tcomp16-avr-o{order}"
        tcomp16_vectors.write_tcomp16_header(case, gen / "tcomp16_vectors.h")
        func, harness, src, defines = "sig_tcomp16_apply_q", "tcomp16_harness.c", TCOMP16_SRC, []
    else:
        case = base = vectors.tcomp_case(order)
        gen = runner.BUILD_DIR / "gen" / f"tcomp-avr-o{order}"
        vectors.write_tcomp_header(case, gen / "tcomp_vectors.h")
        fl = form == "float"
        func = "sig_tcomp_apply_f" if fl else "sig_tcomp_apply_q"
        harness, src, defines = "tcomp_harness.c", TCOMP_SRC, ["BENCH_FLOAT"] if fl else []
    img = runner.build_avr(src, HARNESS / harness, defines, include_dirs=[gen],
                           name=f"tcomp-o{order}-{form}")
    n, a = base.in_q.shape
    esize = 4 if form == "float" else 2
    r = runner.measure(img, funcs=[func], regions=[BATCH],
                       reads={"vec_out": esize * n * a, "vec_status": 2 * n})
    (check_tcomp16 if compact else check_tcomp)(case, form, r["reads"])
    model = runner.symbol_size(img, "model")
    row = _cost(img, func, r, n)
    row.update(family="poly", form=form, order=order, axes=a, model_bytes=model,
               ram_bytes=model + row["stack_bytes"],
               ops=tcomp_ops("fixed16" if compact else form, order), checked_vectors=n)
    return row


def pwl_row_avr(value_frac=(9, 4, 1), spacing_shift=8) -> dict:
    """The table family: sig_pwl_eval_q16, one axis per call, the three
    tables of lab.mcu.pwl_vectors (one per output-scaling branch)."""
    case = pwl_vectors.pwl_case(spacing_shift=spacing_shift, value_frac=value_frac)
    gen = runner.BUILD_DIR / "gen" / f"pwl-avr-{''.join(map(str, value_frac))}"
    pwl_vectors.write_pwl_header(case, gen / "pwl_vectors.h")
    img = runner.build_avr([runner.c_source("sig_pwl")], HARNESS / "pwl_harness.c",
                           {"PW_EVAL": "sig_pwl_eval_q16"}, include_dirs=[gen], name="pwl")
    n = len(case.temps)
    r = runner.measure(img, funcs=["sig_pwl_eval_q16"], regions=[BATCH],
                       reads={"vec_out": 12 * n, "vec_status": 6 * n})
    h_out, h_st = pwl_vectors.host_eval(case)
    if not (np.array_equal(np.frombuffer(r["reads"]["vec_out"], "<i4").reshape(3, n), h_out)
            and np.array_equal(_i16(r["reads"]["vec_status"]).reshape(3, n), h_st)):
        raise SystemExit("table lookup on the AVR: firmware results differ from the host C")
    row = _cost(img, "sig_pwl_eval_q16", r, 3 * n)
    row.update(family="table", form="fixed", n_knots=case.n_knots, value_frac=list(value_frac),
               axes=1, checked_values=3 * n)
    return row


def image_loader_row_avr(family: str) -> dict:
    """sig_tmodel_load_image on a fitted image kept in a const array (CRC
    checked, sections found, the model set up), then a batch of
    sig_tmodel_apply on raw codes: every output and status equal to the
    host C."""
    from pysig.tcomp import _tmodel
    image, codes, readings = tmodel_case(family)
    gen = runner.BUILD_DIR / "gen" / f"tmodel-avr-{family}"
    gen.mkdir(parents=True, exist_ok=True)
    write_tmodel_header(gen / "tmodel_vectors.h", image, codes, readings)
    img = runner.build_avr(runner.csrc_sources("sig_tmodel", "sig_tmodel_image"),
                           HARNESS / "tmodel_harness.c", [], include_dirs=[gen],
                           name=f"tmodel-{family}")
    n, a = readings.shape
    r = runner.measure(img, funcs=["sig_tmodel_load_image"], regions=[BATCH],
                       reads={"vec_out": 2 * n * a, "vec_status": 2 * n, "init_status": 2})
    h_out, h_st = _tmodel.TModel.from_image(image).apply(codes, readings)
    if not (_i16(r["reads"]["init_status"])[0] == 0
            and np.array_equal(_i16(r["reads"]["vec_out"]).reshape(n, a), h_out)
            and np.array_equal(_i16(r["reads"]["vec_status"]), h_st)):
        raise SystemExit(f"image loader ({family}) on the AVR: results differ from the host C")
    row = _cost(img, "sig_tmodel_load_image", r, n)
    row["cycles_apply_avg_batch"] = row.pop("cycles_avg_batch")
    row.update(family=family, form="image load", image_bytes=len(image), axes=a,
               model_bytes=runner.symbol_size(img, "model"), checked_vectors=n)
    return row


def tcomp_rows_avr(orders=(1, 2, 3, 4, 5)):
    """Compensation families on the AVR: polynomial (fixed, compact, float)
    per order, the table, and the image loader of each family."""
    rows = [tcomp_row_avr(o, f) for f in ("fixed", "fixed16", "float") for o in orders]
    rows.append(pwl_row_avr())
    rows += [image_loader_row_avr(f) for f in ("poly", "table")]
    return rows
