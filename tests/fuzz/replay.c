/* Runs the fuzz harness (fuzz_api.c) over stored inputs without libFuzzer: `make test`
 * replays the seed corpus (every reproducer the fuzzer ever found is in it) in both
 * precisions under the sanitizers, so each stays a regression test on a machine without
 * clang; `make fuzz-cov` replays the corpora for coverage. Arguments: files or directories.
 * An input that breaks a promise aborts with the harness's message (the test run reports
 * the crash); otherwise the closing line is "N passed, 0 failed", one pass per input. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static uint8_t buf[1 << 20];
static int passed, failed;

static void replay_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    size_t n;
    if (!f) {
        fprintf(stderr, "replay: cannot open %s\n", path);
        failed++;
        return;
    }
    n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    LLVMFuzzerTestOneInput(buf, n);
    passed++;
}

int main(int argc, char **argv)
{
    int i;
    for (i = 1; i < argc; i++) {
        DIR *d = opendir(argv[i]);
        struct dirent *e;
        if (!d) {
            replay_file(argv[i]);
            continue;
        }
        while ((e = readdir(d)) != 0) {
            char path[4096];
            if (e->d_name[0] == '.')
                continue;
            snprintf(path, sizeof path, "%s/%s", argv[i], e->d_name);
            replay_file(path);
        }
        closedir(d);
    }
    printf("fuzz inputs replayed: %d\n", passed);
    printf("%d passed, %d failed\n", passed, failed);
    return failed != 0;
}
