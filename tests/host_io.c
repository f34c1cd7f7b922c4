/* Host platform file for the test harness: characters go to stdout. */
#include <stdio.h>
#include "harness.h"

void th_putchar(int c) { putchar(c); }
