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


WARM_N, WARM_REPEAT = 40, 8


def learn_case(seed=0, per_bin=5):
    """The batches of the harness, each (t, raw, resid, still), and the model
    image in use.  learn: samples over all 16 bins of 64 units whose offsets
    follow a curve the model in use (a 5-knot table fitted to another curve)
    misses, a few moving and out-of-grid ones: what makes the solve fit,
    validate and commit.  warm: 40 still samples the model is right on
    (residual = noise) in three bins, run WARM_REPEAT times (the 8051's
    flash holds no longer table): enough block pairs to arm the CUSUM at
    that solve.  The committed image is then put in use.  field: the
    measured per-sample batch, as a device sees it at one sample
    a minute: the temperature drifting slowly up through six bins (~2.5
    units a sample), one sample in ten moving, the committed model right,
    the CUSUM armed; a second solve after it validates a candidate that is
    not better than the committed model (no commit: the common solve)."""
    from pysig import tcomp
    from pysig.learn import DeviceLearner
    from pysig.tcomp._tmodel import TModel
    rng = np.random.default_rng(seed)
    temp = np.linspace(0.0, 10.23, 400)
    cols = {a: np.rint(20 * np.sin(temp / 3 + k)) for k, a in enumerate("xyz")}
    img = tcomp.image_bytes(tcomp.fit_model(temp, cols, spec="table:5").model, sequence=7)
    model = TModel.from_image(img)

    def resid_of(t, raw):
        return np.asarray(model.apply(t.astype(np.int64) & 0xFFFF, raw.astype(np.int16))[0], np.int16)

    def model_right(t):
        """raw readings whose residual under the model is noise"""
        corr, _ = model.apply(t.astype(np.int64) & 0xFFFF, np.zeros((t.size, 3), np.int16))
        return np.rint(-np.asarray(corr, float) + rng.normal(0, 1.5, (t.size, 3))).astype(np.int16)

    n = 16 * per_bin
    t = np.concatenate([np.repeat(np.arange(16) * 64, per_bin) + rng.integers(0, 64, n), [-5, 1100, 300]])
    raw = np.rint(30 * np.cos(t[:, None] / 200.0 + np.arange(3)) + rng.normal(0, 1, (t.size, 3))).astype(np.int16)
    still = np.ones(t.size, dtype=bool)
    still[rng.choice(n, 6, replace=False)] = False
    t = t.astype(np.int16)
    learn = (t, raw, resid_of(t, raw), still)
    tw = (600 + rng.integers(0, 192, WARM_N)).astype(np.int16)
    rw = model_right(tw)
    warm = (tw, rw, resid_of(tw, rw), np.ones(tw.size, dtype=bool))
    dev = DeviceLearner(CONFIG)
    dev.use_image(img)
    for t_, raw_, resid_, still_ in [learn] + [warm] * WARM_REPEAT:
        for i in range(t_.size):
            dev.step(int(t_[i]), raw_[i].tolist(), resid_[i].tolist(), bool(still_[i]))
    _, committed, _ = dev.solve()
    if committed is None:
        raise ValueError("the learner's cost case did not commit")
    model = TModel.from_image(committed)         # the field batch: the committed model in use
    tf = np.rint(200 + np.cumsum(rng.uniform(0.5, 4.5, 160))).astype(np.int16)
    rf = model_right(tf)
    sf = rng.random(tf.size) >= 0.1
    field = (tf, rf, resid_of(tf, rf), sf)
    return img, learn, warm, field


def host_run(img, learn, warm, field):
    """What the host C does with the same batches: the statuses of every
    step (learn, warm, field), the first solve's status and image, the
    second solve's (the committed image in use) status and report."""
    from pysig.learn import DeviceLearner
    dev = DeviceLearner(CONFIG)
    dev.use_image(img)

    def batch(b):
        t, raw, resid, still = b
        return [dev.step(int(t[i]), raw[i].tolist(), resid[i].tolist(), bool(still[i])) for i in range(t.size)]

    sts = batch(learn)
    for _ in range(WARM_REPEAT):
        sts += batch(warm)
    st, out, _ = dev.solve()
    dev.use_image(out)
    sts += batch(field)
    st2, _, rep2 = dev.solve()
    return np.array(sts, dtype=np.int16), st, out, st2, rep2


