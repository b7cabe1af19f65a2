"""The chain's C entry points on bad arguments: SIG_ERR_ARG (or
SIG_ERR_NONFINITE) and the caller's state left byte for byte as it was.
A small C program is compiled with gcc in both float forms and run."""
import subprocess

import pytest

from conftest import CSRC, require_tool

PROGRAM = r"""
#include <stdio.h>
#include <string.h>
#include "sig_chain.h"

static int failures = 0;
#define EXPECT(cond) do { if (!(cond)) { printf("FAIL line %d: %s\n", __LINE__, #cond); failures++; } } while (0)
/* call must return `code` and leave *obj unchanged */
#define UNCHANGED(obj, call, code) do { \
    memcpy(&snap, (obj), sizeof *(obj)); \
    EXPECT((call) == (code)); \
    EXPECT(memcmp(&snap, (obj), sizeof *(obj)) == 0); } while (0)

static union { sig_chain_f cf; sig_chain_q cq; } snap;

int main(void)
{
    sig_chain_params_f pf, bad;
    sig_chain_params_q pq, badq;
    sig_chain_f cf;
    sig_chain_q cq;
    sig_limit_f lf; sig_antipulse_f af; sig_kalman1_f kf; sig_stable_f sf;
    sig_limit_q lq; sig_antipulse_q aq; sig_kalman1_q kq; sig_stable_q sq;
    sig_real out; int32_t outq; bool stable;
    sig_real zero = SIG_REAL(0.0);
    sig_real nan = zero / zero, inf = SIG_REAL(1.0) / zero;

    EXPECT(sig_chain_params_paper_f(&pf) == SIG_OK);
    EXPECT(sig_chain_init_f(&cf, &pf) == SIG_OK);
    EXPECT(sig_chain_step_f(&cf, SIG_REAL(3.0), &out, &stable) >= 0);
    bad = pf; bad.window = 33;          UNCHANGED(&cf, sig_chain_init_f(&cf, &bad), SIG_ERR_ARG);
    bad = pf; bad.window = 2;           UNCHANGED(&cf, sig_chain_init_f(&cf, &bad), SIG_ERR_ARG);
    bad = pf; bad.r = SIG_REAL(-0.05);  UNCHANGED(&cf, sig_chain_init_f(&cf, &bad), SIG_ERR_ARG);
    bad = pf; bad.r = zero;             UNCHANGED(&cf, sig_chain_init_f(&cf, &bad), SIG_ERR_ARG);
    bad = pf; bad.q = nan;              UNCHANGED(&cf, sig_chain_init_f(&cf, &bad), SIG_ERR_ARG);
    bad = pf; bad.a0 = zero;            UNCHANGED(&cf, sig_chain_init_f(&cf, &bad), SIG_ERR_ARG);
    bad = pf; bad.a0 = inf;             UNCHANGED(&cf, sig_chain_init_f(&cf, &bad), SIG_ERR_ARG);
    bad = pf; bad.p0 = SIG_REAL(-1.0);  UNCHANGED(&cf, sig_chain_init_f(&cf, &bad), SIG_ERR_ARG);
    bad = pf; bad.stable_count = 0;     UNCHANGED(&cf, sig_chain_init_f(&cf, &bad), SIG_ERR_ARG);
    bad = pf; bad.motion_count = 0;     UNCHANGED(&cf, sig_chain_init_f(&cf, &bad), SIG_ERR_ARG);
    bad = pf; bad.zero_rate = nan;      UNCHANGED(&cf, sig_chain_init_f(&cf, &bad), SIG_ERR_ARG);
    UNCHANGED(&cf, sig_chain_init_f(&cf, NULL), SIG_ERR_ARG);
    UNCHANGED(&cf, sig_chain_step_f(&cf, SIG_REAL(1.0), NULL, &stable), SIG_ERR_ARG);
    UNCHANGED(&cf, sig_chain_step_f(&cf, SIG_REAL(1.0), &out, NULL), SIG_ERR_ARG);
    UNCHANGED(&cf, sig_chain_set_offset_f(&cf, nan), SIG_ERR_ARG);
    EXPECT(sig_chain_step_f(NULL, SIG_REAL(1.0), &out, &stable) == SIG_ERR_ARG);
    EXPECT(sig_chain_init_f(NULL, &pf) == SIG_ERR_ARG);
    /* a non-finite sample before any finite one changes nothing */
    EXPECT(sig_chain_reset_f(&cf) == SIG_OK);
    UNCHANGED(&cf, sig_chain_step_f(&cf, nan, &out, &stable), SIG_ERR_NONFINITE);
    UNCHANGED(&cf, sig_chain_step_f(&cf, -inf, &out, &stable), SIG_ERR_NONFINITE);
    /* after a finite one it is an impulse */
    EXPECT(sig_chain_step_f(&cf, SIG_REAL(2.0), &out, &stable) >= 0);
    EXPECT((sig_chain_step_f(&cf, nan, &out, &stable) & SIG_WARN_REJECTED) != 0 && out == out);

    pq.a0 = 1000; pq.window = 12; pq.q_q30 = 2147u; pq.p0_q16 = 13107200u; pq.x0_q7 = 0;
    pq.seed_first = true; pq.stable_step_q7 = 128; pq.stable_count = 1; pq.lockout_n = 3;
    pq.motion_band_q7 = 0; pq.motion_count = 1; pq.zero_band_q7 = 0; pq.zero_rate_q7 = 0;
    EXPECT(sig_chain_init_q(&cq, &pq) == SIG_OK);
    EXPECT(sig_chain_step_q(&cq, 5000, &outq, &stable) >= 0);
    badq = pq; badq.a0 = 0;                          UNCHANGED(&cq, sig_chain_init_q(&cq, &badq), SIG_ERR_ARG);
    badq = pq; badq.window = 40;                     UNCHANGED(&cq, sig_chain_init_q(&cq, &badq), SIG_ERR_ARG);
    badq = pq; badq.q_q30 = 1073741825u;             UNCHANGED(&cq, sig_chain_init_q(&cq, &badq), SIG_ERR_ARG);
    badq = pq; badq.p0_q16 = 1073741825u;            UNCHANGED(&cq, sig_chain_init_q(&cq, &badq), SIG_ERR_ARG);
    badq = pq; badq.stable_step_q7 = -1;             UNCHANGED(&cq, sig_chain_init_q(&cq, &badq), SIG_ERR_ARG);
    badq = pq; badq.motion_band_q7 = -1;             UNCHANGED(&cq, sig_chain_init_q(&cq, &badq), SIG_ERR_ARG);
    badq = pq; badq.zero_rate_q7 = -5;               UNCHANGED(&cq, sig_chain_init_q(&cq, &badq), SIG_ERR_ARG);
    UNCHANGED(&cq, sig_chain_step_q(&cq, 1, NULL, &stable), SIG_ERR_ARG);
    UNCHANGED(&cq, sig_chain_step_q(&cq, 1, &outq, NULL), SIG_ERR_ARG);

    /* the stages alone */
    EXPECT(sig_limit_init_f(&lf, SIG_REAL(1.0), 0) == SIG_OK);
    UNCHANGED(&lf, sig_limit_init_f(&lf, SIG_REAL(-1.0), 0), SIG_ERR_ARG);
    UNCHANGED(&lf, sig_limit_step_f(&lf, nan, &out), SIG_ERR_NONFINITE);
    EXPECT(sig_limit_init_q(&lq, 10, 0) == SIG_OK);
    UNCHANGED(&lq, sig_limit_init_q(&lq, 0, 0), SIG_ERR_ARG);
    EXPECT(sig_antipulse_init_f(&af, 12) == SIG_OK);
    UNCHANGED(&af, sig_antipulse_init_f(&af, 33), SIG_ERR_ARG);
    UNCHANGED(&af, sig_antipulse_step_f(&af, inf, &out), SIG_ERR_NONFINITE);
    EXPECT(sig_antipulse_init_q(&aq, 12) == SIG_OK);
    UNCHANGED(&aq, sig_antipulse_init_q(&aq, 2), SIG_ERR_ARG);
    EXPECT(sig_kalman1_init_f(&kf, SIG_REAL(1e-7), SIG_REAL(0.05), SIG_REAL(10.0), SIG_REAL(1.0), false) == SIG_OK);
    UNCHANGED(&kf, sig_kalman1_init_f(&kf, SIG_REAL(1e-7), SIG_REAL(-0.05), SIG_REAL(10.0), SIG_REAL(1.0), false), SIG_ERR_ARG);
    UNCHANGED(&kf, sig_kalman1_init_f(&kf, SIG_REAL(-1e-7), SIG_REAL(0.05), SIG_REAL(10.0), SIG_REAL(1.0), false), SIG_ERR_ARG);
    UNCHANGED(&kf, sig_kalman1_step_f(&kf, nan, &out), SIG_ERR_NONFINITE);
    EXPECT(sig_kalman1_init_q(&kq, 2147u, 13107200u, 128, false) == SIG_OK);
    UNCHANGED(&kq, sig_kalman1_init_q(&kq, 1073741825u, 13107200u, 128, false), SIG_ERR_ARG);
    EXPECT(sig_stable_init_f(&sf, SIG_REAL(0.01), 1) == SIG_OK);
    UNCHANGED(&sf, sig_stable_init_f(&sf, SIG_REAL(-0.01), 1), SIG_ERR_ARG);
    UNCHANGED(&sf, sig_stable_init_f(&sf, SIG_REAL(0.01), 0), SIG_ERR_ARG);
    EXPECT(sig_stable_init_q(&sq, 1, 1) == SIG_OK);
    UNCHANGED(&sq, sig_stable_init_q(&sq, -1, 1), SIG_ERR_ARG);

    printf("%d failures\n", failures);
    return failures != 0;
}
"""


@pytest.mark.parametrize("real", ["float", "double"])
def test_c_bad_arguments_leave_state_unchanged(tmp_path, real):
    gcc = require_tool("gcc")
    src = tmp_path / "chain_args.c"
    src.write_text(PROGRAM)
    exe = tmp_path / "chain_args"
    defs = ["-DSIG_REAL_DOUBLE"] if real == "double" else []
    sources = [str(CSRC / f"sig_{n}.c") for n in ("limit", "antipulse", "kalman1", "stable", "chain")]
    build = subprocess.run([gcc, "-std=c99", "-O1", "-Wall", "-fsanitize=undefined,address",
                            "-fno-sanitize-recover=all", *defs, "-I", str(CSRC), str(src), *sources,
                            "-o", str(exe)], capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    run = subprocess.run([str(exe)], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "0 failures" in run.stdout
