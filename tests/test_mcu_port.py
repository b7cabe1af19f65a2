"""The port layer (csrc/port/): target-specific forms of the core's hot
paths, each proven to compute exactly what the portable C computes.

- csrc/port/mcs51/sig_chain_mcs51.c, the fixed weighing chain for the 8051:
  the same C compiled for the host (lab.mcu.host_port) equals the
  portable chain (pysig.weigh.Chain(fixed=True)) on hypothesis-drawn
  parameters and signals, and built with sdcc it runs in s51 with the same
  outputs, stability flags and statuses on a 700-sample weighing run
  (load changes, impulses, a lock-out re-seed, a motion restart); the
  same for the default chain (`auto`: noise measured, ramps followed,
  stable only when backed), whose steady state the port runs in its own
  arithmetic, on hypothesis-drawn counts, Kalman settings and signals
  with pours and bumps fed in pieces.
- csrc/port/msp430/*.S, assembly on the 16x16 multiplier: every output and
  status in mspdebug's simulator equals the host C (sig_tcomp16_apply_q,
  sig_pwl_eval_q16 through Cython) on the bench's vectors and on others.
- every port file builds warning-free for its targets (and the C one for the
  host, strict C99)."""
import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from conftest import CSRC_INCLUDE, ROOT, require_tool

from pysig.errors import RangeError
from lab.mcu import pwl_vectors, runner, tcomp16_vectors, vectors
from lab.mcu.cost_tables import chain_mcs51_port_build
from lab.mcu.host_port import ChainMcs51, gain_table
from spec.chain import Chain as Spec, chain_fixed_params, chain_params
from pysig.weigh import Chain

PORT = ROOT / "csrc" / "port"
HARNESS = ROOT / "bench" / "mcu" / "harness"
CHAIN_PORT = PORT / "mcs51" / "sig_chain_mcs51.c"
ASM_DEFINES = {"MPY_BASE": runner.MSP430_MPY_BASE_SIM}


def _compile(cmd, tmp_path):
    import subprocess
    res = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, cwd=tmp_path)
    out = res.stdout + res.stderr
    assert res.returncode == 0 and "warning" not in out.lower(), " ".join(map(str, cmd)) + "\n" + out


# ------------------------------------------------------------ portability ---
# the default chain's build: the shared stage code of csrc/weigh, fixed-only
AUTO_FLAGS = ["-DSIG_CHAIN_MCS51_AUTO", "-DSIG_NO_FLOAT", "-I", ROOT / "csrc" / "weigh"]


@pytest.mark.parametrize("auto", [False, True], ids=["fixed", "auto"])
@pytest.mark.parametrize("src", sorted((PORT / "mcs51").glob("*.c")), ids=lambda p: p.name)
def test_mcs51_port_builds_warning_free(src, auto, tmp_path):
    gcc, sdcc = require_tool("gcc"), require_tool("sdcc")
    extra = AUTO_FLAGS if auto else []
    _compile([gcc, "-std=c99", "-Wall", "-Wextra", "-Wconversion", "-Wshadow", "-pedantic",
              "-Werror", "-O2", "-I", CSRC_INCLUDE, *extra, "-c", src, "-o", tmp_path / "x.o"], tmp_path)
    for model in (["--model-large"], ["--model-large", "--stack-auto", "--xstack"]) if auto else (["--model-large"],):
        _compile([sdcc, "-mmcs51", *model, "--std-c99", "-I", CSRC_INCLUDE, *extra, "-c", src,
                  "-o", str(tmp_path) + "/"], tmp_path)


@pytest.mark.parametrize("src", sorted((PORT / "msp430").glob("*.S")), ids=lambda p: p.name)
def test_msp430_port_builds_warning_free(src, tmp_path):
    clang = require_tool("clang-14", "clang")
    _compile([clang, "--target=msp430", "-Werror", "-c", src, "-o", tmp_path / "x.o"], tmp_path)
    # the headers' struct-layout checks hold for the offsets the assembly uses
    (tmp_path / "t.c").write_text('#include "sig_tcomp16_msp430.h"\n#include "sig_pwl_msp430.h"\n'
                                  'int port_headers_ok;\n')
    _compile([clang, "--target=msp430", "-std=c99", "-ffreestanding", "-Wall", "-Wextra",
              "-pedantic", "-Werror", "-I", CSRC_INCLUDE, "-I", PORT / "msp430", "-c",
              tmp_path / "t.c", "-o", tmp_path / "t.o"], tmp_path)


