/* cycle_cal_harness.c - the cycle-counter calibration: a short instruction
 * sequence whose cycle count the MCU's user guide states (cal_seq, generated
 * by bench/lab/mcu/cycle_calibration.py from its table of instructions and
 * their documented cycles) is measured the way every bench row is:
 *
 * - from cal_seq's entry through its return (the direct call in main), and
 * - between the bench_start/bench_stop markers; the CAL_EMPTY build has the
 *   same markers with nothing between them, so the difference of the two
 *   regions is the call, the sequence and its return.
 *
 * cal_seq computes from cal_data into cal_result, which the runner reads
 * back: the sequence really ran as written. */
#include <stdint.h>

#include "bench_marks.h"

uint16_t cal_data[3] = { 0x1234u, 0x0101u, 0x2002u };
uint16_t cal_result[6];       /* words: the MSP430 stores words at even addresses */

void cal_seq(void);

int main(void)
{
    bench_start();
#ifndef CAL_EMPTY
    cal_seq();
#endif
    bench_stop();
#ifdef CAL_EMPTY
    cal_seq();
#endif
    bench_done();
    return 0;
}
