/* Tiny assertions for libhalo's unit tests.
 *
 * Each test is a function `static int test_NAME(void)` returning 0; a failed CHECK
 * prints both operands with file:line and returns 1 from that function. main runs
 * every test with RUN_TEST and returns check_exit_status(): 0 when all passed, 1 when
 * one failed (the automake harness reports FAIL), 99 after SETUP_FAIL (a broken
 * setup: the harness reports ERROR). Assertions on diagnostics compare message ids,
 * never wording. */
#ifndef HALO_TEST_CHECK_H
#define HALO_TEST_CHECK_H

#include "halo.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int check_failed_tests;

/* Prints the diagnostics collected so far (on a failure, to show what there was). */
static inline void check_print_diags(const halo_diagnostics *d)
{
    if (!d)
        return;
    size_t n = halo_diagnostics_describe(d).count;
    fprintf(stderr, "    %zu diagnostic%s:\n", n, n == 1 ? "" : "s");
    for (size_t i = 0; i < n; i++) {
        const halo_diagnostic *g = halo_diagnostics_get(d, i);
        fprintf(stderr, "    [%s] %s:%d:%d: %s\n", halo_message_name(g->id), g->file, g->line, g->column, g->text);
    }
}

/* The first diagnostic with this id (and this line, when line > 0), or NULL. */
static inline const halo_diagnostic *check_find_diag(const halo_diagnostics *d, halo_message_id id, int line)
{
    for (size_t i = 0; i < halo_diagnostics_describe(d).count; i++) {
        const halo_diagnostic *g = halo_diagnostics_get(d, i);
        if (g->id == id && (line <= 0 || g->line == line))
            return g;
    }
    return NULL;
}

/* Number of diagnostics with this id. */
static inline int check_count_diag(const halo_diagnostics *d, halo_message_id id)
{
    int n = 0;
    for (size_t i = 0; i < halo_diagnostics_describe(d).count; i++)
        n += halo_diagnostics_get(d, i)->id == id;
    return n;
}

#define CHECK_FAIL_AT(...)                              \
    do {                                                \
        fprintf(stderr, "%s:%d: ", __FILE__, __LINE__); \
        fprintf(stderr, __VA_ARGS__);                   \
        fputc('\n', stderr);                            \
        return 1;                                       \
    } while (0)

