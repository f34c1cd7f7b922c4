/* Host platform file for the test harness: characters go to stdout. */
#include <stdio.h>
#include "harness.h"

/* Line-flushed, so a sanitizer abort does not swallow the lines before it. */
void th_putchar(int c)
{
    putchar(c);
    if (c == '\n')
        fflush(stdout);
}
