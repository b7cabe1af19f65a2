/* learn_harness.c - the device learner as firmware runs it: a model image
 * in a const array (flash) is loaded and put in use, a batch of samples
 * (temperature, raw readings, the model's outputs, still gate) goes through
 * sig_learn_step between the bench markers, then one sig_learn_solve fits,
 * validates and writes a new image.  Every status, the image and the
 * report are stored for the simulator script to read back.
 * Vectors: learn_vectors.h (pysig.mcu.learn_cost). */
#include <stdint.h>
#include "sig_learn.h"
#include "learn_vectors.h"

#include "bench_marks.h"

sig_status init_status;
sig_status solve_status;
sig_status vec_status[LV_N];
uint8_t out_image[SIG_LEARN_IMAGE_MAX];
uint16_t out_len;
sig_learn_report report;
sig_learn_scratch work;   /* xdata on the 8051: the solve's scratch */
sig_learn learner;
sig_tmodel model;
int16_t storage[LV_STORAGE];

int main(void)
{
    sig_learn_config cfg = LV_CONFIG;
    uint16_t i;
    init_status = sig_learn_init(&learner, &cfg);
    init_status |= sig_tmodel_load_image(&model, storage, LV_STORAGE, lv_image, LV_IMAGE_LEN);
    init_status |= sig_learn_use_model(&learner, &model);
    bench_start();
    for (i = 0; i < LV_N; i++)
        vec_status[i] = sig_learn_step(&learner, lv_t[i], lv_raw[i], lv_resid[i], lv_still[i] != 0u);
    bench_stop();
    solve_status = sig_learn_solve(&learner, &model, LV_SEQ, out_image, SIG_LEARN_IMAGE_MAX, &out_len, &report, &work);
    bench_done();
    return 0;
}
