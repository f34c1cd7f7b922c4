/* edmi test harness: CHECK / CHECK_NEAR with file:line reports, closing "N passed, N failed".
 * Every character goes through th_putchar(), which the platform file supplies (host_io.c on
 * the host, the semihosting glue on an emulated target), so the same test sources run both. */
#ifndef EDMI_TEST_HARNESS_H
#define EDMI_TEST_HARNESS_H

#include "../edmi.h"

/* The one output hook. */
void th_putchar(int c);

void th_puts(const char *s);
void th_put_int(long v);
/* Scientific notation with `sig` (1 to 9) significant digits, computed in long double. */
void th_put_ld(long double x, int sig);
void th_put_real(edmi_real x, int sig);
void th_newline(void);

/* Start a named group of checks (printed). */
void th_suite(const char *name);
/* Record one check; returns cond. Prints a FAIL line with file:line and text when false. */
int th_check(int cond, const char *file, int line, const char *text);
/* |a - b| <= abs_tol + rel_tol * |b|; prints both values and the bound on failure. */
int th_check_near(edmi_real a, edmi_real b, edmi_real abs_tol, edmi_real rel_tol,
                  const char *file, int line, const char *text);
/* Print "N passed, N failed" and return the number failed. */
int th_finish(void);
int th_failed(void);

#define CHECK(cond) th_check((cond) ? 1 : 0, __FILE__, __LINE__, #cond)
#define CHECK_NEAR(a, b, abs_tol, rel_tol) \
    th_check_near((a), (b), (abs_tol), (rel_tol), __FILE__, __LINE__, #a " ~ " #b)
#define CHECK_STATUS(call, want) \
    th_check((call) == (want), __FILE__, __LINE__, #call " == " #want)

/* A line of context for the log: label = value. */
void th_note_real(const char *label, edmi_real v);
void th_note_int(const char *label, long v);

#endif
