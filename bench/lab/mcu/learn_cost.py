"""The device learner (csrc/learn) in the MCU simulators: a batch of
sig_learn_step calls and one full sig_learn_solve (16 covered bins, 3 axes,
a table model in use, a commit) on the MSP430F5510 and the 8051; the
statuses, the written image and its length read back must equal the host C
(through Cython) before any cycle count is returned."""
from __future__ import annotations

import struct
import tempfile
from pathlib import Path

import numpy as np

from lab.mcu import runner

HARNESS = runner.MCU_DIR / "harness" / "learn_harness.c"
SOURCES = runner.csrc_sources("sig_learn", "sig_learn_solve", "sig_tmodel", "sig_tmodel_image")
CONFIG = dict(period=1, t_base=0, min_count=4, sigma_floor=8, k_sigma=32, h_sigma=192, bin_shift=6,
              n_bins=16, min_bins=3, margin_shift=2, n_axes=3, code_kind=0)


def learn_case(seed=0, per_bin=5):
    """(config, model image, t, raw, resid, still): samples over all 16 bins
    of 64 units, offsets a curve the model in use (a 5-knot table fitted to
    another curve) misses, a few moving and out-of-grid samples."""
    from pysig import tcomp
    from pysig.learn import DeviceLearner
    rng = np.random.default_rng(seed)
    temp = np.linspace(0.0, 10.23, 400)
    cols = {a: np.rint(20 * np.sin(temp / 3 + k)) for k, a in enumerate("xyz")}
    img = tcomp.image_bytes(tcomp.fit_model(temp, cols, spec="table:5").model, sequence=7)
    n = 16 * per_bin
    t = np.concatenate([np.repeat(np.arange(16) * 64, per_bin) + rng.integers(0, 64, n), [-5, 1100, 300]])
    raw = np.rint(30 * np.cos(t[:, None] / 200.0 + np.arange(3)) + rng.normal(0, 1, (t.size, 3)))
    still = np.ones(t.size, dtype=bool)
    still[rng.choice(n, 6, replace=False)] = False
    dev = DeviceLearner(CONFIG)
    assert dev.use_image(img) == 0
    from pysig.tcomp._tmodel import TModel
    resid, _ = TModel.from_image(img).apply((t & 0xFFFF).astype(np.int64), raw.astype(np.int16))
    return img, t.astype(np.int16), raw.astype(np.int16), np.asarray(resid, np.int16), still


def host_run(img, t, raw, resid, still):
    """Statuses, solve status and image of the host C on the same inputs."""
    from pysig.learn import DeviceLearner
    dev = DeviceLearner(CONFIG)
    dev.use_image(img)
    sts = [dev.step(int(t[i]), raw[i].tolist(), resid[i].tolist(), bool(still[i])) for i in range(t.size)]
    st, out, _ = dev.solve()
    return np.array(sts, dtype=np.int16), st, out


def _header(path, img, t, raw, resid, still):
    c = CONFIG
    rows = lambda a: ",\n".join("{" + ", ".join(str(int(v)) for v in r) + "}" for r in a)
    cfg = (f"{{ UINT32_C({c['period']}), {c['t_base']}, {c['min_count']}u, {c['sigma_floor']}u, {c['k_sigma']}u, "
           f"{c['h_sigma']}u, {c['bin_shift']}u, {c['n_bins']}u, {c['min_bins']}u, {c['margin_shift']}u, "
           f"{c['n_axes']}u, {c['code_kind']}u }}")
    path.write_text(f"""#define LV_N {t.size}u
#define LV_IMAGE_LEN {len(img)}u
#define LV_STORAGE {3 * 16}u
#define LV_SEQ UINT32_C({struct.unpack_from('<I', img, 8)[0]})
#define LV_CONFIG {cfg}
static const uint8_t lv_image[{len(img)}] = {{ {', '.join(str(b) for b in img)} }};
static const int16_t lv_t[LV_N] = {{ {', '.join(str(int(v)) for v in t)} }};
static const int16_t lv_raw[LV_N][3] = {{ {rows(raw)} }};
static const int16_t lv_resid[LV_N][3] = {{ {rows(resid)} }};
static const uint8_t lv_still[LV_N] = {{ {', '.join(str(int(v)) for v in still)} }};
""")


def learn_row(target: str) -> dict:
    """Cycles of the learner on `target` ("msp430" or "mcs51"), checked
    against the host C first (McuError when they differ)."""
    case = learn_case()
    img, t, raw, resid, still = case
    h_st, h_solve, h_img = host_run(*case)
    with tempfile.TemporaryDirectory() as tmp:
        _header(Path(tmp) / "learn_vectors.h", *case)
        if target == "msp430":
            fw = runner.build_msp430(SOURCES, HARNESS, [], include_dirs=[tmp])
        else:
            # the firmware's memory model (examples/firmware/mcs51): with
            # --stack-auto alone the solve's call chain down to the table
            # evaluation (solve 46 B, model_at_points 26, model_q4 24,
            # sig_tmodel_apply 13, apply_tables 30, sig_pwl_eval_q16 ...)
            # runs the internal stack past 0xFF and the program restarts at 0;
            # --xstack moves the frames into the pdata page, so the internal
            # stack holds return addresses and saved registers only
            fw = runner.build_mcs51(SOURCES, HARNESS, ["SIG_NO_FLOAT"], include_dirs=[tmp],
                                    extra_flags=["--stack-auto", "--xstack"])
        n = t.size
        m = runner.measure(fw, funcs=["sig_learn_solve"], regions=["bench_start:bench_stop"],
                           reads={"vec_status": 2 * n, "init_status": 2, "solve_status": 2,
                                  "out_len": 2, "out_image": len(h_img or b"")}, stack=True)
    r = m["reads"]
    fw_st = np.frombuffer(r["vec_status"], "<i2")
    out_len = struct.unpack("<H", r["out_len"])[0]
    if (struct.unpack("<h", r["init_status"])[0] != 0 or not np.array_equal(fw_st, h_st)
            or struct.unpack("<h", r["solve_status"])[0] != h_solve or h_img is None
            or out_len != len(h_img) or bytes(r["out_image"]) != h_img):
        raise runner.McuError(f"learner on {target} differs from the host C")
    steps = m["regions"]["bench_start:bench_stop"]
    solve = m["funcs"]["sig_learn_solve"]
    return {"target": target, "samples": int(n), "step_cycles_mean": steps["cycles"] / n,
            "solve_cycles": solve["cycles"], "solve_stack_bytes": solve.get("stack_bytes"),
            "image_bytes": len(h_img), "checked_against_host": True}
