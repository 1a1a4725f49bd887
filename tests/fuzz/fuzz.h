/* The fuzz targets share one entry point, as libFuzzer defines it. Built two ways:
 * with driver.c into a plain program that make check runs (replays the corpus and a
 * fixed number of deterministic mutations of it), and by run-libfuzzer.sh with clang's
 * -fsanitize=fuzzer for real fuzzing in CI. */
#ifndef HALO_FUZZ_H
#define HALO_FUZZ_H
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The input as a NUL-terminated text (free() it), or NULL when memory runs out. */
static inline char *fuzz_text(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (text) {
        memcpy(text, data, size);
        text[size] = '\0';
    }
    return text;
}
#endif
