/* Target platform file for the test harness: characters go to the emulator's console through
 * Arm semihosting (port/cortex-m/semihost.c), a line at a time. The counterpart of
 * host_io.c; linked instead of it by `make test-target` (port/target.mk). */
#include "harness.h"
#include "cortex-m/semihost.h"

void th_putchar(int c) { tgt_putchar(c); }
