"""Error against cost of drift models (lab.studies.pareto, lab.mcu.model_cost,
printed by bench/model_pareto.py): rows complete and consistent, the Pareto
front, energy, and the MSP430 results equal to the host C bit for bit (in the
simulator) for a polynomial and a table."""
import json
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT, SHARED_DATA, require_shared_data, require_tool
from pysig.errors import InputFileError
from lab.mcu import model_cost, runner
from lab.studies import pareto

KEYS = {"family", "size", "axis", "cv_rms", "fit_rms", "data_bytes", "text_bytes", "cycles",
        "energy_uj"}


MPU_CSV = SHARED_DATA / "mpu6000_gyro_offset_vs_temp" / "mpu6000_sn102_gyro_offset.csv"


def test_energy_at_the_stated_operating_point():
    # 8000 cycles = 1 ms at 8 MHz; 1.56 mA x 3.3 V x 1 ms = 5.148 µJ
    assert model_cost.energy_uj(8000) == pytest.approx(5.148)


def test_pareto_front_drops_dominated_rows():
    rows = [{"cycles": c, "cv_rms": e, "n": i}
            for i, (c, e) in enumerate([(100, 5.0), (100, 4.0), (200, 4.5), (300, 1.0), (50, 9.0)])]
    front = pareto.pareto_front(rows)
    assert [r["n"] for r in front] == [4, 1, 3]


def test_rows_without_mcu_on_the_chamber():
    (curve, unit), = pareto.datasets(["chamber"]).values()
    rows = pareto.run_dataset("chamber", curve, unit, mcu=False, log=lambda m: None,
                              poly_orders=(1, 2, 3), pwl_knots=(2, 5, 9))
    assert len(rows) == 6 * 3
    for r in rows:
        assert KEYS <= set(r)
        assert r["cycles"] is None and r["energy_uj"] is None
        assert r["cv_rms"] > 0 and r["fit_rms"] > 0
    by = {(r["family"], r["size"], r["axis"]): r for r in rows}
    # the simulated drift is quadratic: order 2 beats order 1 by far, and the
    # fixed-point fit is within a few percent of the float fit
    for axis in "xyz":
        assert by[("poly", 2, axis)]["cv_rms"] < 0.3 * by[("poly", 1, axis)]["cv_rms"]
        assert by[("poly", 2, axis)]["fit_rms"] == pytest.approx(
            by[("poly", 2, axis)]["fit_rms_float"], rel=0.05)
        assert by[("pwl", 2, axis)]["data_bytes"] == 2 * 2 + 10
        assert by[("poly", 3, axis)]["data_bytes"] == 1 + 4 * 4 + 12
    summary = pareto.summarise("chamber", curve, rows)
    assert summary["axes"]["x"]["four_point"]["mode"] == "nearest"
    assert summary["axes"]["x"]["cv_choice_poly"] == 2


