#include <float.h>

#include "harness.h"

static long th_npass;
static long th_nfail;

void th_puts(const char *s)
{
    while (*s)
        th_putchar(*s++);
}

void th_newline(void) { th_putchar('\n'); }

void th_put_int(long v)
{
    char buf[24];
    int n = 0;
    unsigned long u = v < 0 ? 0UL - (unsigned long)v : (unsigned long)v;
    if (v < 0)
        th_putchar('-');
    do {
        buf[n++] = (char)('0' + (int)(u % 10UL));
        u /= 10UL;
    } while (u != 0UL);
    while (n > 0)
        th_putchar(buf[--n]);
}

void th_put_ld(long double x, int sig)
{
    int e10 = 0, i;
    long double scale = 1.0L;
    if (x != x) {
        th_puts("nan");
        return;
    }
    if (x < 0.0L) {
        th_putchar('-');
        x = -x;
    }
    if (x > LDBL_MAX) {
        th_puts("inf");
        return;
    }
    if (sig < 1)
        sig = 1;
    if (sig > 9)
        sig = 9;
    if (x != 0.0L) {
        while (x >= 10.0L) {
            x /= 10.0L;
            e10++;
        }
        while (x < 1.0L) {
            x *= 10.0L;
            e10--;
        }
    }
    for (i = 1; i < sig; i++)
        scale *= 10.0L;
    {
        /* round to sig digits as an integer mantissa */
        unsigned long mant = (unsigned long)(x * scale + 0.5L);
        char buf[12];
        int n = 0;
        if ((long double)mant >= scale * 10.0L) {
            mant /= 10UL;
            e10++;
        }
        for (i = 0; i < sig; i++) {
            buf[n++] = (char)('0' + (int)(mant % 10UL));
            mant /= 10UL;
        }
        th_putchar(buf[--n]);
        if (n > 0)
            th_putchar('.');
        while (n > 0)
            th_putchar(buf[--n]);
    }
    th_putchar('e');
    th_put_int(e10);
}

void th_put_real(edmi_real x, int sig) { th_put_ld((long double)x, sig); }

void th_suite(const char *name)
{
    th_puts("== ");
    th_puts(name);
    th_newline();
}

static void th_where(const char *file, int line, const char *text)
{
    th_puts("FAIL ");
    th_puts(file);
    th_putchar(':');
    th_put_int(line);
    th_puts(": ");
    th_puts(text);
}

int th_check(int cond, const char *file, int line, const char *text)
{
    if (cond) {
        th_npass++;
        return 1;
    }
    th_nfail++;
    th_where(file, line, text);
    th_newline();
    return 0;
}

int th_check_near(edmi_real a, edmi_real b, edmi_real abs_tol, edmi_real rel_tol,
                  const char *file, int line, const char *text)
{
    edmi_real d = a - b, bb = b < EDMI_R(0.0) ? -b : b;
    edmi_real bound = abs_tol + rel_tol * bb;
    if (d < EDMI_R(0.0))
        d = -d;
    if (d <= bound) { /* false for NaN */
        th_npass++;
        return 1;
    }
    th_nfail++;
    th_where(file, line, text);
    th_puts(" (");
    th_put_real(a, 9);
    th_puts(" vs ");
    th_put_real(b, 9);
    th_puts(", |diff| ");
    th_put_real(d, 3);
    th_puts(" > ");
    th_put_real(bound, 3);
    th_puts(")");
    th_newline();
    return 0;
}

void th_note_real(const char *label, edmi_real v)
{
    th_puts("  ");
    th_puts(label);
    th_puts(" = ");
    th_put_real(v, 4);
    th_newline();
}

void th_note_int(const char *label, long v)
{
    th_puts("  ");
    th_puts(label);
    th_puts(" = ");
    th_put_int(v);
    th_newline();
}

int th_failed(void) { return (int)th_nfail; }

int th_has_scheme(edmi_scheme s)
{
    switch (s) {
    case EDMI_SCHEME_MP: return EDMI_WITH_MP;
    case EDMI_SCHEME_LG: return EDMI_WITH_LG;
    case EDMI_SCHEME_GE: return EDMI_WITH_GE;
    case EDMI_SCHEME_PM: return EDMI_WITH_PM;
    case EDMI_SCHEME_PT: return EDMI_WITH_PT;
    default: return 0;
    }
}

int th_has_pot(edmi_pot_kind k)
{
    switch (k) {
    case EDMI_POT_HARMONIC: return EDMI_WITH_HARMONIC;
    case EDMI_POT_QUARTIC: return EDMI_WITH_QUARTIC;
    case EDMI_POT_NEO_HOOKE: return EDMI_WITH_NEO_HOOKE;
    case EDMI_POT_LJ: return EDMI_WITH_LJ;
    case EDMI_POT_INVERSE: return EDMI_WITH_INVERSE;
    case EDMI_POT_USER: return EDMI_WITH_USER;
    case EDMI_POT_CONTACT:
    case EDMI_POT_TETHER: return EDMI_WITH_CONTACT;
    default: return 0;
    }
}

int th_has_params(const edmi_params *p)
{
    return th_has_scheme(p->scheme) &&
           (p->scheme != EDMI_SCHEME_LG || p->lg_form != EDMI_LG_QUOTIENT || EDMI_WITH_LG_QUOTIENT) &&
           (p->guard != EDMI_GUARD_ON || EDMI_WITH_GUARD);
}

int th_has_system(const edmi_system *sys)
{
    int j;
    if (!th_has_params(&sys->params) || (sys->has_field && !EDMI_WITH_FIELD) ||
        (sys->internal.n_forced > 0 && !EDMI_WITH_PORTS))
        return 0;
    for (j = 0; j < sys->n_links; j++) {
        const edmi_potential *pot = &sys->link[j].pot;
        if (!th_has_pot(pot->kind) ||
            (pot->kind == EDMI_POT_USER && !pot->dd && sys->params.scheme == EDMI_SCHEME_LG &&
             !EDMI_WITH_LG_QUOTIENT))
            return 0;
    }
    return 1;
}

static long th_nskip;

int th_skip(int have, const char *what)
{
    if (have)
        return 0;
    if (th_nskip < 20) {
        th_puts("  skip (compiled out): ");
        th_puts(what);
        th_newline();
    }
    th_nskip++;
    return 1;
}

int th_finish(void)
{
    if (th_nskip > 0) {
        th_put_int(th_nskip);
        th_puts(" cases skipped: they need what this build compiled out (EDMI_WITH_*)");
        th_newline();
    }
    th_put_int(th_npass);
    th_puts(" passed, ");
    th_put_int(th_nfail);
    th_puts(" failed");
    th_newline();
    return (int)th_nfail;
}
