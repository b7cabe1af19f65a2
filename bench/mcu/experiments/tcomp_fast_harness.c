/* tcomp_fast_harness.c - the compensation harness with the experimental
 * tcomp_fast_apply_q in place of sig_tcomp_apply_q (fixed form only). */
#include "tcomp_fast.h"
#define sig_tcomp_apply_q tcomp_fast_apply_q
#include "../harness/tcomp_harness.c"
