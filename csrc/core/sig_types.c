/* sig_types.c - the saturating helpers of sig_types.h as ordinary functions,
 * for sdcc only: one copy for the whole 8051 program instead of one per file
 * (see sig_types.h).  Host compilers and clang inline them from the header;
 * for them this file defines nothing. */
#define SIG_TYPES_DEFINE
#include "sig_types.h"
