/* sig_chain_mcs51_gains.c - the Kalman gain table of the 8051 chain
 * (sig_chain_mcs51.h), by the portable sig_kalman1: a separate module, so
 * that firmware which takes the table from its code memory links none of
 * the portable Kalman. */
#include "sig_chain_mcs51.h"

sig_status sig_chain_mcs51_gains(uint32_t q_q30, uint32_t p0_q16, uint32_t *table,
                                 uint16_t max, uint16_t *n)
{
    sig_kalman1_q kf;
    int32_t out;
    uint16_t i;
    if (table == NULL || n == NULL || sig_kalman1_init_q(&kf, q_q30, p0_q16, 0, false) != SIG_OK)
        return SIG_ERR_ARG;
    for (i = 0u; i < max; i++) {
        (void)sig_kalman1_step_q(&kf, 0, &out);
        table[i] = UINT32_C(1073741824) - kf.y;
        if (kf.phase == 3u) {            /* settled: the gain holds from here on */
            *n = (uint16_t)(i + 1u);
            return SIG_OK;
        }
    }
    return SIG_ERR_ARG;
}
