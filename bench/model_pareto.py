"""Error against cost of drift models (issue 10): polynomial orders 1-8 and
piecewise-linear tables, side by side, on a real drift curve and on the
project's simulated chamber.

    python bench/model_pareto.py --json pareto.json --plot figs/

For each dataset, axis, family and size:
  cv_rms      blocked cross-validation RMS over temperature (pysig.tcomp.model_select:
              interior blocks of the temperature range held out in turn), in
              the data's unit, of the float least-squares model;
  fit_rms     in-sample RMS of the deployed fixed-point model as the C
              computes it (sig_tcomp_delta_q / sig_pwl_eval_q16 via Cython),
              temperature quantised to 0.01 °C;
  data_bytes  bytes of one axis' model as stored (coefficients or table plus
              its parameters);
  text_bytes  .text bytes of the evaluation code from csrc (the call tree of
              the entry point, runtime helpers such as __mspabi_mpyl_f5hw
              counted separately in helper_bytes);
  cycles      MSP430F5510 MCLK cycles per call, mspdebug 0.22 `sim` (classic
              MSP430 timing), hardware-multiplier helpers on the simulated
              16x16 MPY: mean over N_TEMPS temperatures spread over the range,
              loop overhead removed (the same loop around a no-op function);
  energy_uj   cycles / 8 MHz x 1.56 mA x 3.3 V.
Every MCU result is read back from the simulator and compared with the host
C bit for bit; a mismatch stops the bench.

Family "pwl2" (with --port-tables): tables whose knots are a power of two temperature units apart
(the grid starts at the data's first temperature and ends at or before its
last one; beyond the last knot the table is flat), the layout the MSP430
assembly lookup of csrc/port/msp430/sig_pwl_msp430.S indexes with one
product: cycles of sig_pwl_eval_axes_msp430 (the three axes of one image per
call) divided by 3, checked bit for bit against the host C sig_pwl_eval_q16.
Its entries are stored with at most 4 fraction bits (1/16 LSB: value_frac 4
needs no output shift; the extra rounding is below 1/32 LSB).
Its size is the grid's own knot count (the requested count rounded up to
the next power-of-two spacing).

Datasets: the MPU-6000 gyro offset curve of ../shared/data (MatrixPilot,
GPL: read from there, never bundled) and pysig.sim.chamber's default run
(the seed paper's 0/25/50/70 °C steps) averaged into 0.25 °C bins."""
from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent

from pysig.mcu import runner  # noqa: E402  (bench/mcu/runner.py)

from pysig.tcomp import quant  # noqa: E402
from pysig.tcomp._tcomp import TcompQ  # noqa: E402
from pysig.io import atomic_output  # noqa: E402
from pysig.lsq import fit_poly  # noqa: E402
from pysig.tcomp.model_select import (CHOICE_TOLERANCE, PAPER_ORDER, bin_by_temperature,  # noqa: E402
                                choose, four_point_choice, four_point_study, load_curve,
                                score_sizes)
from pysig.tcomp.pwl import PwlQ16, fit_pwl, fit_pwl_q16, quantize_values  # noqa: E402
from pysig.tcomp.model_select import cross_validate  # noqa: E402
from pysig.mcu import pwl_vectors  # noqa: E402
from pysig.sim.chamber import ChamberParams, simulate  # noqa: E402

HERE = Path(__file__).resolve().parent / "model_pareto"
SHARED_DATA = Path(os.environ.get("PYSIG_SHARED_DATA", ROOT.parent / "shared" / "data"))  # a worktree elsewhere
MPU_CSV = SHARED_DATA / "mpu6000_gyro_offset_vs_temp" / "mpu6000_sn102_gyro_offset.csv"

