/* learn_harness.c - the device learner as firmware runs it: a model image
 * in a const array (flash) is loaded and put in use; a batch of samples the
 * model misses and a warm-up batch it is right on, run a few times (temperature, raw
 * readings, the model's outputs, still gate) go through sig_learn_step; one
 * sig_learn_solve fits, validates and writes a new image (and arms the
 * CUSUM); the new image is put in use; a field-like batch it is right on
 * goes through sig_learn_step between the bench markers (the per-sample
 * cost with the staleness test running); a second solve validates a
 * candidate that is not better (no commit: the common solve).
 * Every status, the image and the report are stored for the simulator script
 * to read back.  Vectors: learn_vectors.h (lab.mcu.learn_cost). */
#include <stdint.h>
#include "sig_learn.h"
#include "learn_vectors.h"

#include "bench_marks.h"

#define LV_N (LV_LEARN_N + LV_WARM_REPEAT * LV_WARM_N + LV_FIELD_N)

/* around the second solve (the committed image in use: validation only) */
BENCH_MARKER(bench_solve2_start, 8)
BENCH_MARKER(bench_solve2_stop, 9)

sig_status init_status;
sig_status solve_status;
sig_status solve2_status;
uint8_t solve2_outcome;
sig_status vec_status[LV_N];
uint8_t out_image[SIG_LEARN_IMAGE_MAX], out_image2[SIG_LEARN_IMAGE_MAX];
uint16_t out_len, out_len2;
sig_learn_report report;
sig_learn_scratch work;   /* xdata on the 8051: the solve's scratch */
sig_learn learner;
sig_tmodel model, committed;
int16_t storage[LV_STORAGE];
int16_t committed_storage[LV_STORAGE];

int main(void)
{
    sig_learn_config cfg = LV_CONFIG;
    uint16_t i, k, at;
    init_status = sig_learn_init(&learner, &cfg);
    init_status |= sig_tmodel_load_image(&model, storage, LV_STORAGE, lv_image, LV_IMAGE_LEN);
    init_status |= sig_learn_use_model(&learner, &model);
    /* the batches written out in main (sdcc 4.2 --xstack miscompiled a
     * batch helper taking the tables as parameters: its calls learned
     * nothing) */
    for (i = 0u; i < LV_LEARN_N; i++)
        vec_status[i] = sig_learn_step(&learner, lv_learn_t[i], lv_learn_raw[i], lv_learn_resid[i],
                                       lv_learn_still[i] != 0u);
    for (k = 0u, at = LV_LEARN_N; k < LV_WARM_REPEAT; k++)
        for (i = 0u; i < LV_WARM_N; i++, at++)
            vec_status[at] = sig_learn_step(&learner, lv_warm_t[i], lv_warm_raw[i], lv_warm_resid[i],
                                            lv_warm_still[i] != 0u);
    solve_status = sig_learn_solve(&learner, &model, LV_SEQ, out_image, SIG_LEARN_IMAGE_MAX, &out_len, &report, &work);
    init_status |= sig_tmodel_load_image(&committed, committed_storage, LV_STORAGE, out_image, out_len);
    init_status |= sig_learn_use_model(&learner, &committed);
    bench_start();
    for (i = 0u; i < LV_FIELD_N; i++, at++)
        vec_status[at] = sig_learn_step(&learner, lv_field_t[i], lv_field_raw[i], lv_field_resid[i],
                                        lv_field_still[i] != 0u);
    bench_stop();
    bench_solve2_start();
    solve2_status = sig_learn_solve(&learner, &committed, LV_SEQ + 1u, out_image2, SIG_LEARN_IMAGE_MAX,
                                    &out_len2, &report, &work);
    bench_solve2_stop();
    solve2_outcome = report.outcome;
    bench_done();
    return 0;
}
