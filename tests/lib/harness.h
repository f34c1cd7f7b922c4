/* tests/lib/ is the one place for helpers shared across the tree: this harness (with host_io.c
 * and target_io.c), scenes.c/.h, passive.c/.h (the exact-H check) and bench_scenes.h. Its users:
 * the suites (tests/test_*.c), the standalone programs (tests/programs/), the benchmarks
 * (tests/bench/), the fuzzer (tests/fuzz/), the QEMU runner's self-test (port/smoke_test.c) and
 * edmi-sim's energy check (examples/sim/). They include these headers by bare name with
 * -Itests/lib on the compile line, never by a ../ path; tests/lib includes nothing from
 * examples/ or from other folders' private files.
 *
 * edmi test harness: CHECK / CHECK_NEAR with file:line reports, closing "N passed, N failed".
 * Every character goes through th_putchar(), which the platform file supplies (host_io.c on
 * the host, the semihosting glue on an emulated target), so the same test sources run both. */
#ifndef EDMI_TEST_HARNESS_H
#define EDMI_TEST_HARNESS_H

#include "edmi.h"

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

/* What this build carries (edmi.h, EDMI_WITH_*: the tests are compiled with the library's
 * options). In the default build every feature is in and nothing is skipped. */
int th_has_scheme(edmi_scheme s);
int th_has_pot(edmi_pot_kind k);
/* The scheme, for LG its form (the quotient form is EDMI_WITH_LG_QUOTIENT), and the guard
 * where it is asked for (EDMI_GUARD_ON needs EDMI_WITH_GUARD). */
int th_has_params(const edmi_params *p);
/* Everything a system uses: its parameters, its links' potentials, a field, force ports. */
int th_has_system(const edmi_system *sys);
/* 1 (and counted and named in the log) when a test needs what this build compiled out
 * (have == 0): the caller then skips that case. th_finish reports the count. */
int th_skip(int have, const char *what);
#define TH_NEEDS(have) \
    do { if (th_skip((have) ? 1 : 0, #have)) return; } while (0)

/* A line of context for the log: label = value. */
void th_note_real(const char *label, edmi_real v);
void th_note_int(const char *label, long v);

#endif