POLY_ORDERS = tuple(range(1, 9))
PWL_KNOTS = (2, 3, 4, 5, 6, 8, 9, 12, 17, 24, 33, 48, 65, 97, 129, 184)
N_TEMPS = 16
MCLK_HZ = 8e6
SUPPLY_A = 1.56e-3
SUPPLY_V = 3.3
CHAMBER_BIN_C = 0.25
N_BLOCKS = 8
PAPER_CLAIM = ("Seed paper (4 chamber temperatures, its Tables 2-3):\n"
               "order 2 is the best error/cost trade-off")


def energy_uj(cycles):
    return cycles / MCLK_HZ * SUPPLY_A * SUPPLY_V * 1e6


# ---------------------------------------------------------------- datasets --
def datasets(which):
    out = {}
    if "mpu6000" in which:
        if not MPU_CSV.exists():
            raise SystemExit(f"{MPU_CSV} not found: the real curve lives in ../shared/data "
                             f"(GPL, not bundled); run from the workplace checkout or drop "
                             f"--datasets mpu6000")
        curve = load_curve(MPU_CSV, "temp_c", ["gyro_x", "gyro_y", "gyro_z"])
        out["mpu6000"] = (curve, "64 raw LSB (~1/2099 °/s)")
    if "chamber" in which:
        sim = simulate(ChamberParams())
        drift = np.column_stack([sim[a] - sim["ref_" + a] for a in "xyz"])
        curve = bin_by_temperature(sim["temp"], drift, ["x", "y", "z"], CHAMBER_BIN_C,
                                   where="sim_chamber default (0/25/50/70 °C steps)")
        out["chamber"] = (curve, "LSB")
    return out


# ---------------------------------------------------------- deployed models --
def poly_models(curve, order):
    """Fixed-point sig_tcomp_q model of `order` for all axes (f(T) itself,
    no reference folded in), fitted on the abscissa the C uses."""
    t_lo, t_hi = (int(v) for v in quant.to_centi([curve.temp.min(), curve.temp.max()]))
    sc = quant.choose_scaling(t_lo, t_hi)
    axes = []
    for name in curve.names:
        fit = fit_poly(curve.temp, curve.axis(name), order, center=sc.center_c, scale=sc.scale_c,
                       what=f"{name} order {order}")
        axes.append(quant.quantize_axis(fit.coef, what=f"{name} order {order}"))
    model = TcompQ.from_fields([a.coef for a in axes], [a.q for a in axes], sc.t_lo, sc.t_hi,
                               sc.t_center, sc.t_center, sc.u_mul, sc.u_shift)
    return {"scaling": sc, "axes": axes, "model": model}


def poly_eval_host(pm, axis, temp_int):
    d, _ = pm["model"].delta(axis, np.asarray(temp_int, dtype=np.int16))
    return d, d / float(1 << pm["axes"][axis].q)


def poly_data_bytes(order):
    # per axis: q (u8) + (order+1) int32; model header: t_lo, t_hi, t_center,
    # t0, u_mul (int16), u_shift, order (u8) = 12 bytes (sig_image payload)
    return 1 + 4 * (order + 1) + 12


def pwl_models(curve, n_knots):
    return [fit_pwl_q16(curve.temp, curve.axis(a), n_knots, what=f"{a} table of {n_knots}")
            for a in curve.names]


TEMP_UNITS_PER_C = 100          # 0.01 degC, as the compensation's temperature input


def pow2_grid(temp, n_req, scale=TEMP_UNITS_PER_C):
    """(t_lo, shift, n): knots 2^shift units apart from the data's first
    temperature, at least n_req of them (spacing <= span / (n_req - 1)),
    the last one at or before the data's last temperature."""
    t_lo = int(np.ceil(float(np.min(temp)) * scale - 1e-9))
    span = int(np.floor(float(np.max(temp)) * scale + 1e-9)) - t_lo
    shift = max(0, int(np.floor(np.log2(span / (n_req - 1)))))
    n = span // (1 << shift) + 1
    while n > 255:
        shift += 1
        n = span // (1 << shift) + 1
    return t_lo, shift, n


