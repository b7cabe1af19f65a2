"""The chain's C entry points on bad arguments: SIG_ERR_ARG (or
SIG_ERR_NONFINITE) and the caller's state left byte for byte as it was; and
the batch entry points (sig_chain_batch.c) equal to the step loop byte for
byte in both float forms (the firmware's float too, which Python does not
reach).  Small C programs are compiled with gcc (ASan + UBSan) and run."""
import subprocess

import pytest

from conftest import CSRC_INCLUDE, require_tool
from lab.mcu.runner import csrc_sources

PROGRAM = r"""
#include <stdio.h>
#include <string.h>
#include "sig_chain_batch.h"

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
    pq.noise_auto = false;
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

    {   /* batch entry points: NULL pointers refused, nothing changed; n = 0 is a no-op */
        sig_real xs[2] = {SIG_REAL(1.0), SIG_REAL(2.0)}, os[2];
        int32_t xq2[2] = {1, 2}, oq2[2];
        uint8_t st2[2];
        UNCHANGED(&cf, sig_chain_process_f(NULL, xs, 2, os, st2), SIG_ERR_ARG);
        UNCHANGED(&cf, sig_chain_process_f(&cf, NULL, 2, os, st2), SIG_ERR_ARG);
        UNCHANGED(&cf, sig_chain_process_f(&cf, xs, 2, NULL, st2), SIG_ERR_ARG);
        UNCHANGED(&cf, sig_chain_process_f(&cf, xs, 2, os, NULL), SIG_ERR_ARG);
        UNCHANGED(&cf, sig_chain_process_f(&cf, NULL, 0, NULL, NULL), SIG_OK);
        UNCHANGED(&cq, sig_chain_process_q(&cq, NULL, 2, oq2, st2), SIG_ERR_ARG);
        UNCHANGED(&cq, sig_chain_process_q(&cq, xq2, 2, oq2, NULL), SIG_ERR_ARG);
        UNCHANGED(&cq, sig_chain_process_q(&cq, NULL, 0, NULL, NULL), SIG_OK);
    }

    printf("%d failures\n", failures);
    return failures != 0;
}
"""

