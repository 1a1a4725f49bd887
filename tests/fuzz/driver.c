/* A stand-in for libFuzzer's main, for make check: runs the target on every file of
 * the corpus directories given, then on a fixed number of deterministic mutations of
 * each (bit flips, truncations, duplicated and deleted spans, inserted tokens), so the
 * suite exercises the same code paths on every machine without a fuzzing engine.
 * Usage: fuzz_X [-n MUTATIONS] DIR... ; exit 0 unless the target crashes. */
#include "fuzz.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static unsigned long long rng_state = 0x2545F4914F6CDD1DULL;
static unsigned next_random(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (unsigned)(rng_state >> 11);
}

static const char *const tokens[] = {"#pragma halo ",
                                     "param ",
                                     "float",
                                     "vec3[4]",
                                     "channels",
                                     "default=",
                                     "[[",
                                     "]]",
                                     "{",
                                     "}",
                                     "\"",
                                     "\n",
                                     "NaN",
                                     "1e999",
                                     "-1",
                                     "module x\n",
                                     "hook sample\n",
                                     "\"stages\"",
                                     ":",
                                     ",",
                                     "halo_",
                                     "pass p entry=",
                                     "\\",
                                     "/*",
                                     "*/",
                                     "//",
                                     "(",
                                     ")",
                                     ";",
                                     "\0"};

static void mutate(unsigned char *buf, size_t *len, size_t cap)
{
    size_t n = *len;
    switch (next_random() % 5) {
    case 0: /* flip a bit */
        if (n)
            buf[next_random() % n] ^= (unsigned char)(1u << (next_random() % 8));
        break;
    case 1: /* truncate */
        if (n)
            *len = next_random() % n;
        break;
    case 2: { /* delete a span */
        if (n < 2)
            break;
        size_t at = next_random() % n, k = 1 + next_random() % (n - at);
        memmove(buf + at, buf + at + k, n - at - k);
        *len = n - k;
        break;
    }
    case 3: { /* duplicate a span */
        if (!n)
            break;
        size_t at = next_random() % n, k = 1 + next_random() % (n - at);
        if (n + k > cap)
            break;
        memmove(buf + at + k, buf + at, n - at);
        *len = n + k;
        break;
    }
    default: { /* insert a token */
        const char *t = tokens[next_random() % (sizeof tokens / sizeof tokens[0])];
        size_t k = strlen(t) ? strlen(t) : 1, at = n ? next_random() % (n + 1) : 0;
        if (n + k > cap)
            break;
        memmove(buf + at + k, buf + at, n - at);
        memcpy(buf + at, t, k);
        *len = n + k;
    }
    }
}

static int run_file(const char *path, int mutations)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return 0;
    size_t cap = 1 << 20;
    unsigned char *orig = malloc(cap), *buf = malloc(cap);
    if (!orig || !buf) {
        fclose(f);
        free(orig);
        free(buf);
        return 1;
    }
    size_t len = fread(orig, 1, cap / 2, f);
    fclose(f);
    LLVMFuzzerTestOneInput(orig, len);
    for (int i = 0; i < mutations; i++) {
        size_t n = len;
        memcpy(buf, orig, len);
        for (unsigned k = 0, rounds = 1 + next_random() % 4; k < rounds; k++)
            mutate(buf, &n, cap);
        LLVMFuzzerTestOneInput(buf, n);
    }
    free(orig);
    free(buf);
    return 1;
}

int main(int argc, char **argv)
{
    int mutations = 200, files = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "-n") && i + 1 < argc) {
            mutations = atoi(argv[++i]);
            continue;
        }
        DIR *d = opendir(argv[i]);
        if (!d) {
            files += run_file(argv[i], mutations);
            continue;
        }
        struct dirent *e;
        while ((e = readdir(d)) != NULL) {
            if (e->d_name[0] == '.')
                continue;
            char path[4096];
            snprintf(path, sizeof path, "%s/%s", argv[i], e->d_name);
            files += run_file(path, mutations);
        }
        closedir(d);
    }
    if (!files) {
        fprintf(stderr, "fuzz driver: no corpus files found\n");
        return 99;
    }
    printf("%d corpus files, %d mutations each: no crash\n", files, mutations);
    return 0;
}