def pwl2_fitter(n_req, scale=TEMP_UNITS_PER_C):
    """fit(temp, y) -> float table on the power-of-two grid (held-out blocks
    bridged linearly, as for the uniform tables)."""
    def fit(temp, y):
        t_lo, shift, n = pow2_grid(temp, n_req, scale)
        return fit_pwl(temp, y, n, lo=t_lo / scale, hi=(t_lo + (n - 1) * (1 << shift)) / scale,
                       bridge=True, what=f"power-of-two table of {n} knots")
    return fit


def pwl2_models(curve, n_req, scale=TEMP_UNITS_PER_C):
    """The deployed fixed-point tables (one per axis, shared grid)."""
    t_lo, shift, n = pow2_grid(curve.temp, n_req, scale)
    tabs = []
    for a in curve.names:
        f = pwl2_fitter(n_req, scale)(curve.temp, curve.axis(a))
        table, vf = quantize_values(f.values, what=f"{a} power-of-two table")
        if vf > 4:      # 1/16 LSB steps are plenty, and value_frac 4 needs no output shift
            vf = 4
            table = np.round(np.asarray(f.values) * 16).astype(np.int16)
        tabs.append(PwlQ16(table=table, t_lo=t_lo, t_hi=t_lo + (n - 1) * (1 << shift),
                           recip=1 << (32 - shift), value_frac=vf, units_per_c=float(scale),
                           rms=0.0))
    return tabs, shift