# ------------------------------------------------------ 8051 chain, host ---
def _portable(preset, upk, ov, x):
    out, stable, status = Chain(preset, fixed=True, units_per_kg=upk, **ov).process(
        x.astype(float), flags=True)
    return np.round(out * 128).astype(np.int64), stable, status


@st.composite
def chain_cases(draw):
    preset = draw(st.sampled_from(["recommended", "paper"]))
    upk = draw(st.sampled_from([100.0, 2204.6] + ([20000.0] if preset == "recommended" else [])))
    r = draw(st.sampled_from([1e-6, 1e-5, 1e-4, 1e-3]))
    ov = dict(window=draw(st.integers(3, 32)), R=r,
              Q=r * draw(st.sampled_from([1e-4, 1e-3, 1e-2, 0.1])),     # q = Q/R <= 1
              P0=r * draw(st.sampled_from([1.0, 100.0, 1e4])),          # P0/R <= 16384
              stable_count=draw(st.integers(1, 6)),
              lockout_n=draw(st.sampled_from([0, 1, 2, 3, 8])),
              motion_count=draw(st.integers(1, 4)))
    seed = draw(st.integers(0, 2**32 - 1))
    n = draw(st.integers(1, 600))
    noise = draw(st.sampled_from([0.0, 3.0, 70.0, 400.0]))
    offset = draw(st.sampled_from([0, 12345, -2**23, 2**24 - 500]))
    return preset, upk, ov, seed, n, noise, offset


def _signal(seed, n, noise, offset):
    """steps, ramps, impulses and noise around an offset code; some samples
    beyond the 25-bit clamp"""
    rng = np.random.default_rng(seed)
    steps = np.cumsum(rng.choice([0] * 12 + [1], n) * rng.normal(0, 30 * noise + 300, n))
    ramp = np.cumsum(rng.choice([0, 0, 0, 1], n) * rng.normal(0, noise + 1, n))
    x = offset + steps + ramp + rng.normal(0, noise, n)
    x += rng.choice([0] * 25 + [1], n) * rng.normal(0, 60 * noise + 2000, n)
    x[rng.random(n) < 0.005] = rng.choice([2**25, -2**25])
    return np.clip(np.round(x), -2**31, 2**31 - 1).astype(np.int64)


@settings(max_examples=80, deadline=None)
@given(chain_cases())
def test_chain_mcs51_equals_portable_chain(case):
    preset, upk, ov, seed, n, noise, offset = case
    try:
        fixed = chain_fixed_params(chain_params(preset, units_per_kg=upk, **ov))
        chain = ChainMcs51(fixed)
    except RangeError:
        assume(False)                   # outside the port's range: test_..._refuses covers it
    x = _signal(seed, n, noise, offset)
    out, stable, status = chain.process(x.astype(np.int32))
    h_out, h_stable, h_status = _portable(preset, upk, ov, x)
    np.testing.assert_array_equal(out, h_out)
    np.testing.assert_array_equal(stable, h_stable)
    np.testing.assert_array_equal(status, h_status)


# ------------------------------------------- the default chain on the port ---
@st.composite
def auto_cases(draw):
    """the default preset with its count and Kalman overrides, on signals
    with load changes, pours (ramps of several slopes), bumps, impulses and
    noise of any size, around any offset; split at random points"""
    ov = dict(window=draw(st.integers(3, 32)),
              Q=draw(st.sampled_from([1e-4, 1e-3, 1e-2, 0.1])),
              P0=draw(st.sampled_from([1.0, 10.0, 100.0])),
              stable_count=draw(st.integers(1, 6)),
              lockout_n=draw(st.sampled_from([0, 1, 2, 3, 8])),
              motion_count=draw(st.integers(1, 4)))
    seed = draw(st.integers(0, 2**32 - 1))
    n = draw(st.integers(1, 600))
    noise = draw(st.sampled_from([0.0, 0.4, 3.0, 70.0, 2000.0]))
    offset = draw(st.sampled_from([0, 12345, -2**23, 2**24 - 500]))
    cuts = sorted(draw(st.lists(st.integers(0, n), max_size=4)))
    return ov, seed, n, noise, offset, cuts