BATCH = r"""
#include <stdio.h>
#include <string.h>
#include "sig_chain_batch.h"

#define N 6000
static uint32_t rng = 12345u;
static uint32_t next(void) { rng = rng * 1664525u + 1013904223u; return rng >> 8; }
static sig_real uniform(void) { return (sig_real)next() / (sig_real)16777216.0; }   /* [0, 1) */

static sig_real xs[N], o1[N], o2[N];
static int32_t xq[N], q1[N], q2[N];
static uint8_t s1[N], s2[N];

int main(void)
{
    sig_chain_params_f pf;
    sig_chain_params_q pq;
    sig_chain_f a, b;
    sig_chain_q qa, qb;
    size_t i, at;
    int failures = 0, round;
    for (round = 0; round < 40; round++) {
        sig_real level = SIG_REAL(5000.0), zero = SIG_REAL(0.0);
        (void)sig_chain_params_paper_f(&pf);
        pf.a0 = (sig_real)(50 + (int)(next() % 3000u));
        pf.window = (uint8_t)(3u + next() % 30u);
        pf.q = SIG_REAL(4.8); pf.r = SIG_REAL(4860.0); pf.p0 = SIG_REAL(4.8e7); pf.x0 = SIG_REAL(0.0);
        pf.seed_first = (next() & 1u) != 0u;
        pf.stable_step = (sig_real)(next() % 20u);
        pf.stable_count = (uint8_t)(1u + next() % 5u);
        pf.lockout_n = (uint8_t)(next() % 6u);
        pf.motion_band = (next() & 1u) ? (sig_real)(next() % 200u) : SIG_REAL(0.0);
        pf.motion_count = (uint8_t)(1u + next() % 3u);
        pf.zero_band = (next() & 1u) ? SIG_REAL(300.0) : SIG_REAL(0.0);
        pf.zero_rate = SIG_REAL(1.5);
        pf.noise_auto = round % 5 == 4;            /* thresholds from the measured noise */
        for (i = 0; i < N; i++) {                  /* steps, noise, glitches, non-finite, huge */
            uint32_t r = next() % 1000u;
            if (r < 4u) level = (sig_real)(next() % 5u) * SIG_REAL(10000.0);
            xs[i] = level + (uniform() - SIG_REAL(0.5)) * SIG_REAL(240.0);
            if (r == 5u) xs[i] = SIG_REAL(-8387000.0);
            if (r == 6u && round % 4 == 1) xs[i] = SIG_REAL(1.0) / zero;          /* inf */
            if (r == 7u && round % 4 == 1) xs[i] = zero / zero;                   /* NaN */
            if (r == 8u && round % 4 == 2) xs[i] = SIG_REAL(1e37) * (sig_real)(next() % 30u);
            if (r == 9u && round % 4 == 3) xs[i] = SIG_REAL(-3e38);
            xq[i] = (int32_t)(level + (sig_real)(next() % 200u)) - (r == 5u ? 8387000 : 0);
        }
        if (round % 4 == 0) xs[0] = zero / zero;   /* non-finite before the first finite sample */
        memset(&a, 0, sizeof a); memset(&b, 0, sizeof b);
        if (sig_chain_init_f(&a, &pf) != SIG_OK || sig_chain_init_f(&b, &pf) != SIG_OK) { printf("init\n"); return 1; }
        for (i = 0; i < N; i++) {
            bool st;
            if (sig_chain_step_f(&a, xs[i], &o1[i], &st) < 0) { o1[i] = xs[i] - xs[i]; st = false; }
            s1[i] = (uint8_t)st;
        }
        for (at = 0; at < N; ) {                   /* the batch, split at random points */
            size_t len = 1u + next() % 1500u;
            if (len > N - at) len = N - at;
            (void)sig_chain_process_f(&b, xs + at, len, o2 + at, s2 + at);
            at += len;
        }
        for (i = 0; i < N; i++) {
            if (memcmp(&o1[i], &o2[i], sizeof o1[i]) != 0 && !(o1[i] != o1[i] && o2[i] != o2[i])) {
                printf("round %d float sample %u: %.9g != %.9g\n", round, (unsigned)i, (double)o1[i], (double)o2[i]);
                failures++;
                break;
            }
            if (s1[i] != s2[i]) { printf("round %d float stable %u\n", round, (unsigned)i); failures++; break; }
        }
        if (memcmp(&a, &b, sizeof a) != 0) { printf("round %d float state differs\n", round); failures++; }

        pq.a0 = (int32_t)pf.a0; pq.window = pf.window; pq.q_q30 = 1073742u; pq.p0_q16 = 655360000u;
        pq.x0_q7 = 0; pq.seed_first = pf.seed_first; pq.stable_step_q7 = (int32_t)pf.stable_step * 128;
        pq.stable_count = pf.stable_count; pq.lockout_n = pf.lockout_n;
        pq.motion_band_q7 = (int32_t)pf.motion_band * 128; pq.motion_count = pf.motion_count;
        pq.zero_band_q7 = (int32_t)pf.zero_band * 128; pq.zero_rate_q7 = 192;
        pq.noise_auto = pf.noise_auto;
        memset(&qa, 0, sizeof qa); memset(&qb, 0, sizeof qb);
        if (sig_chain_init_q(&qa, &pq) != SIG_OK || sig_chain_init_q(&qb, &pq) != SIG_OK) { printf("init q\n"); return 1; }
        for (i = 0; i < N; i++) {
            bool st;
            (void)sig_chain_step_q(&qa, xq[i], &q1[i], &st);
            s1[i] = (uint8_t)st;
        }
        for (at = 0; at < N; ) {
            size_t len = 1u + next() % 1500u;
            if (len > N - at) len = N - at;
            (void)sig_chain_process_q(&qb, xq + at, len, q2 + at, s2 + at);
            at += len;
        }
        if (memcmp(q1, q2, sizeof q1) != 0 || memcmp(s1, s2, sizeof s1) != 0 || memcmp(&qa, &qb, sizeof qa) != 0) {
            printf("round %d fixed differs\n", round);
            failures++;
        }
    }
    printf("%d failures\n", failures);
    return failures != 0;
}
"""


@pytest.mark.parametrize("real", ["float", "double"])
def test_c_bad_arguments_leave_state_unchanged(tmp_path, real):
    run_chain_program(tmp_path, "chain_args", PROGRAM, real, "-O1")


def run_chain_program(tmp_path, name, program, real, opt):
    """Build `program` with the chain's C under ASan+UBSan and run it: it
    prints '0 failures' when its checks pass."""
    gcc = require_tool("gcc")
    src = tmp_path / f"{name}.c"
    src.write_text(program)
    exe = tmp_path / name
    defs = ["-DSIG_REAL_DOUBLE"] if real == "double" else []
    sources = [str(f) for f in csrc_sources("sig_chain_batch")]    # the chain and every module it includes
    build = subprocess.run([gcc, "-std=c99", opt, "-Wall", "-fsanitize=undefined,address",
                            "-fno-sanitize-recover=all", *defs, "-I", str(CSRC_INCLUDE), str(src), *sources,
                            "-o", str(exe)], capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    run = subprocess.run([str(exe)], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "0 failures" in run.stdout


@pytest.mark.parametrize("real", ["float", "double"])
def test_c_batch_equals_step_loop_byte_for_byte(tmp_path, real):
    """sig_chain_process_f/_q split at random points == the step loop, outputs,
    flags and the whole state byte for byte, over 40 random parameter sets
    with steps, glitches, NaN/inf and samples near the float range (the fast
    path's bound is 1e36 in float: those samples take the step path)."""
    run_chain_program(tmp_path, "chain_batch", BATCH, real, "-O2")
