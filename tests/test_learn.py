"""The device learner (csrc/learn/): C == the pure-Python spec bit for bit
over whole device loops (model applied, samples learned, solves, commits
loaded), also with the log split into calls at random points; what it
writes is an image the firmware's loader and `pysig apply` read; staleness
is flagged after an offset shift and a correct model is never replaced."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from pysig.learn import DeviceLearner, LearnConfig, replay
from pysig.learn._learn import OUTCOMES
from spec import learn as R
from spec import tmodel as RT
from pysig.status import Status, Warn
from pysig import tcomp


def _log(seed, n, n_axes, t_lo, t_hi, noise, shift_at=None, shift=0):
    """A field log: temperature swinging between t_lo and t_hi (int16 t),
    offsets a smooth curve of it plus noise, still about 2/3 of the time."""
    rng = np.random.default_rng(seed)
    phase = np.cumsum(rng.uniform(0.002, 0.02, n))
    t = np.rint(t_lo + (t_hi - t_lo) * (0.5 + 0.5 * np.sin(phase))).astype(np.int64)
    u = (t - t_lo) / max(1, t_hi - t_lo)
    curve = np.stack([40 * u - 25 * u ** 2 + 7 * a - 10 for a in range(n_axes)], 1)
    x = curve + rng.normal(0, noise, (n, n_axes))
    if shift_at is not None:
        x[shift_at:] += shift
    still = rng.random(n) < 0.66
    return t, np.clip(np.rint(x), -32768, 32767).astype(np.int64), still


configs = st.builds(
    dict, period=st.integers(1, 400), min_count=st.integers(1, 40), sigma_floor=st.integers(1, 40),
    k_sigma=st.integers(0, 64), h_sigma=st.integers(16, 300), min_bins=st.integers(3, 5),
    margin_shift=st.integers(1, 8), n_axes=st.integers(1, 3), code_kind=st.integers(0, 1))


def _run_c(cfg, t, x, still, start, solve_every, splits=()):
    dev = DeviceLearner(cfg)
    assert dev.status == 0
    if start is not None:
        assert dev.use_image(start) == 0
    codes = ((t + 32768) if cfg["code_kind"] else (t & 0xFFFF)).astype(np.uint16)
    bounds = [0, *sorted(splits), len(t)]
    parts = [dev.replay(codes[a:b], x[a:b].astype(np.int16), still[a:b], solve_every)
             for a, b in zip(bounds, bounds[1:])]
    comp = np.concatenate([p[0] for p in parts])
    status = np.concatenate([p[1] for p in parts])
    seq = np.concatenate([p[2] for p in parts])
    commits = [(i + a, rep, img) for (a, p) in zip(bounds, parts) for i, rep, img in p[3]]
    return comp, status, seq, commits


def _run_spec(cfg, t, x, still, start, solve_every):
    codes = (t + 32768) if cfg["code_kind"] else (t & 0xFFFF)
    dev = R.Device(cfg, start)
    return R.replay(dev, codes, x.tolist(), still, solve_every)


def _grid(t_lo, t_hi, cfg):
    return LearnConfig.for_range(t_lo, t_hi, n_axes=cfg["n_axes"]).as_dict() | {
        k: v for k, v in cfg.items() if k not in ("t_base", "bin_shift", "n_bins")}


@settings(max_examples=25, deadline=None)
@given(cfg=configs, seed=st.integers(0, 2 ** 32 - 1), t_lo=st.integers(-3000, 2000),
       span=st.integers(300, 8000), noise=st.sampled_from([0.3, 1.0, 4.0, 20.0]),
       solve_every=st.integers(1, 97), n=st.integers(50, 1500), with_start=st.booleans(),
       data=st.data())
def test_c_equals_spec_whole_loop_and_split(cfg, seed, t_lo, span, noise, solve_every, n, with_start, data):
    cfg = _grid(t_lo, t_lo + span, cfg)
    t, x, still = _log(seed, n, cfg["n_axes"], t_lo, t_lo + span, noise, shift_at=n // 2, shift=6 * noise)
    start = None
    if with_start:        # a model learned from an earlier log of the same device
        t0, x0, s0 = _log(seed + 1, 3000, cfg["n_axes"], t_lo, t_lo + span, noise)
        r0 = _run_c(dict(cfg, period=1), t0, x0, s0, None, 50)
        start = r0[3][-1][2] if r0[3] else None
    comp, status, seq, commits, _ = _run_spec(cfg, t, x, still, start, solve_every)
    splits = data.draw(st.lists(st.integers(1, n - 1), max_size=4, unique=True))
    for parts in ((), splits):
        c = _run_c(cfg, t, x, still, start, solve_every, parts)
        assert np.array_equal(c[0], np.array(comp, dtype=np.int16).reshape(c[0].shape))
        assert np.array_equal(c[1], np.array(status, dtype=np.int16))
        assert np.array_equal(c[2], np.array(seq, dtype=np.uint32))
        assert [(i, img) for i, _, img in c[3]] == [(i, img) for i, _, img in commits]
        assert [rep for _, rep, _ in c[3]] == [rep for _, rep, _ in commits]


def test_commit_is_an_image_the_loaders_and_apply_read():
    t, x, still = _log(3, 4000, 3, 1000, 4000, 2.0)
    r = replay(t, x, still, LearnConfig.for_range(1000, 4000, n_axes=3, period=500, min_count=20))
    assert r.commits and r.image is not None
    assert [c["sequence"] for c in r.commits] == list(range(1, len(r.commits) + 1))
    st_, model = RT.load(r.image)
    assert st_ == 0 and model[0] == "table"
    cols, clamped = tcomp.apply_image(r.image, t / 100.0, [x[:, a] for a in range(3)],
                                       tmodel_tempcode())
    # the model undoes the drift where it was learned: corrected still readings are near 0
    inside = ~clamped
    for a in range(3):
        assert abs(np.mean(cols[a][inside & still])) < 1.0


def tmodel_tempcode():
    return tcomp.CELSIUS


def test_stale_after_offset_shift_then_relearned():
    n, shift_at = 20000, 12000
    t, x, still = _log(5, n, 1, 0, 3000, 2.0, shift_at=shift_at, shift=12.0)
    cfg = LearnConfig.for_range(0, 3000, n_axes=1, period=600, min_count=20)
    r = replay(t, x, still, cfg)
    stale = np.flatnonzero(r.stale)
    assert r.commits and r.commits[0]["index"] < shift_at
    assert stale.size and not r.stale[:shift_at].any()
    assert stale[0] - shift_at < 200
    # a model learned after the shift replaces the stale one, and the flag clears
    later = [c for c in r.commits if c["index"] > stale[0]]
    assert later and not r.stale[later[0]["index"] + 1:].any()


def test_correct_model_is_never_replaced():
    t, x, still = _log(7, 30000, 2, -500, 2500, 1.5)
    cfg = LearnConfig.for_range(-500, 2500, n_axes=2, period=300, min_count=20)
    first = replay(t[:8000], x[:8000], still[:8000], cfg)
    assert first.image is not None
    r = replay(t[8000:], x[8000:], still[8000:], cfg, start_image=first.image)
    assert not r.stale.any()
    outcomes = {s["outcome"] for s in r.solves}
    assert "not-better" in outcomes
    for c in r.commits:               # anything committed beat the model in use by the margin
        assert c["sse_new"] <= c["sse_stored"] - (c["sse_stored"] >> cfg.margin_shift)


def test_bad_config_and_arguments_leave_state_unchanged():
    good = LearnConfig(n_axes=2).as_dict()
    for field, bad in (("n_axes", 0), ("n_axes", 4), ("n_bins", 2), ("n_bins", 25), ("n_bins", 33), ("bin_shift", 0),
                       ("bin_shift", 11), ("min_bins", 2), ("min_count", 0), ("margin_shift", 9),
                       ("h_sigma", 15), ("period", 0), ("code_kind", 2), ("t_base", 32000)):
        assert DeviceLearner(dict(good, **{field: bad})).status == Status.ERR_ARG, field
    dev, spec = DeviceLearner(good), R.Learner(good)
    t, x, still = _log(9, 3000, 2, 0, 3000, 1.0)
    for i in range(2000):
        spec.step(int(t[i]), x[i].tolist(), None, True)
        dev.step(int(t[i]), x[i].tolist(), None, True)
    img_st, img, rep = dev.solve()
    assert img_st == Warn.LEARN_COMMITTED and dev.use_image(img) == 0
    spec.solve(0)
    spec.use_model(RT.load(img)[1])
    # a model in use but no residual given: refused, nothing changes
    assert dev.step(100, [1, 2], None, True) == Status.ERR_ARG
    assert dev.use_image(img[:-1] + bytes([img[-1] ^ 1])) == Status.ERR_CRC
    for i in range(2000, 3000):
        y = RT.apply(spec.model, int(t[i]) & 0xFFFF, x[i].tolist())[0]
        assert dev.step(int(t[i]), x[i].tolist(), y, bool(still[i])) == \
            spec.step(int(t[i]), x[i].tolist(), y, bool(still[i]))
    spec.flush()        # counts() includes the pending samples
    assert dev.counts().tolist() == spec.count


def test_outcome_names_match_header():
    header = open("csrc/include/sig_learn.h").read()
    for value, name in enumerate(OUTCOMES):
        macro = {"commit": "COMMIT"}.get(name, name.upper().replace("-", "_"))
        assert f"#define SIG_LEARN_{macro}" in header and f"{value}u" in header


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), n_axes=st.integers(1, 3), gap=st.integers(2, 6),
       noise=st.sampled_from([0.5, 2.0, 8.0]))
def test_no_table_across_an_unseen_stretch(seed, n_axes, gap, noise):
    """Still samples only in two stretches of the grid, `gap` uncovered bins
    apart, each too short to make min_bins on its own: no solve commits (a
    table across the gap would be a line the held-out test cannot judge),
    and C == spec on it."""
    cfg = dict(LearnConfig.for_range(0, 16 * 256 - 1, n_axes=n_axes, min_count=10, min_bins=4,
                                     period=1).as_dict())
    w = 1 << cfg["bin_shift"]
    rng = np.random.default_rng(seed)
    lo = rng.integers(0, 3) * w
    hi = lo + (2 + gap + 1) * w           # bins b, b+1 then gap uncovered, then b+gap+2, b+gap+3
    n = 1200
    t = np.where(np.arange(n) % 2 == 0, rng.integers(lo, lo + 2 * w, n), rng.integers(hi, hi + 2 * w, n))
    t = np.clip(t, cfg["t_base"], cfg["t_base"] + (cfg["n_bins"] << cfg["bin_shift"]) - 1).astype(np.int64)
    x = np.clip(np.rint(np.stack([t / 50.0 + a for a in range(n_axes)], 1) + rng.normal(0, noise, (n, n_axes))),
                -2047, 2047).astype(np.int64)
    still = np.ones(n, bool)
    comp, status, seq, commits, solves = _run_spec(cfg, t, x, still, None, 50)
    assert commits == [] and all(rep["outcome"] == R.WAIT_COVERAGE for _, rep in solves)
    c = _run_c(cfg, t, x, still, None, 50)
    assert np.array_equal(c[1], np.array(status, dtype=np.int16)) and c[3] == []