def _pours(seed, n, noise):
    """a ramp of tens of sigma per sample (a pour) in about one sample of
    eight, then the load stays; a bump: a short force, then the same load"""
    rng = np.random.default_rng(seed ^ 0x5EED)
    x = np.zeros(n)
    level, i = 0.0, 0
    while i < n:
        k = int(rng.integers(5, 60))
        if rng.random() < 0.5:
            slope = rng.choice([-1, 1]) * rng.uniform(3, 60) * (noise + 1)
            x[i:i + k] = level + slope * np.arange(1, min(k, n - i) + 1)
            level = x[min(i + k, n) - 1]
        else:
            x[i:i + k] = level
            if rng.random() < 0.3:
                x[i + k // 2:i + k // 2 + 2] += rng.uniform(20, 200) * (noise + 1)
        i += k
    return x[:n]


@settings(max_examples=60, deadline=None)
@given(auto_cases())
def test_chain_mcs51_default_chain_equals_portable_chain(case):
    """the port running the default chain (its steady state in the port's
    own arithmetic, every other step the portable chain) equals the portable
    fixed chain bit for bit: outputs, stable flags, statuses, with the
    samples fed in pieces"""
    ov, seed, n, noise, offset, cuts = case
    fixed = chain_fixed_params(chain_params("auto", **ov))
    x = _signal(seed, n, noise, offset) + np.round(_pours(seed, n, noise)).astype(np.int64)
    x = np.clip(x, -2**31, 2**31 - 1)
    chain = ChainMcs51(fixed)
    parts = [chain.process(p.astype(np.int32)) for p in np.split(x, cuts)]
    out, stable, status = (np.concatenate([p[i] for p in parts]) for i in range(3))
    h_out, h_stable, h_status = _portable("auto", None, ov, x)
    np.testing.assert_array_equal(out, h_out)
    np.testing.assert_array_equal(stable, h_stable)
    np.testing.assert_array_equal(status, h_status)


def test_chain_mcs51_default_chain_holds_the_block_after_a_large_change():
    """a removal of 15000 sigma with swing and creep: the first drift block
    after it counts as drifting (the spec's state shows where such a block
    ends; the port's steady step ends blocks on the shared verdict); port
    and portable chain agree bit for bit, stable before and after"""
    rng = np.random.default_rng(7)
    t = np.arange(250) / 10.0
    step = -15000.0 * 2.0
    x = np.full(400, 50000.0)
    x[150:] += step * (1.0 + 0.002 * (1.0 - np.exp(-t / 2.0))) + 0.3 * abs(step) * np.exp(-t / 0.5) * np.sin(3 * np.pi * t)
    x = np.round(x + rng.normal(0, 2.0, x.size)).astype(np.int64)
    chain = ChainMcs51(chain_fixed_params(chain_params("auto")))
    out, stable, status = chain.process(x.astype(np.int32))
    h_out, h_stable, h_status = _portable("auto", None, {}, x)
    np.testing.assert_array_equal(out, h_out)
    np.testing.assert_array_equal(stable, h_stable)
    np.testing.assert_array_equal(status, h_status)
    assert stable[:150].any() and stable[150:].any()
    spec, ends = Spec(fixed=True), []           # where a held block ends (the spec's state)
    for i, v in enumerate(x):
        held = spec.hold_block
        spec.step(float(v))
        if held and not spec.hold_block and spec.ap.count == spec.ap.n:
            ends.append(i)
    assert ends and all(chain.hot[i - 1] for i in ends)     # the port's fields were live there


def test_chain_mcs51_default_chain_runs_its_steady_state_on_the_port():
    """on a weighing run the port's own path takes most steps (the state
    stays in the port's fields between them), and the run has what the
    default chain's rules act on: rejections, restarts, stable samples"""
    case = vectors.chain_case(n=700, preset="auto")
    chain = ChainMcs51(case.fixed)
    out, stable, status = chain.process(case.x)
    assert chain.hot.mean() > 0.8
    assert (status & 4).any() and (status & 16).any() and stable.mean() > 0.5
    h_out, h_stable, h_status = _portable("auto", None, {}, case.x)
    np.testing.assert_array_equal(out, h_out)
    np.testing.assert_array_equal(stable, h_stable)
    np.testing.assert_array_equal(status, h_status)


def test_chain_mcs51_state_carries_across_calls():
    case = vectors.chain_case(n=500, seed=3)
    whole = ChainMcs51(case.fixed).process(case.x)
    c = ChainMcs51(case.fixed)
    parts = [c.process(p) for p in np.split(case.x, [1, 77, 300])]
    for a, b in zip(whole, (np.concatenate([p[i] for p in parts]) for i in range(3))):
        np.testing.assert_array_equal(a, b)


def test_chain_mcs51_refuses_what_it_cannot_hold():
    f = dict(vectors.chain_case().fixed)
    with pytest.raises(RangeError, match="8051"):
        ChainMcs51(dict(f, a0=9000))              # wider than the int16 window range allows
    with pytest.raises(RangeError, match="8051"):
        ChainMcs51(dict(f, window=2))
    # the default chain's start rule (it re-seeds on the window mean) as the
    # portable chain's
    with pytest.raises(RangeError, match="8051"):
        ChainMcs51(dict(vectors.chain_case(preset="auto").fixed, seed_first=False))
    with pytest.raises(RangeError, match="settle"):
        gain_table(f["q_q30"], f["p0_q16"], max_len=50)


def test_gain_table_replays_the_portable_kalman():
    """the table is the gain the portable fixed Kalman uses step by step
    after a (re)start, and its last entry is the value it then holds"""
    from pysig.weigh import Kalman1
    p = chain_params("recommended")
    f = chain_fixed_params(p)
    g = [int(v) for v in gain_table(f["q_q30"], f["p0_q16"])]
    kf = Kalman1(p["Q"], p["R"], 0.0, p["P0"], False, fixed=True)
    z = 1 << 20                                   # codes: a unit step seen through the filter
    fw = np.round(kf.process(np.full(len(g) + 20, float(z))) * 128).astype(np.int64)
    x, expect = 0, []
    for k in g + [g[-1]] * 20:                    # x += round-half-up(K (z - x)), Q30 gain
        x += ((z * 128 - x) * k + (1 << 29)) >> 30
        expect.append(x)
    np.testing.assert_array_equal(fw, expect)


# ------------------------------------------------------- 8051 chain, s51 ---
@pytest.mark.parametrize("preset", [vectors.CHAIN_PRESET, "auto"])
def test_chain_mcs51_in_s51_equals_portable_chain(preset, tmp_path):
    """the port built by sdcc, in s51, on a 700-sample weighing run: every
    output, flag and status as the portable chain's on the host; for the
    default chain the build of the bench (SIG_CHAIN_MCS51_AUTO, fixed-only,
    the portable chain beside the port)"""
    require_tool("sdcc")
    require_tool("s51")
    case = vectors.chain_case(n=700, preset=preset)
    gains = gain_table(case.fixed["q_q30"], case.fixed["p0_q16"])
    x_restart, n_pre = vectors.chain_restart_plan(case)
    img = chain_mcs51_port_build(case, gains, tmp_path, f"chain-mcs51-test-{preset}")
    n = len(case.x)
    res = runner.measure(img, reads={"vec_out": 4 * n, "vec_stable": n, "vec_status": 2 * n,
                                     "init_status": 2, "one_status": 2, "one_out": 4,
                                     "restart_status": 2, "restart_out": 4}, stack=False)
    assert not res["total"]["stack_overflow"]       # the internal RAM is nearly full
    r = res["reads"]
    seq = np.r_[case.x, case.one_x, np.full(n_pre + 1, x_restart)]
    h_out, h_stable, h_status = _portable(case.preset, None, {}, seq)
    assert np.frombuffer(r["init_status"], "<i2")[0] == 0
    np.testing.assert_array_equal(np.frombuffer(r["vec_out"], "<i4"), h_out[:n])
    np.testing.assert_array_equal(np.frombuffer(r["vec_stable"], np.uint8).astype(bool), h_stable[:n])
    np.testing.assert_array_equal(np.frombuffer(r["vec_status"], "<i2"), h_status[:n])
    assert np.frombuffer(r["one_out"], "<i4")[0] == h_out[n]
    assert np.frombuffer(r["restart_out"], "<i4")[0] == h_out[-1]
    assert np.frombuffer(r["restart_status"], "<i2")[0] == h_status[-1]
    assert h_status[-1] & 32                        # the measured restart step restarts
    st_ = np.frombuffer(r["vec_status"], "<i2")
    assert (st_ & 4).any() and (st_ & 16).any()     # the batch rejects impulses, re-seeds


# ------------------------------------------------------- MSP430 assembly ---
def _msp430_tools():
    require_tool("clang-14", "clang")
    require_tool("mspdebug")
    require_tool("ld.lld-14", "ld.lld")


@pytest.mark.parametrize("order,amplitude", [(1, 300.0), (2, 300.0), (2, 3000.0), (3, 300.0),
                                             (5, 300.0)])
def test_tcomp16_assembly_equals_host(order, amplitude, tmp_path):
    _msp430_tools()
    from pysig.tcomp._tcomp16 import Tcomp16Q
    case = tcomp16_vectors.tcomp16_case(order, amplitude=amplitude)
    tcomp16_vectors.write_tcomp16_header(case, tmp_path / "tcomp16_vectors.h")
    img = runner.build_msp430(
        runner.csrc_sources("sig_tcomp16") + [PORT / "msp430" / "sig_tcomp16_msp430.S"],
        HARNESS / "tcomp16_harness.c",
        dict(ASM_DEFINES, TC16_PORT_HEADER='"sig_tcomp16_msp430.h"',
             TC16_APPLY="sig_tcomp16_apply_msp430"),
        hwmult=True, include_dirs=[tmp_path, PORT / "msp430"])
    n, a = case.base.in_q.shape
    r = runner.measure(img, reads={"vec_out": 2 * n * a, "vec_status": 2 * n}, stack=False)["reads"]
    h_out, h_st = Tcomp16Q.from_compact(case.compact).apply(case.base.t_q, case.base.in_q)
    fw_st = np.frombuffer(r["vec_status"], "<i2")
    np.testing.assert_array_equal(np.frombuffer(r["vec_out"], "<i2").reshape(n, a), h_out)
    np.testing.assert_array_equal(fw_st, h_st)
    assert (fw_st & 1).any() and (fw_st & 2).any()   # clamped temperatures, saturated outputs


@pytest.mark.parametrize("entry,value_frac,spacing_shift", [
    ("sig_pwl_eval_msp430", (9, 4, 1), 8),
    ("sig_pwl_eval_msp430", (15, 0, 12), 6),
    ("sig_pwl_eval_axes_msp430", (4, 4, 4), 8),
    ("sig_pwl_eval_axes_msp430", (15, 0, 7), 6),
    ("sig_pwl_eval_axes_msp430", (5, 3, 12), 12),
])
def test_table_lookup_assembly_equals_host(entry, value_frac, spacing_shift, tmp_path):
    _msp430_tools()
    case = pwl_vectors.pwl_case(spacing_shift=spacing_shift, value_frac=value_frac, seed=spacing_shift)
    pwl_vectors.write_pwl_header(case, tmp_path / "pwl_vectors.h")
    axes = entry.endswith("_axes_msp430")
    macro = "PW_EVAL_AXES" if axes else "PW_EVAL"
    img = runner.build_msp430([runner.c_source("sig_pwl"), PORT / "msp430" / "sig_pwl_msp430.S"],
                              HARNESS / "pwl_harness.c",
                              dict(ASM_DEFINES, PW_PORT_HEADER='"sig_pwl_msp430.h"', **{macro: entry}),
                              hwmult=True, include_dirs=[tmp_path, PORT / "msp430"])
    n = len(case.temps)
    names = ("vec_out3", "vec_status3") if axes else ("vec_out", "vec_status")
    r = runner.measure(img, reads={names[0]: 12 * n, names[1]: (2 if axes else 6) * n},
                       stack=False)["reads"]
    h_out, h_st = pwl_vectors.host_eval(case)
    out = np.frombuffer(r[names[0]], "<i4")
    st_ = np.frombuffer(r[names[1]], "<i2")
    if axes:
        np.testing.assert_array_equal(out.reshape(n, 3).T, h_out)
        np.testing.assert_array_equal(st_, h_st[0])
    else:
        np.testing.assert_array_equal(out.reshape(3, n), h_out)
        np.testing.assert_array_equal(st_.reshape(3, n), h_st)
    assert (h_st == 1).any() and (h_st == 0).any()


def test_table_lookup_assembly_hands_other_tables_to_the_c(tmp_path):
    """a recip with a non-zero low word (knots not 2^16 / rh apart) runs
    the portable sig_pwl_eval_q16: same results"""
    _msp430_tools()
    case = pwl_vectors.pwl_case()
    case.recip += 12345                         # still a valid mapping for these knots
    pwl_vectors.write_pwl_header(case, tmp_path / "pwl_vectors.h")
    img = runner.build_msp430([runner.c_source("sig_pwl"), PORT / "msp430" / "sig_pwl_msp430.S"],
                              HARNESS / "pwl_harness.c",
                              dict(ASM_DEFINES, PW_PORT_HEADER='"sig_pwl_msp430.h"',
                                   PW_EVAL_AXES="sig_pwl_eval_axes_msp430"),
                              hwmult=True, include_dirs=[tmp_path, PORT / "msp430"])
    n = len(case.temps)
    r = runner.measure(img, reads={"vec_out3": 12 * n, "vec_status3": 2 * n}, stack=False)["reads"]
    h_out, h_st = pwl_vectors.host_eval(case)
    np.testing.assert_array_equal(np.frombuffer(r["vec_out3"], "<i4").reshape(n, 3).T, h_out)
    np.testing.assert_array_equal(np.frombuffer(r["vec_status3"], "<i2"), h_st[0])
