/* The tools' command lines (tool_options.h). */
#include "tool_options.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int halo_tool_args_next(halo_tool_args *a, const halo_tool_option *table)
{
    a->option = a->value = NULL;
    if (a->next >= a->argc)
        return HALO_TOOL_ARGS_END;
    const char *arg = a->argv[a->next++];
    a->option = arg;
    if (!strcmp(arg, "--help") || !strcmp(arg, "-h")) {
        if (a->usage)
            a->usage(stdout);
        return HALO_TOOL_ARGS_HELP;
    }
    for (int k = 0; table[k].name; ++k) {
        if (strcmp(arg, table[k].name) && !(table[k].alias && !strcmp(arg, table[k].alias)))
            continue;
        if (!table[k].valued)
            return k;
        if (a->next >= a->argc) {
            fprintf(stderr, "%s: error: %s needs a value\n", a->tool, arg);
            if (a->usage)
                a->usage(stderr);
            return HALO_TOOL_ARGS_ERROR;
        }
        a->value = a->argv[a->next++];
        return k;
    }
    fprintf(stderr, "%s: error: unknown argument '%s'\n", a->tool, arg);
    if (a->usage)
        a->usage(stderr);
    return HALO_TOOL_ARGS_ERROR;
}

/* Whether strto* read all of text (end at its end, no overflow, and ok); else one
 * message saying what it is not. */
static int read_whole(const char *tool, const char *option, const char *text, const char *end, int ok, const char *what)
{
    if (text && end != text && *end == '\0' && errno != ERANGE && ok)
        return 1;
    fprintf(stderr, "%s: error: %s: '%s' is not %s\n", tool, option, text ? text : "", what);
    return 0;
}

/* In a parser of x (its number type's printf FORMAT): stores x in *out and returns 1 when
 * it lies in lo..hi, else says so and returns 0. */
#define STORE_IN_RANGE(FORMAT)                                                                                         \
    do {                                                                                                               \
        if (x < lo || x > hi) {                                                                                        \
            fprintf(stderr, "%s: error: %s: " FORMAT " is outside " FORMAT ".." FORMAT "\n", tool, option, x, lo, hi); \
            return 0;                                                                                                  \
        }                                                                                                              \
        *out = x;                                                                                                      \
        return 1;                                                                                                      \
    } while (0)

int halo_tool_number(const char *tool, const char *option, const char *text, double lo, double hi, double *out)
{
    char *end = NULL;
    errno = 0;
    double x = text ? strtod(text, &end) : NAN;
    if (!read_whole(tool, option, text, end, isfinite(x), "a finite number"))
        return 0;
    STORE_IN_RANGE("%g");
}

int halo_tool_long(const char *tool, const char *option, const char *text, long lo, long hi, long *out)
{
    char *end = NULL;
    errno = 0;
    long x = text ? strtol(text, &end, 10) : 0;
    if (!read_whole(tool, option, text, end, 1, "an integer"))
        return 0;
    STORE_IN_RANGE("%ld");
}

int halo_tool_int(const char *tool, const char *option, const char *text, int lo, int hi, int *out)
{
    long x;
    if (!halo_tool_long(tool, option, text, lo, hi, &x))
        return 0;
    *out = (int)x;
    return 1;
}

int halo_tool_split(const char *tool, const char *option, const char *text, char separator, int count, char parts[][64])
{
    const char *p = text ? text : "";
    for (int k = 0; k < count; ++k) {
        const char *end = k + 1 < count ? strchr(p, separator) : p + strlen(p);
        if (!end || end == p || (size_t)(end - p) >= 64) {
            fprintf(stderr, "%s: error: %s: '%s' is not %d values separated by '%c'\n", tool, option, text ? text : "",
                    count, separator);
            return 0;
        }
        memcpy(parts[k], p, (size_t)(end - p));
        parts[k][end - p] = '\0';
        p = end + (k + 1 < count);
    }
    return 1;
}

int halo_tool_size(const char *tool, const char *option, const char *text, int max, int *width, int *height)
{
    char parts[2][64];
    return halo_tool_split(tool, option, text, 'x', 2, parts) && halo_tool_int(tool, option, parts[0], 1, max, width) &&
           halo_tool_int(tool, option, parts[1], 1, max, height);
}

int halo_tool_choice(const char *tool, const char *option, const char *text, const char *const *names, int *out)
{
    int count = 0;
    for (; names[count]; ++count)
        if (text && !strcmp(text, names[count])) {
            *out = count;
            return 1;
        }
    fprintf(stderr, "%s: error: %s: '%s' is not ", tool, option, text ? text : "");
    for (int k = 0; k < count; ++k)
        fprintf(stderr, "%s%s", k == 0 ? "" : k + 1 < count ? ", " : " or ", names[k]);
    fprintf(stderr, "\n");
    return 0;
}