def _header(path, img, learn, warm, field):
    c = CONFIG
    rows = lambda a: ",\n".join("{" + ", ".join(str(int(v)) for v in r) + "}" for r in a)
    cfg = (f"{{ UINT32_C({c['period']}), {c['t_base']}, {c['min_count']}u, {c['sigma_floor']}u, {c['k_sigma']}u, "
           f"{c['h_sigma']}u, {c['bin_shift']}u, {c['n_bins']}u, {c['min_bins']}u, {c['margin_shift']}u, "
           f"{c['n_axes']}u, {c['code_kind']}u }}")
    text = f"""#define LV_WARM_REPEAT {WARM_REPEAT}u
#define LV_IMAGE_LEN {len(img)}u
#define LV_STORAGE {3 * 16}u
#define LV_SEQ UINT32_C({struct.unpack_from('<I', img, 8)[0]})
#define LV_CONFIG {cfg}
static const uint8_t lv_image[{len(img)}] = {{ {', '.join(str(b) for b in img)} }};
"""
    for name, (t, raw, resid, still) in (("learn", learn), ("warm", warm), ("field", field)):
        text += f"""#define LV_{name.upper()}_N {t.size}u
static const int16_t lv_{name}_t[{t.size}] = {{ {', '.join(str(int(v)) for v in t)} }};
static const int16_t lv_{name}_raw[{t.size}][3] = {{ {rows(raw)} }};
static const int16_t lv_{name}_resid[{t.size}][3] = {{ {rows(resid)} }};
static const uint8_t lv_{name}_still[{t.size}] = {{ {', '.join(str(int(v)) for v in still)} }};
"""
    path.write_text(text)


def learn_row(target: str) -> dict:
    """Cycles of the learner on `target` ("msp430" or "mcs51"), checked
    against the host C first (McuError when they differ)."""
    case = learn_case()
    img, learn, warm, field = case
    h_st, h_solve, h_img, h_solve2, h_rep2 = host_run(*case)
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
        n = h_st.size
        m = runner.measure(fw, funcs=["sig_learn_solve"],
                           regions=["bench_start:bench_stop", "bench_solve2_start:bench_solve2_stop"],
                           reads={"vec_status": 2 * n, "init_status": 2, "solve_status": 2,
                                  "out_len": 2, "out_image": len(h_img or b""), "solve2_status": 2,
                                  "solve2_outcome": 1}, stack=True)
    r = m["reads"]
    fw_st = np.frombuffer(r["vec_status"], "<i2")
    out_len = struct.unpack("<H", r["out_len"])[0]
    if (struct.unpack("<h", r["init_status"])[0] != 0 or not np.array_equal(fw_st, h_st)
            or struct.unpack("<h", r["solve_status"])[0] != h_solve or h_img is None
            or out_len != len(h_img) or bytes(r["out_image"]) != h_img
            or struct.unpack("<h", r["solve2_status"])[0] != h_solve2
            or r["solve2_outcome"][0] != h_rep2["outcome"]):
        raise runner.McuError(f"learner on {target} differs from the host C")
    steps = m["regions"]["bench_start:bench_stop"]
    solve = m["funcs"]["sig_learn_solve"]
    nf = field[0].size
    return {"target": target, "samples": int(nf), "step_cycles_mean": steps["cycles"] / nf,
            "solve_cycles": solve["cycles"], "solve_stack_bytes": solve.get("stack_bytes"),
            "validate_only_solve_cycles": m["regions"]["bench_solve2_start:bench_solve2_stop"]["cycles"],
            "validate_only_outcome": h_rep2["outcome"],
            "image_bytes": len(h_img), "checked_against_host": True}
