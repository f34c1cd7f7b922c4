/* memcpy, memmove, memset and memcmp for a -nostdlib build (RISC-V rv32imac here).
 * GCC requires a freestanding environment to provide these four even when the source never
 * calls them: it emits memcpy for large struct copies (edmi.c does; see `make cross`, which
 * lists each object's external references). A firmware with a C library does not need this
 * file. Byte loops are enough for edmi's use (a few struct copies per call). Compile with
 * -fno-builtin -fno-tree-loop-distribute-patterns, or GCC turns these loops back into calls
 * to themselves. */
#include <stddef.h>

void *memcpy(void *restrict dst, const void *restrict src, size_t n);
void *memmove(void *dst, const void *src, size_t n);
void *memset(void *dst, int c, size_t n);
int memcmp(const void *a, const void *b, size_t n);

void *memcpy(void *restrict dst, const void *restrict src, size_t n)
{
    unsigned char *d = dst;
    const unsigned char *s = src;
    while (n--)
        *d++ = *s++;
    return dst;
}

void *memmove(void *dst, const void *src, size_t n)
{
    unsigned char *d = dst;
    const unsigned char *s = src;
    if (d < s) {
        while (n--)
            *d++ = *s++;
    } else {
        while (n--)
            d[n] = s[n];
    }
    return dst;
}

void *memset(void *dst, int c, size_t n)
{
    unsigned char *d = dst;
    while (n--)
        *d++ = (unsigned char)c;
    return dst;
}

int memcmp(const void *a, const void *b, size_t n)
{
    const unsigned char *x = a, *y = b;
    for (; n > 0; n--, x++, y++)
        if (*x != *y)
            return *x < *y ? -1 : 1;
    return 0;
}
