"""Error against cost of drift models: polynomial orders and piecewise-linear
tables side by side, each scored by blocked cross-validation over
temperature, evaluated as the deployed fixed-point C evaluates it, and (with
`mcu=True`) measured on the MSP430F5510 simulator (lab.mcu.model_cost).

Per dataset, axis, family and size a row holds:

  cv_rms      blocked cross-validation RMS over temperature
              (pysig.tcomp._cross_validation: interior blocks of the temperature
              range held out in turn), in the data's unit, of the float
              least-squares model;
  fit_rms     in-sample RMS of the deployed fixed-point model as the C
              computes it (sig_tcomp_delta_q / sig_pwl_eval_q16 via Cython),
              temperature quantised to 0.01 °C;
  data_bytes  bytes of one axis' model as stored (coefficients or table plus
              its parameters);
  text_bytes, helper_bytes, cycles, single_call_cycles, energy_uj
              the MSP430 figures (see lab.mcu.model_cost), None without MCU;
  avr_cycles, avr_text_bytes, avr_helper_bytes
              the same portable C on the ATmega328P (gcc-avr -Os, simavr,
              Timer 1 cycles; `avr=True`), None otherwise and for pwl2 (the
              MSP430 assembly lookup).
"""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from lab.mcu.model_cost import energy_uj, mcu_poly, mcu_pwl, mcu_pwl2, poly_eval_host
from pysig.errors import InputFileError
from pysig.lsq import fit_poly
from pysig.sim._chamber import ChamberParams, simulate
from pysig.tcomp import _quant as quant
from pysig.tcomp._tcomp import TcompQ
from pysig.tcomp._cross_validation import (CHOICE_TOLERANCE, DEFAULT_BLOCKS, PAPER_ORDER, bin_by_temperature,
                           choose, cross_validate, four_point_choice, four_point_study,
                           load_curve, score_sizes)
from pysig.tcomp._table_fit import PwlQ16, fit_pwl, fit_pwl_q16, quantize_values

POLY_ORDERS = tuple(range(1, 9))
PWL_KNOTS = (2, 3, 4, 5, 6, 8, 9, 12, 17, 24, 33, 48, 65, 97, 129, 184)
CHAMBER_BIN_C = 0.25
MPU_COLUMNS = ("temp_c", ("gyro_x", "gyro_y", "gyro_z"))


def datasets(which, mpu_csv=None):
    """The drift curves to compare models on.

    Parameters
    ----------
    which : iterable of str
        ``"mpu6000"`` (a real gyro offset curve read from `mpu_csv`) and/or
        ``"chamber"`` (pysig.sim._chamber's default run, binned by 0.25 °C).
    mpu_csv : path-like, optional
        The MPU-6000 gyro offset recording (columns temp_c, gyro_x..z); it is
        GPL-licensed and never bundled, so the caller says where it is.

    Returns
    -------
    dict
        name -> (Curve, unit string).

    Raises
    ------
    InputFileError
        ``"mpu6000"`` asked for and `mpu_csv` missing.

    Examples
    --------
    >>> (curve, unit), = datasets(["chamber"]).values()
    >>> curve.names, unit
    (('x', 'y', 'z'), 'LSB')
    """
    out = {}
    if "mpu6000" in which:
        if mpu_csv is None or not Path(mpu_csv).exists():
            raise InputFileError(f"{mpu_csv} not found: the real curve lives in ../shared/data "
                                 f"(GPL, not bundled); run from the workplace checkout or drop "
                                 f"the mpu6000 dataset")
        curve = load_curve(mpu_csv, MPU_COLUMNS[0], list(MPU_COLUMNS[1]))
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


def poly_data_bytes(order):
    """Bytes of one axis' polynomial as stored: q (u8) + (order+1) int32,
    plus the model header t_lo, t_hi, t_center, t0, u_mul (int16), u_shift,
    order (u8) = 12 bytes (the sig_image payload)."""
    return 1 + 4 * (order + 1) + 12


def pwl_models(curve, n_knots):
    """One fixed-point table of `n_knots` per axis (pysig.tcomp._table_fit)."""
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
    """The deployed fixed-point power-of-two tables (one per axis, shared
    grid) and the grid's shift."""
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


