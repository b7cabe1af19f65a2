/* node.c - load the calibration from flash (A/B slots), compensate readings,
 * weigh samples: the calls a firmware makes, in the order it makes them. */
#include <stdbool.h>

#include "calibration.h"
#include "node.h"
#include "sig_chain.h"
#include "sig_image.h"
#include "sig_tcomp16.h"

uint8_t node_slot = 0xFFu;
sig_status node_start_status = SIG_ERR_EMPTY;
int16_t node_comp_out[CAL_N_READINGS * CAL_N_AXES];
sig_status node_comp_status[CAL_N_READINGS];
int32_t node_weight_q7[CAL_N_SAMPLES];
uint8_t node_stable[CAL_N_SAMPLES];
sig_status node_weight_status[CAL_N_SAMPLES];

/* Static, not on the stack: the 8051 has 256 bytes of internal RAM. */
static sig_tcomp16_q model;
static sig_chain_q chain;
static sig_chain_params_q chain_params;

/* Boot: the newer valid slot wins; a slot left invalid by a power cut
 * while it was written is skipped, so the previous calibration stays. */
static sig_status load_calibration(void)
{
    sig_status st = sig_image_select_slot(cal_slot_a, sizeof cal_slot_a,
                                          cal_slot_b, sizeof cal_slot_b, &node_slot);
    if (st < 0)
        return st;
    if (node_slot == SIG_IMAGE_SLOT_A)
        return sig_tcomp16_load_image(&model, cal_slot_a, sizeof cal_slot_a);
    return sig_tcomp16_load_image(&model, cal_slot_b, sizeof cal_slot_b);
}

sig_status node_demo(void)
{
    uint16_t i;
    bool stable;

    node_start_status = load_calibration();
    if (node_start_status < 0)
        return node_start_status;
    /* the default chain: no sensor constant, the thresholds follow the
     * noise it measures on the samples */
    (void)sig_chain_params_auto_q(&chain_params);
    node_start_status = sig_chain_init_q(&chain, &chain_params);
    if (node_start_status < 0)
        return node_start_status;
    for (i = 0; i < CAL_N_READINGS; i++)
        node_comp_status[i] = sig_tcomp16_apply_q(&model, cal_temp_centi[i], cal_readings[i],
                                                  &node_comp_out[i * CAL_N_AXES]);
    for (i = 0; i < CAL_N_SAMPLES; i++) {
        node_weight_status[i] = sig_chain_step_q(&chain, cal_samples[i], &node_weight_q7[i], &stable);
        node_stable[i] = stable ? 1u : 0u;
    }
    return node_start_status;
}