#define CHECK(cond)                                   \
    do {                                              \
        if (!(cond))                                  \
            CHECK_FAIL_AT("CHECK(%s) failed", #cond); \
    } while (0)

#define CHECK_INT_EQ(a, b)                                                                          \
    do {                                                                                            \
        long long check_a_ = (long long)(a), check_b_ = (long long)(b);                             \
        if (check_a_ != check_b_)                                                                   \
            CHECK_FAIL_AT("CHECK_INT_EQ(%s, %s) failed: %lld != %lld", #a, #b, check_a_, check_b_); \
    } while (0)

#define CHECK_INT_NE(a, b)                                                                 \
    do {                                                                                   \
        long long check_a_ = (long long)(a), check_b_ = (long long)(b);                    \
        if (check_a_ == check_b_)                                                          \
            CHECK_FAIL_AT("CHECK_INT_NE(%s, %s) failed: both are %lld", #a, #b, check_a_); \
    } while (0)

#define CHECK_STR_EQ(a, b)                                                                                         \
    do {                                                                                                           \
        const char *check_a_ = (a), *check_b_ = (b);                                                               \
        if (!check_a_ || !check_b_ || strcmp(check_a_, check_b_))                                                  \
            CHECK_FAIL_AT("CHECK_STR_EQ(%s, %s) failed: \"%s\" != \"%s\"", #a, #b, check_a_ ? check_a_ : "(null)", \
                          check_b_ ? check_b_ : "(null)");                                                         \
    } while (0)

#define CHECK_STR_CONTAINS(haystack, needle)                                                                 \
    do {                                                                                                     \
        const char *check_h_ = (haystack), *check_n_ = (needle);                                             \
        if (!check_h_ || !check_n_ || !strstr(check_h_, check_n_))                                           \
            CHECK_FAIL_AT("CHECK_STR_CONTAINS(%s, %s) failed: \"%s\" not found in:\n%s", #haystack, #needle, \
                          check_n_ ? check_n_ : "(null)", check_h_ ? check_h_ : "(null)");                   \
    } while (0)

#define CHECK_STR_NOT_CONTAINS(haystack, needle)                                                               \
    do {                                                                                                       \
        const char *check_h_ = (haystack), *check_n_ = (needle);                                               \
        const char *check_at_ = check_h_ && check_n_ ? strstr(check_h_, check_n_) : NULL;                      \
        if (!check_h_ || check_at_)                                                                            \
            CHECK_FAIL_AT("CHECK_STR_NOT_CONTAINS(%s, %s) failed: \"%s\" found at: %.80s", #haystack, #needle, \
                          check_n_ ? check_n_ : "(null)", check_at_ ? check_at_ : "(null haystack)");          \
    } while (0)

/* |a - b| <= tol, and neither is NaN. */
#define CHECK_NEAR(a, b, tol)                                                                                        \
    do {                                                                                                             \
        double check_a_ = (double)(a), check_b_ = (double)(b), check_t_ = (double)(tol);                             \
        if (!(fabs(check_a_ - check_b_) <= check_t_))                                                                \
            CHECK_FAIL_AT("CHECK_NEAR(%s, %s, %s) failed: %.17g vs %.17g (difference %.3g, tolerance %.3g)", #a, #b, \
                          #tol, check_a_, check_b_, fabs(check_a_ - check_b_), check_t_);                            \
    } while (0)

#define CHECK_FINITE(a)                                                 \
    do {                                                                \
        double check_a_ = (double)(a);                                  \
        if (!isfinite(check_a_))                                        \
            CHECK_FAIL_AT("CHECK_FINITE(%s) failed: %g", #a, check_a_); \
    } while (0)

/* The diagnostics hold one with this id. */
#define CHECK_DIAG(diags, ID)                                                                                     \
    do {                                                                                                          \
        const halo_diagnostics *check_d_ = (diags);                                                               \
        if (!halo_diagnostics_has(check_d_, ID)) {                                                                \
            fprintf(stderr, "%s:%d: CHECK_DIAG(%s, %s) failed: no such diagnostic\n", __FILE__, __LINE__, #diags, \
                    #ID);                                                                                         \
            check_print_diags(check_d_);                                                                          \
            return 1;                                                                                             \
        }                                                                                                         \
    } while (0)

/* The diagnostics hold one with this id at this line (of whatever file). */
#define CHECK_DIAG_LINE(diags, ID, LINE)                                                                              \
    do {                                                                                                              \
        const halo_diagnostics *check_d_ = (diags);                                                                   \
        if (!check_find_diag(check_d_, ID, (LINE))) {                                                                 \
            fprintf(stderr, "%s:%d: CHECK_DIAG_LINE(%s, %s, %d) failed: no such diagnostic at that line\n", __FILE__, \
                    __LINE__, #diags, #ID, (int)(LINE));                                                              \
            check_print_diags(check_d_);                                                                              \
            return 1;                                                                                                 \
        }                                                                                                             \
    } while (0)

/* No error was reported. */
#define CHECK_NO_ERRORS(diags)                                                                  \
    do {                                                                                        \
        const halo_diagnostics *check_d_ = (diags);                                             \
        if (halo_diagnostics_describe(check_d_).errors) {                                       \
            fprintf(stderr, "%s:%d: CHECK_NO_ERRORS(%s) failed\n", __FILE__, __LINE__, #diags); \
            check_print_diags(check_d_);                                                        \
            return 1;                                                                           \
        }                                                                                       \
    } while (0)

/* A broken setup (cannot create a library, out of memory): not a test failure. */
#define SETUP_FAIL(...)                                               \
    do {                                                              \
        fprintf(stderr, "%s:%d: broken setup: ", __FILE__, __LINE__); \
        fprintf(stderr, __VA_ARGS__);                                 \
        fputc('\n', stderr);                                          \
        exit(99);                                                     \
    } while (0)

#define SETUP(cond)                  \
    do {                             \
        if (!(cond))                 \
            SETUP_FAIL("%s", #cond); \
    } while (0)

/* A minimal fragment host of the contract: one sample through halo_apply. */
static const char check_sample_host[] =
    "#version 330 core\n"
    "#pragma halo declarations\n"
    "out vec4 fragment_color;\n"
    "void main()\n"
    "{\n"
    "    vec4 color = vec4(0.8, 0.6, 0.4, 0.5);\n"
    "#ifdef HALO_LINKED\n"
    "    halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.1, 0.2, 0.3), vec3(0.0, 0.0, 1.0), 0.5,\n"
    "                                     gl_FragCoord.xy, color.rgb, color.a);\n"
    "    halo_apply(s);\n"
    "    color = vec4(s.color, s.opacity);\n"
    "#endif\n"
    "    fragment_color = color;\n"
    "}\n";

/* A diagnostics list and the built-in library (a broken setup when they cannot be made). */
static inline halo_library *check_library_setup(halo_diagnostics **diags)
{
    *diags = halo_diagnostics_create();
    SETUP(*diags != NULL);
    halo_library *library = halo_library_create(*diags);
    if (!library) {
        check_print_diags(*diags);
        SETUP_FAIL("halo_library_create failed");
    }
    return library;
}

/* Runs one test: "ok   NAME" or "FAIL NAME" on stdout, the failure counted. */
static inline void check_run(const char *name, int (*test)(void))
{
    int check_r_ = test();
    printf("%s %s\n", check_r_ ? "FAIL" : "ok  ", name);
    fflush(stdout);
    if (check_r_)
        check_failed_tests++;
}

#define RUN_TEST(fn) check_run(#fn, fn)

/* A test of a table run by check_main_with_library. */
typedef struct check_test {
    const char *name;
    int (*run)(void);
} check_test;
#define CHECK_TEST(fn) \
    {                  \
#fn, fn        \
    }

static inline int check_exit_status(void)
{
    if (check_failed_tests)
        fprintf(stderr, "%d test%s failed\n", check_failed_tests, check_failed_tests == 1 ? "" : "s");
    return check_failed_tests ? 1 : 0;
}

/* The main of a test program over the built-in library: *library and *diags made
 * (check_library_setup), each test run in order as RUN_TEST runs it, both freed;
 * returns check_exit_status(). */
static inline int check_main_with_library(halo_library **library, halo_diagnostics **diags, const check_test *tests,
                                          size_t count)
{
    *library = check_library_setup(diags);
    for (size_t i = 0; i < count; i++)
        check_run(tests[i].name, tests[i].run);
    halo_library_destroy(*library);
    halo_diagnostics_destroy(*diags);
    return check_exit_status();
}

#endif