# ------------------------------------------------------------------- rows --
def run_dataset(name, curve, unit, mcu=True, log=print, poly_orders=POLY_ORDERS,
                pwl_knots=PWL_KNOTS, n_blocks=DEFAULT_BLOCKS, port_tables=False, avr=False):
    """Every row (see the module docstring) of one dataset.

    Parameters
    ----------
    name : str
        The dataset's name, copied into each row.
    curve : pysig.tcomp._cross_validation.Curve
        The drift curve, one column per axis (three axes).
    unit : str
        The curve's unit, copied into each row.
    mcu : bool
        Build and run each model on the MSP430 simulator for its cycles and
        code bytes (needs clang-14 and mspdebug); if False those are None.
    log : callable
        Receives one progress line per model.
    poly_orders, pwl_knots : tuple of int
        The polynomial orders and table sizes to compare.
    n_blocks : int
        Temperature blocks of the cross-validation.
    avr : bool
        Also build and run the polynomial and table models on the
        ATmega328P (needs gcc-avr, avr-libc and simavr; with mcu).
    port_tables : bool
        Add family ``"pwl2"``: tables with knots a power of two temperature
        units apart, measured on the MSP430 assembly lookup (three axes per
        call, cycles / 3); its size is the grid's own knot count.

    Returns
    -------
    list of dict
        One row per (family, size, axis).

    Raises
    ------
    lab.mcu.runner.McuError
        An MSP430 result differs from the host C, or a build fails.

    Examples
    --------
    >>> (curve, unit), = datasets(["chamber"]).values()
    >>> rows = run_dataset("chamber", curve, unit, mcu=False, log=lambda m: None,
    ...                    poly_orders=(2,), pwl_knots=(9,))
    >>> [(r["family"], r["size"], r["axis"]) for r in rows][:2]
    [('poly', 2, 'x'), ('poly', 2, 'y')]
    """
    rows = []
    temp = curve.temp
    cv = {}
    for axis in curve.names:
        y = curve.axis(axis)
        for fam, sizes in (("poly", poly_orders), ("pwl", pwl_knots)):
            sizes = [s for s in sizes if fam == "poly" or s <= temp.size]
            for s in score_sizes(fam, sizes, temp, y, n_blocks=n_blocks):
                cv[(fam, s.size, axis)] = s
    for fam, sizes in (("poly", poly_orders), ("pwl", pwl_knots)):
        for size in sizes:
            if fam == "pwl" and size > temp.size:
                continue
            t0 = time.time()
            if fam == "poly":
                pm = poly_models(curve, size)
                fixed = [poly_eval_host(pm, a, quant.to_centi(temp))[1] for a in range(3)]
                data_bytes = poly_data_bytes(size)
                meas = mcu_poly(f"{name}-poly{size}", pm, size) if mcu else None
                avr_meas = mcu_poly(f"{name}-poly{size}", pm, size, "avr") if mcu and avr else None
            else:
                tabs = pwl_models(curve, size)
                fixed = [t(temp) for t in tabs]
                data_bytes = tabs[0].data_bytes
                meas = mcu_pwl(f"{name}-pwl{size}", tabs, size) if mcu else None
                avr_meas = mcu_pwl(f"{name}-pwl{size}", tabs, size, "avr") if mcu and avr else None
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
                       "avr_cycles": avr_meas["cycles"][a] if avr_meas else None,
                       "avr_text_bytes": avr_meas["text_bytes"] if avr_meas else None,
                       "avr_helper_bytes": avr_meas["helper_bytes"] if avr_meas else None,
                       "unit": unit}
                rows.append(row)
            log(f"  {name} {fam} {size}: {time.time() - t0:.1f} s")
    done = set()
    for n_req in pwl_knots if port_tables else ():
        if n_req > temp.size:
            continue
        t0 = time.time()
        tabs, shift = pwl2_models(curve, n_req)
        size = tabs[0].n_knots
        if size in done or size > temp.size:
            continue
        done.add(size)
        meas = mcu_pwl2(f"{name}-pwl2-{size}", tabs) if mcu else None
        for a, axis in enumerate(curve.names):
            y = curve.axis(axis)
            cv_rms, _ = cross_validate(pwl2_fitter(n_req), temp, y, n_blocks)
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
                         "avr_cycles": None, "avr_text_bytes": None, "avr_helper_bytes": None,
                         "unit": unit})
        log(f"  {name} pwl2 {size} (spacing {1 << shift}): {time.time() - t0:.1f} s")
    return rows


def summarise(name, curve, rows):
    """Choices by blocked CV, the magnetometer paper's four-point study,
    Pareto fronts (by cycles when measured, and by data bytes)."""
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
    """Rows not dominated in (cost, cv_rms), cheapest first.

    Examples
    --------
    >>> rows = [{"cycles": 100, "cv_rms": 5.0}, {"cycles": 100, "cv_rms": 4.0},
    ...         {"cycles": 200, "cv_rms": 4.5}, {"cycles": 300, "cv_rms": 1.0}]
    >>> [r["cycles"] for r in pareto_front(rows)]
    [100, 300]
    """
    front = []
    for r in sorted(rows, key=lambda r: (r[cost], r["cv_rms"])):
        if not front or r["cv_rms"] < front[-1]["cv_rms"]:
            front.append(r)
    return front


def model_name(r):
    """'order N', 'table of N knots' or 'power-of-two table of N knots'."""
    if r["family"] == "poly":
        return f"order {r['size']}"
    return f"{'power-of-two ' if r['family'] == 'pwl2' else ''}table of {r['size']} knots"


def cheapest_within(rows, tolerance=CHOICE_TOLERANCE, cost="cycles"):
    """The cheapest model whose CV RMS is within `tolerance` of the best."""
    best = min(r["cv_rms"] for r in rows)
    return min((r for r in rows if r["cv_rms"] <= best * (1 + tolerance)),
               key=lambda r: (r[cost], r["data_bytes"]))