def test_bench_script_writes_json_atomically(tmp_path):
    """The bench as a user runs it, from another directory with only the
    package importable: the table on stdout, the JSON written whole."""
    bench = str(ROOT / "bench" / "model_pareto.py")
    out = tmp_path / "p.json"
    run = subprocess.run([sys.executable, bench, "--datasets", "chamber", "--no-mcu",
                          "--orders", "1,2", "--knots", "3", "--json", str(out)], cwd=tmp_path, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    doc = json.loads(out.read_text())
    assert len(doc["rows"]) == 3 * 3 and doc["summary"][0]["dataset"] == "chamber"
    assert list(tmp_path.iterdir()) == [out]                        # no temporary left
    assert "chamber" in run.stdout
    refused = subprocess.run([sys.executable, bench, "--datasets", "chamber", "--no-mcu",
                              "--plot", str(tmp_path)], cwd=tmp_path, capture_output=True,
                             text=True)
    assert refused.returncode == 2 and "--plot needs the MCU cycles" in refused.stderr


def test_msp430_equals_host_on_the_real_curve():
    """Build both evaluations for the MSP430, run them in mspdebug and compare
    every output with the host C (run_dataset raises on a mismatch)."""
    require_tool("clang-14", "clang")
    require_tool("mspdebug")
    require_shared_data("mpu6000_gyro_offset_vs_temp/mpu6000_sn102_gyro_offset.csv")
    (curve, unit), = pareto.datasets(["mpu6000"], MPU_CSV).values()
    rows = pareto.run_dataset("mpu6000", curve, unit, mcu=True, log=lambda m: None,
                              poly_orders=(2,), pwl_knots=(9,))
    by = {(r["family"], r["axis"]): r for r in rows}
    for axis in curve.names:
        poly, pwl = by[("poly", axis)], by[("pwl", axis)]
        for r in (poly, pwl):
            assert r["cycles"] > 50 and r["text_bytes"] > 50
            assert r["energy_uj"] == pytest.approx(model_cost.energy_uj(r["cycles"]))
        # a table lookup is cheaper than an order-2 Horner pass
        assert pwl["cycles"] < poly["cycles"]
        # and on this curve the 9-knot table is far better than order 2
        assert pwl["cv_rms"] < 0.5 * poly["cv_rms"]


def test_pwl_table_cycles_do_not_grow_with_size():
    require_tool("clang-14", "clang")
    require_tool("mspdebug")
    temp = np.linspace(0.0, 50.0, 200)
    from pysig.tcomp._cross_validation import Curve
    curve = Curve(temp=temp, values=np.column_stack([np.sin(temp / 7.0) * 300 + k for k in range(3)]),
                  names=("a", "b", "c"))
    small = model_cost.mcu_pwl("test-pwl3", pareto.pwl_models(curve, 3), 3)
    big = model_cost.mcu_pwl("test-pwl100", pareto.pwl_models(curve, 100), 100)
    assert abs(np.mean(big["cycles"]) - np.mean(small["cycles"])) < 0.1 * np.mean(small["cycles"])
    assert big["text_bytes"] == small["text_bytes"]


def test_cheapest_within_tolerance():
    rows = [{"family": "poly", "size": 2, "cv_rms": 1.00, "cycles": 750, "data_bytes": 25},
            {"family": "pwl", "size": 9, "cv_rms": 1.04, "cycles": 450, "data_bytes": 28},
            {"family": "pwl", "size": 3, "cv_rms": 3.00, "cycles": 440, "data_bytes": 16}]
    assert pareto.cheapest_within(rows)["size"] == 9
    assert pareto.cheapest_within(rows, tolerance=0.01)["size"] == 2


def test_msp430_pwl_bit_exact_on_random_tables_all_branches():
    """Random int16 tables (rails included), every rescaling branch
    (value_frac < 4, = 4, > 4), temperatures outside the range (clamped and
    flagged) and on the last knot: the MSP430 gives the reference's bits and
    statuses."""
    require_tool("clang-14", "clang")
    require_tool("mspdebug")
    from pysig.tcomp._table_fit import plan_q16
    from spec import pwl as ref
    rng = np.random.default_rng(20261123)
    n = 11
    t_lo, t_hi = -1234, 5678
    recip = plan_q16(t_lo, t_hi, n)
    tables = rng.integers(-32768, 32768, size=(3, n))
    tables[0, :3] = [32767, -32768, 32767]
    vfs = [0, 4, 15]
    temps = np.concatenate([[-32768, t_lo - 1, t_lo, t_hi, t_hi + 1, 32767],
                            rng.integers(t_lo, t_hi + 1, size=model_cost.N_TEMPS - 6)]).astype(np.int16)
    arr = model_cost.c_array
    h = (f"#define N_AXES 3\n#define N_KNOTS {n}\n#define N_TEMPS {model_cost.N_TEMPS}\n"
         f"#define PWL_TABLES {{{', '.join(arr(t) for t in tables)}}}\n"
         f"#define PWL_RANGES {{{', '.join(arr([t_lo, t_hi]) for _ in range(3))}}}\n"
         f"#define PWL_RECIPS {{{', '.join(f'UINT32_C({recip})' for _ in range(3))}}}\n"
         f"#define PWL_VFS {arr(vfs)}\n#define TEMPS {arr(temps)}\n")
    m = model_cost.measure_case("test-pwl-random", "harness_pwl.c", [runner.c_source("sig_pwl")], h,
                           "sig_pwl_eval_q16")
    for a in range(3):
        expect = [ref.eval_q16([int(v) for v in tables[a]], t_lo, t_hi, recip, vfs[a], int(t))
                  for t in temps]
        assert [int(v) for v in m["out"][a]] == [e[0] for e in expect]
        assert [int(s) for s in m["status"][a]] == [e[1] for e in expect]
    assert list(m["status"][0][:6]) == [1, 1, 0, 0, 1, 1]


def test_msp430_pwl_float_within_tolerance():
    """The float form on the MSP430 (float32, compiler-rt soft float) against
    the reference in float64: within a few float32 ulps of the table's scale;
    clamping and NaN flagged the same."""
    require_tool("clang-14", "clang")
    require_tool("mspdebug")
    from spec import pwl as ref
    rng = np.random.default_rng(7)
    n = 13
    table = np.float32(rng.uniform(-500.0, 500.0, n))
    t_lo, t_hi = np.float32(-12.5), np.float32(61.25)
    inv_step = np.float32((n - 1) / (float(t_hi) - float(t_lo)))
    temps = np.float32(np.concatenate([[-100.0, t_lo, t_hi, 100.0, np.nan],
                                       rng.uniform(t_lo, t_hi, model_cost.N_TEMPS - 5)]))

    def lit(v):
        v = float(v)
        return "(0.0f/0.0f)" if np.isnan(v) else repr(v) + "f"

    d = model_cost.case_dir("test-pwl-float")
    (d / "pareto_case.h").write_text(
        f"#define N_KNOTS {n}\n#define N_TEMPS {model_cost.N_TEMPS}\n"
        f"#define TABLE_F {{{', '.join(lit(v) for v in table)}}}\n"
        f"#define TEMPS_F {{{', '.join(lit(v) for v in temps)}}}\n"
        f"#define T_LO_F {lit(t_lo)}\n#define T_HI_F {lit(t_hi)}\n#define INV_STEP_F {lit(inv_step)}\n")
    img = runner.build_msp430([runner.c_source("sig_pwl_f")], model_cost.HARNESS_DIR / "harness_pwl_f.c",
                              include_dirs=[d], hwmult=True, name="test-pwl-float")
    res = runner.measure(img, funcs=["sig_pwl_eval_f"], regions=["bench_start:bench_stop"],
                         reads={"out": 4 * model_cost.N_TEMPS, "status": 2 * model_cost.N_TEMPS,
                                "init_status": 2}, stack=False)
    assert res["reads"]["init_status"] == b"\0\0"
    out = np.frombuffer(res["reads"]["out"], "<f4")
    status = np.frombuffer(res["reads"]["status"], "<i2")
    scale = float(np.abs(table).max())
    for t, y, s in zip(temps, out, status):
        ry, rs = ref.eval_f([float(v) for v in table], float(t_lo), float(t_hi), float(inv_step),
                            float(t))
        assert s == rs
        if rs >= 0:
            assert abs(float(y) - ry) <= 8 * np.finfo(np.float32).eps * scale
    assert list(status[:5]) == [1, 0, 0, 1, -2]
    assert res["funcs"]["sig_pwl_eval_f"]["cycles"] > 0


def test_missing_real_curve_is_a_clear_error(tmp_path):
    with pytest.raises(InputFileError, match="absent.csv not found.*not bundled"):
        pareto.datasets(["mpu6000"], tmp_path / "absent.csv")
