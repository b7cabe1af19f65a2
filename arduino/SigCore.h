/* SigCore.h - the C core for Arduino and PlatformIO sketches: every public
 * header of the library, with C linkage for C++ (a sketch is C++).
 * The functions and their Q formats are documented in each sig_*.h. */
#ifndef SIGCORE_H
#define SIGCORE_H

#ifdef __cplusplus
extern "C" {
#endif

#include "sig_status.h"
#include "sig_types.h"
#include "sig_chain.h"
#include "sig_chain_defaults.h"
#include "sig_image.h"
#include "sig_tmodel.h"
#include "sig_tcomp16.h"
#include "sig_crc16.h"

#ifdef __cplusplus
}
#endif

#endif
