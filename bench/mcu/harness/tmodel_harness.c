/* tmodel_harness.c - the firmware a user writes: the calibration image sits
 * in a const array (standing for flash), sig_tmodel_load_image reads it
 * whatever model family it holds, and sig_tmodel_apply compensates a batch
 * of readings at raw temperature codes; every output and status is stored
 * for the simulator script to read back.  Vectors: tmodel_vectors.h. */
#include <stdint.h>
#include "sig_tmodel.h"
#include "tmodel_vectors.h"

#include "bench_marks.h"

sig_status init_status;
uint8_t loaded_family;
sig_status vec_status[TM_N];
int16_t vec_out[TM_N][TM_AXES];
sig_tmodel model;
int16_t storage[TM_STORAGE];

#define VECTOR(i) sig_tmodel_apply(&model, tm_code[i], tm_in[i], vec_out[i])

int main(void)
{
    BENCH_CALL(init_status = sig_tmodel_load_image(&model, storage, TM_STORAGE, tm_image, TM_IMAGE_LEN));
    loaded_family = model.family;
    BENCH_VECTORS(TM_N, vec_status, VECTOR);
    return 0;
}