def mcu_pwl2(tag, tabs, shift):
    """sig_pwl_eval_axes_msp430 on the three tables: cycles of one call / 3
    (the assembly's cost hardly depends on the temperature: one index
    product, no search), every output of N_TEMPS temperatures checked."""
    temps = mcu_temps(tabs[0].t_lo, tabs[0].t_hi)
    case = pwl_vectors.PwlCase(np.array([t.table for t in tabs]), tuple(t.value_frac for t in tabs),
                               tabs[0].t_lo, tabs[0].t_hi, tabs[0].recip,
                               np.asarray(temps, dtype=np.int16), int(temps[len(temps) // 2]))
    d = _case_dir(tag)
    pwl_vectors.write_pwl_header(case, d / "pwl_vectors.h")
    harness = ROOT / "bench" / "mcu" / "harness" / "pwl_harness.c"
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
        raise SystemExit(f"{tag}: MSP430 assembly result differs from the host C")
    one = res["funcs"][entry]["cycles"]
    text, helper, tree = call_tree_bytes(img, entry)
    return {"cycles": [one / 3] * 3, "single_call_cycles": one, "text_bytes": text,
            "helper_bytes": helper, "call_tree": tree}


# ------------------------------------------------------------------ MCU side --
def _arr(values):
    return "{" + ", ".join(str(int(v)) for v in values) + "}"


def _case_dir(tag):
    d = runner.BUILD_DIR / "model_pareto" / tag
    d.mkdir(parents=True, exist_ok=True)
    return d


def mcu_temps(t_lo, t_hi):
    return np.round(np.linspace(t_lo, t_hi, N_TEMPS)).astype(np.int16)


_DIS_CACHE = {}


def call_tree_bytes(img, entry):
    """(csrc bytes, runtime-helper bytes) of the functions reachable from
    `entry` by direct calls (MSP430 disassembly)."""
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


def measure_case(tag, harness, source_files, header_text, entry):
    """Build, run, read back: per-axis cycles, outputs, statuses."""
    d = _case_dir(tag)
    (d / "pareto_case.h").write_text(header_text)
    img = runner.build_msp430(source_files, HERE / harness, include_dirs=[d], hwmult=True,
                              name=f"pareto-{tag}")
    regions = ["bench_start:bench_axis1", "bench_axis1:bench_axis2", "bench_axis2:bench_stop",
               "bench_null_start:bench_null_stop"]
    res = runner.measure(img, funcs=[entry], regions=regions,
                         reads={"out": 3 * N_TEMPS * 4, "status": 3 * N_TEMPS * 2}, stack=False)
    null = res["regions"][regions[3]]["cycles"]
    cycles = [(res["regions"][r]["cycles"] - null) / N_TEMPS for r in regions[:3]]
    out = np.frombuffer(res["reads"]["out"], "<i4").reshape(3, N_TEMPS)
    status = np.frombuffer(res["reads"]["status"], "<i2").reshape(3, N_TEMPS)
    text, helper, tree = call_tree_bytes(img, entry)
    return {"cycles": cycles, "single_call_cycles": res["funcs"][entry]["cycles"],
            "out": out, "status": status, "text_bytes": text, "helper_bytes": helper,
            "call_tree": tree}


def mcu_poly(tag, pm, order):
    sc = pm["scaling"]
    temps = mcu_temps(sc.t_lo, sc.t_hi)
    coef = [c for a in pm["axes"] for c in a.coef]
    h = (f"#define N_AXES 3\n#define ORDER {order}\n#define N_TEMPS {N_TEMPS}\n"
         f"#define POLY_COEF {{{', '.join(f'INT32_C({c})' for c in coef)}}}\n"
         f"#define POLY_Q {_arr([a.q for a in pm['axes']])}\n"
         f"#define POLY_T_LO {sc.t_lo}\n#define POLY_T_HI {sc.t_hi}\n"
         f"#define POLY_T_CENTER {sc.t_center}\n#define POLY_U_MUL {sc.u_mul}\n"
         f"#define POLY_U_SHIFT {sc.u_shift}\n#define TEMPS {_arr(temps)}\n")
    m = measure_case(tag, "harness_poly.c",
                     [runner.c_source("sig_tcomp"), runner.c_source("sig_poly"),
                      runner.c_source("sig_image"), runner.c_source("sig_crc16")],
                     h, "sig_tcomp_delta_q")
    for a in range(3):
        host, _ = poly_eval_host(pm, a, temps)
        if not np.array_equal(host, m["out"][a]):
            raise SystemExit(f"{tag}: MSP430 result differs from the host C on axis {a}: "
                             f"{m['out'][a]} vs {host}")
    return m


def mcu_pwl(tag, tabs, n_knots):
    temps = mcu_temps(min(t.t_lo for t in tabs), max(t.t_hi for t in tabs))
    h = (f"#define N_AXES 3\n#define N_KNOTS {n_knots}\n#define N_TEMPS {N_TEMPS}\n"
         f"#define PWL_TABLES {{{', '.join(_arr(t.table) for t in tabs)}}}\n"
         f"#define PWL_RANGES {{{', '.join(_arr([t.t_lo, t.t_hi]) for t in tabs)}}}\n"
         f"#define PWL_RECIPS {{{', '.join(f'UINT32_C({t.recip})' for t in tabs)}}}\n"
         f"#define PWL_VFS {_arr([t.value_frac for t in tabs])}\n#define TEMPS {_arr(temps)}\n")
    m = measure_case(tag, "harness_pwl.c", [runner.c_source("sig_pwl")], h, "sig_pwl_eval_q16")
    for a, t in enumerate(tabs):
        host, hstat = t.eval_c(temps)
        if not (np.array_equal(host, m["out"][a]) and np.array_equal(hstat, m["status"][a])):
            raise SystemExit(f"{tag}: MSP430 result differs from the host C on axis {a}: "
                             f"{m['out'][a]} vs {host}")
    return m


# ------------------------------------------------------------------- bench --
def run_dataset(name, curve, unit, mcu=True, log=print, port_tables=False):
    rows = []
    temp = curve.temp
    cv = {}
    for axis in curve.names:
        y = curve.axis(axis)
        for fam, sizes in (("poly", POLY_ORDERS), ("pwl", PWL_KNOTS)):
            sizes = [s for s in sizes if fam == "poly" or s <= temp.size]
            for s in score_sizes(fam, sizes, temp, y, n_blocks=N_BLOCKS):
                cv[(fam, s.size, axis)] = s
    for fam, sizes in (("poly", POLY_ORDERS), ("pwl", PWL_KNOTS)):
        for size in sizes:
            if fam == "pwl" and size > temp.size:
                continue
            t0 = time.time()
            if fam == "poly":
                pm = poly_models(curve, size)
                fixed = [poly_eval_host(pm, a, quant.to_centi(temp))[1] for a in range(3)]
                data_bytes = poly_data_bytes(size)
                meas = mcu_poly(f"{name}-poly{size}", pm, size) if mcu else None
            else:
                tabs = pwl_models(curve, size)
                fixed = [t(temp) for t in tabs]
                data_bytes = tabs[0].data_bytes
                meas = mcu_pwl(f"{name}-pwl{size}", tabs, size) if mcu else None
            for a, axis in enumerate(curve.names):
                s = cv[(fam, size, axis)]
                fit_rms = float(np.sqrt(np.mean((curve.axis(axis) - fixed[a]) ** 2)))
                row = {"dataset": name, "family": fam, "size": size, "axis": axis,
                       "cv_rms": s.cv_rms, "fit_rms": fit_rms, "fit_rms_float": s.fit_rms,
                       "data_bytes": data_bytes,
                       "text_bytes": meas["text_bytes"] if meas else None,
                       "helper_bytes": meas["helper_bytes"] if meas else None,
                       "cycles": meas["cycles"][a] if meas else None,
                       "single_call_cycles": meas["single_call_cycles"] if meas else None,
                       "energy_uj": energy_uj(meas["cycles"][a]) if meas else None,
                       "unit": unit}
                rows.append(row)
            log(f"  {name} {fam} {size}: {time.time() - t0:.1f} s")
    done = set()
    for n_req in PWL_KNOTS if port_tables else ():
        if n_req > temp.size:
            continue
        t0 = time.time()
        tabs, shift = pwl2_models(curve, n_req)
        size = tabs[0].n_knots
        if size in done or size > temp.size:
            continue
        done.add(size)
        meas = mcu_pwl2(f"{name}-pwl2-{size}", tabs, shift) if mcu else None
        for a, axis in enumerate(curve.names):
            y = curve.axis(axis)
            cv_rms, _ = cross_validate(pwl2_fitter(n_req), temp, y, N_BLOCKS)
            fit_float = pwl2_fitter(n_req)(temp, y)
            fixed = tabs[a](temp)
            rows.append({"dataset": name, "family": "pwl2", "size": size, "axis": axis,
                         "knot_spacing_units": 1 << shift, "cv_rms": cv_rms,
                         "fit_rms": float(np.sqrt(np.mean((y - fixed) ** 2))),
                         "fit_rms_float": float(np.sqrt(np.mean((y - fit_float(temp)) ** 2))),
                         "data_bytes": tabs[0].data_bytes,
                         "text_bytes": meas["text_bytes"] if meas else None,
                         "helper_bytes": meas["helper_bytes"] if meas else None,
                         "cycles": meas["cycles"][a] if meas else None,
                         "single_call_cycles": meas["single_call_cycles"] if meas else None,
                         "energy_uj": energy_uj(meas["cycles"][a]) if meas else None,
                         "unit": unit})
        log(f"  {name} pwl2 {size} (spacing {1 << shift}): {time.time() - t0:.1f} s")
    return rows


def summarise(name, curve, rows):
    """Choices by blocked CV, the paper's four-point study, Pareto fronts."""
    out = {"dataset": name, "notes": list(curve.notes), "temp_range_c": [float(curve.temp.min()),
                                                                         float(curve.temp.max())],
           "n_temperatures": int(curve.temp.size), "axes": {}}
    for axis in curve.names:
        mine = [r for r in rows if r["axis"] == axis]
        ax = {}
        for fam in ("poly", "pwl", "pwl2"):
            scores = [type("S", (), {"size": r["size"], "cv_rms": r["cv_rms"]})
                      for r in mine if r["family"] == fam]
            if scores:
                ax[f"cv_choice_{fam}"] = choose(scores).size
        pts, res = four_point_study(curve.temp, curve.axis(axis))
        ax["four_point"] = {"mode": pts.mode, "targets_c": list(pts.targets),
                            "temps_c": [float(curve.temp[i]) for i in pts.index],
                            "orders": [{"order": r.order, "points_rms": r.points_rms,
                                        "loo_rms": r.loo_rms, "dense_rms": r.dense_rms}
                                       for r in res],
                            "loo_choice": four_point_choice(res).order}
        paper = next(r for r in mine if r["family"] == "poly" and r["size"] == PAPER_ORDER)
        ax["paper_order_cv_rms"] = paper["cv_rms"]
        if mine[0]["cycles"] is not None:
            ax["pareto_front"] = [(r["family"], r["size"]) for r in pareto_front(mine)]
            cheap = cheapest_within(mine)
            ax["cheapest_within_5pct"] = {"family": cheap["family"], "size": cheap["size"],
                                          "cv_rms": cheap["cv_rms"], "cycles": cheap["cycles"]}
        ax["pareto_front_bytes"] = [(r["family"], r["size"]) for r in pareto_front(mine, "data_bytes")]
        out["axes"][axis] = ax
    return out


def pareto_front(rows, cost="cycles"):
    """Rows not dominated in (cost, cv_rms), cheapest first."""
    front = []
    for r in sorted(rows, key=lambda r: (r[cost], r["cv_rms"])):
        if not front or r["cv_rms"] < front[-1]["cv_rms"]:
            front.append(r)
    return front


def model_name(r):
    if r["family"] == "poly":
        return f"order {r['size']}"
    return f"{'power-of-two ' if r['family'] == 'pwl2' else ''}table of {r['size']} knots"


def cheapest_within(rows, tolerance=CHOICE_TOLERANCE, cost="cycles"):
    """The cheapest model whose CV RMS is within `tolerance` of the best."""
    best = min(r["cv_rms"] for r in rows)
    return min((r for r in rows if r["cv_rms"] <= best * (1 + tolerance)),
               key=lambda r: (r[cost], r["data_bytes"]))


def print_table(rows):
    hdr = (f"{'dataset':8} {'axis':7} {'family':6} {'size':>4} {'cv_rms':>9} {'fit_rms':>9} "
           f"{'data_B':>6} {'text_B':>6} {'cycles':>8} {'energy_uJ':>9}")
    print(hdr)
    print("-" * len(hdr))
    for r in rows:
        cyc = "-" if r["cycles"] is None else f"{r['cycles']:8.1f}"
        en = "-" if r["energy_uj"] is None else f"{r['energy_uj']:9.3f}"
        tb = "-" if r["text_bytes"] is None else str(r["text_bytes"])
        print(f"{r['dataset']:8} {r['axis']:7} {r['family']:6} {r['size']:4d} {r['cv_rms']:9.3f} "
              f"{r['fit_rms']:9.3f} {r['data_bytes']:6d} {tb:>6} {cyc:>8} {en:>9}")


def print_summary(summary):
    for s in summary:
        print(f"\n{s['dataset']}: {s['n_temperatures']} temperatures, "
              f"{s['temp_range_c'][0]:.2f}..{s['temp_range_c'][1]:.2f} °C; " + "; ".join(s["notes"]))
        for axis, a in s["axes"].items():
            fp = a["four_point"]
            o = {r["order"]: r for r in fp["orders"]}
            print(f"  {axis}: blocked CV picks poly order {a['cv_choice_poly']}, table of "
                  f"{a['cv_choice_pwl']} knots; paper's order 2 cv_rms {a['paper_order_cv_rms']:.2f}; "
                  f"four points ({fp['mode']}) at " + ", ".join(f"{t:.2f}" for t in fp["temps_c"])
                  + f" °C choose order {fp['loo_choice']} (leave-one-out); dense-curve RMS "
                  + ", ".join(f"order {k} {o[k]['dense_rms']:.2f}" for k in o))
            if "cheapest_within_5pct" in a:
                c = a["cheapest_within_5pct"]
                print(f"    cheapest model within 5 % of the best CV: {c['family']} {c['size']} "
                      f"(cv_rms {c['cv_rms']:.2f}, {c['cycles']:.0f} cycles)")
            if "pareto_front" in a:
                print("    Pareto front (cycles, cv_rms): "
                      + ", ".join(f"{f} {n}" for f, n in a["pareto_front"]))
            print("    Pareto front (data bytes, cv_rms): "
                  + ", ".join(f"{f} {n}" for f, n in a["pareto_front_bytes"]))


# -------------------------------------------------------------------- plot --
def plot(rows, summary, directory):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    written = []
    for s in summary:
        name = s["dataset"]
        mine = [r for r in rows if r["dataset"] == name]
        axes = list(s["axes"])
        fig, subs = plt.subplots(2, len(axes), figsize=(5.2 * len(axes), 8.4), squeeze=False)
        for col, axis in enumerate(axes):
            rs = [r for r in mine if r["axis"] == axis]
            fp = {o["order"]: o for o in s["axes"][axis]["four_point"]["orders"]}
            for row, cost, label in ((0, "cycles", "MSP430F5510 cycles per call (mspdebug sim)"),
                                     (1, "data_bytes", "model bytes per axis (coefficients / table)")):
                ax = subs[row][col]
                for fam, mk, colr, lab in (
                        ("poly", "o", "tab:blue", "polynomial (order), portable C"),
                        ("pwl", "s", "tab:orange", "table (knots), portable C"),
                        ("pwl2", "^", "tab:green", "table, power-of-two knots (knots), "
                                                   "port assembly, 3 axes per call")):
                    fr = [r for r in rs if r["family"] == fam]
                    if not fr:
                        continue
                    ax.scatter([r[cost] for r in fr], [r["cv_rms"] for r in fr], marker=mk, c=colr,
                               label=lab, zorder=3)
                    for r in fr:
                        ax.annotate(str(r["size"]), (r[cost], r["cv_rms"]), fontsize=7,
                                    xytext=(3, 3), textcoords="offset points")
                front = pareto_front(rs, cost)
                ax.step([r[cost] for r in front], [r["cv_rms"] for r in front], "k--", lw=1,
                        where="post", label="Pareto front", zorder=2)
                paper = next(r for r in rs if r["family"] == "poly" and r["size"] == PAPER_ORDER)
                ax.scatter([paper[cost]], [paper["cv_rms"]], s=180, facecolors="none",
                           edgecolors="red", lw=1.5, label="paper's pick: order 2", zorder=4)
                ax.axhline(fp[PAPER_ORDER]["dense_rms"], color="red", lw=0.8, ls=":",
                           label="order 2 fitted on the 4 paper points: RMS on the dense curve")
                loo = s["axes"][axis]["four_point"]["loo_choice"]
                if loo != PAPER_ORDER:
                    ax.axhline(fp[loo]["dense_rms"], color="purple", lw=0.8, ls="-.",
                               label=f"order {loo}, chosen by the 4 points' own leave-one-out: "
                                     f"dense RMS")
                ax.set_xscale("log")
                ax.set_yscale("log")
                ax.xaxis.set_minor_formatter(NullFormatter())
                ax.set_xlabel(label)
                ax.set_ylabel(f"blocked-CV RMS [{rs[0]['unit']}]")
                ax.set_title(f"{name}: {axis}")
                ax.grid(True, which="both", alpha=0.3)
        subs[0][0].legend(fontsize=7, loc="best")
        fig.text(0.99, 0.01, PAPER_CLAIM, ha="right", va="bottom", fontsize=8,
                 bbox=dict(boxstyle="round", fc="lightyellow", ec="grey"))
        here = []
        for axis in axes:
            rs = [r for r in mine if r["axis"] == axis]
            p2 = next(r for r in rs if r["family"] == "poly" and r["size"] == PAPER_ORDER)
            best = min(rs, key=lambda r: r["cv_rms"])
            cheap = cheapest_within(rs)
            here.append(f"{axis}: order 2 {p2['cv_rms']:.3g} at {p2['cycles']:.0f} cycles; best "
                        f"{model_name(best)} {best['cv_rms']:.3g} at {best['cycles']:.0f}; "
                        f"cheapest within 5 %: {model_name(cheap)} {cheap['cv_rms']:.3g} at "
                        f"{cheap['cycles']:.0f}")
        fig.text(0.01, 0.01, "Measured here (blocked-CV RMS):\n" + "\n".join(here), ha="left",
                 va="bottom", fontsize=8, bbox=dict(boxstyle="round", fc="white", ec="grey"))
        fig.tight_layout(rect=(0, 0.08, 1, 1))
        path = directory / f"pareto_{name}.png"
        with atomic_output(path, "wb") as fh:
            fig.savefig(fh, format="png", dpi=110)
        plt.close(fig)
        written.append(str(path))
    return written


def main(argv=None):
    global N_BLOCKS
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", help="write rows and summary as JSON here")
    ap.add_argument("--plot", help="write pareto_<dataset>.png into this directory")
    ap.add_argument("--datasets", default="mpu6000,chamber",
                    help="comma-separated: mpu6000 (real curve), chamber (simulated)")
    ap.add_argument("--blocks", type=int, default=N_BLOCKS,
                    help=f"temperature blocks of the cross-validation (default {N_BLOCKS}; "
                         f"the two end blocks are never held out)")
    ap.add_argument("--port-tables", action="store_true",
                    help="add the power-of-two tables on the MSP430 assembly lookup (family pwl2)")
    ap.add_argument("--no-mcu", action="store_true",
                    help="skip the MSP430 builds (cycles, text bytes, energy left empty)")
    args = ap.parse_args(argv)
    if args.plot and args.no_mcu:
        ap.error("--plot needs the MCU cycles (drop --no-mcu)")
    N_BLOCKS = args.blocks
    rows, summary = [], []
    for name, (curve, unit) in datasets(args.datasets.split(",")).items():
        print(f"{name}: fitting, cross-validating and measuring ...", file=sys.stderr)
        r = run_dataset(name, curve, unit, mcu=not args.no_mcu,
                        log=lambda m: print(m, file=sys.stderr), port_tables=args.port_tables)
        rows += r
        summary.append(summarise(name, curve, r))
    print_table(rows)
    print_summary(summary)
    if args.plot:
        for p in plot(rows, summary, args.plot):
            print(f"wrote {p}")
    if args.json:
        doc = {"description": __doc__, "mcu": {"target": "MSP430F5510", "mclk_hz": MCLK_HZ,
                                                "supply_a": SUPPLY_A, "supply_v": SUPPLY_V,
                                                "timing": "mspdebug 0.22 sim, classic MSP430 table",
                                                "multiplier": "16x16 MPY helpers (-mhwmult=f5series)",
                                                "temps_per_call_mean": N_TEMPS},
               "cv": {"blocks": N_BLOCKS, "held_out": "interior blocks"},
               "rows": rows, "summary": summary}
        with atomic_output(args.json) as fh:
            json.dump(doc, fh, indent=1)
        print(f"wrote {args.json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
