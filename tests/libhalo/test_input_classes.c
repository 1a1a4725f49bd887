/* Classes of bad input that once passed silently or gave the wrong diagnostic
 * (issue 15): parameter values beyond their type's range, NUL bytes in modules,
 * UTF-8 byte-order marks, and the cap on the number of diagnostics. Each test
 * asserts on message ids and positions, never on wording. No GL; glslang is not
 * needed either. */
#define _DEFAULT_SOURCE /* mkstemps */
#include "check.h"

#include <limits.h>
#include <stdint.h>
#include <unistd.h>

static halo_library *library;
static halo_diagnostics *diags;

static halo_status add(const char *file, const char *source)
{
    halo_diagnostics_clear(diags);
    return halo_library_add(library, file, source, HALO_ADD_NEW, diags);
}


/* ---- Parameters beyond the range of their type ---- */

static int test_param_beyond_type_range(void)
{
    static const struct {
        const char *line; /* line 3 of the module */
        int column;       /* where the offending number starts */
        const char *value;
    } bad[] = {
        {"#pragma halo param k int default=3000000000 \"beyond INT_MAX\"\n", 34, "3000000000"},
        {"#pragma halo param k int default=-2147483649\n", 34, "-2147483649"},
        {"#pragma halo param k int default=1e300\n", 34, "1e+300"},
        {"#pragma halo param k int[2] default=[1, 4294967296]\n", 37, "4294967296"},
        {"#pragma halo param k int default=1 min=-1e10\n", 40, "-10000000000"},
        {"#pragma halo param k int default=1 max=2147483648\n", 40, "2147483648"},
        {"#pragma halo param k float default=1e39\n", 36, "1e+39"},
        {"#pragma halo param k float default=-1e39\n", 36, "-1e+39"},
        {"#pragma halo param k vec3 default=[0, 0, 3.5e38]\n", 35, "3.5e+38"},
        {"#pragma halo param k float default=1 max=1e300\n", 42, "1e+300"},
        {"#pragma halo param k channels default=[1, 1e40]\n", 39, "1e+40"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char source[512];
        snprintf(source, sizeof source,
                 "#pragma halo module beyond_range\n"
                 "#pragma halo hook sample\n"
                 "%s"
                 "void apply(inout halo_sample s) {}\n",
                 bad[i].line);
        if (add("user/range.glsl", source) != HALO_ERROR_INPUT) {
            check_print_diags(diags);
            CHECK_FAIL_AT("accepted: %s", bad[i].line);
        }
        const halo_diagnostic *g = check_find_diag(diags, HALO_MSG_PARAM_DEFAULT_INVALID, 3);
        if (!g) {
            check_print_diags(diags);
            CHECK_FAIL_AT("no PARAM_DEFAULT_INVALID at line 3 for: %s", bad[i].line);
        }
        CHECK_STR_EQ(g->file, "user/range.glsl");
        CHECK_INT_EQ(g->column, bad[i].column);
        CHECK_STR_CONTAINS(g->text, bad[i].value);
        CHECK_STR_CONTAINS(g->text, "range");
    }
    /* the extremes themselves are fine */
    CHECK_INT_EQ(add("user/extremes.glsl",
                     "#pragma halo module extremes\n"
                     "#pragma halo hook sample\n"
                     "#pragma halo param i int default=2147483647 min=-2147483648\n"
                     "#pragma halo param f float default=-3.4e38 max=3.4e38\n"
                     "void apply(inout halo_sample s) { s.value += float(i) + f; }\n"),
                 HALO_OK);
    CHECK_NO_ERRORS(diags);
    return 0;
}

/* Scene values for an int parameter without a range: beyond int they are an error. */
static int test_scene_value_beyond_type_range(void)
{
    SETUP(add("user/unbounded.glsl",
              "#pragma halo module unbounded\n"
              "#pragma halo hook sample\n"
              "#pragma halo param n int default=3\n"
              "#pragma halo param x float default=1\n"
              "void apply(inout halo_sample s) { s.value += float(n) * x; }\n") == HALO_OK);
    static const char *const scenes[] = {
        "{\"halo_scene\": 1, \"stages\": [{\"unbounded\": {\"n\": 1e12}}]}",
        "{\"halo_scene\": 1, \"stages\": [{\"unbounded\": {\"n\": -2147483649}}]}",
        "{\"halo_scene\": 1, \"stages\": [{\"unbounded\": {\"x\": 1e39}}]}",
    };
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
        halo_diagnostics_clear(diags);
        halo_scene *s = halo_scene_load("range.json", scenes[i], library, diags);
        if (s) {
            halo_scene_destroy(s);
            CHECK_FAIL_AT("accepted: %s", scenes[i]);
        }
        CHECK(halo_diagnostics_has(diags, HALO_MSG_SCENE_VALUE_ABOVE_MAX) ||
              halo_diagnostics_has(diags, HALO_MSG_SCENE_VALUE_BELOW_MIN));
    }
    halo_scene *s = halo_scene_create(library);
    SETUP(s);
    double big = 4294967296.0, fine = 2147483647.0;
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_scene_set(s, "unbounded", "n", &big, 1, 0, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_SCENE_VALUE_ABOVE_MAX);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_scene_set(s, "unbounded", "n", &fine, 1, 0, diags), HALO_OK);
    halo_scene_destroy(s);
    return 0;
}

/* ---- NUL bytes ---- */

/* Writes len bytes to a new temporary file; its path in path (PATH_MAX). */
static int write_temp(char *path, const char *suffix, const char *bytes, size_t len)
{
    snprintf(path, 4096, "%s/halo-test-XXXXXX%s", getenv("TMPDIR") && *getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp",
             suffix);
    int fd = mkstemps(path, (int)strlen(suffix));
    if (fd < 0)
        return 0;
    int ok = write(fd, bytes, len) == (ssize_t)len;
    close(fd);
    return ok;
}

/* A NUL byte in a module file is an input error at its line and column, not a
 * module silently cut short there. */
static int test_module_nul_byte(void)
{
    static const char text[] =
        "#pragma halo module cut_short\n"
        "#pragma halo hook sample\n"
        "void apply(inout halo_sample s) {}\n"
        "// after this: \0 #pragma halo param k float default=1\n";
    char path[4096];
    SETUP(write_temp(path, ".glsl", text, sizeof text - 1));
    halo_diagnostics_clear(diags);
    halo_status st = halo_library_add(library, path, NULL, HALO_ADD_NEW, diags);
    halo_status st2 = halo_library_add(library, path, NULL, HALO_ADD_REPLACE, diags);
    unlink(path);
    CHECK_INT_EQ(st, HALO_ERROR_INPUT);
    CHECK_INT_EQ(st2, HALO_ERROR_INPUT);
    CHECK(halo_library_find(library, "cut_short") == NULL);
    const halo_diagnostic *g = check_find_diag(diags, HALO_MSG_INPUT_NUL_BYTE, 4);
    if (!g) {
        check_print_diags(diags);
        CHECK_FAIL_AT("no INPUT_NUL_BYTE at line 4");
    }
    CHECK_STR_EQ(g->file, path);
    CHECK_INT_EQ(g->column, 16);
    CHECK_INT_EQ(g->severity, HALO_SEVERITY_ERROR);
    return 0;
}

/* ---- The cap on diagnostics ---- */

static int test_diagnostics_limit(void)
{
    halo_diagnostics *d = halo_diagnostics_create();
    SETUP(d);
    CHECK_INT_EQ(halo_diagnostics_describe(d).limit, HALO_DIAGNOSTICS_DEFAULT_LIMIT);
    /* a host with 1000 markers: 999 duplicates */
    size_t n = 1000;
    char *host = malloc(64 + n * 32);
    SETUP(host);
    strcpy(host, "#version 330 core\n");
    for (size_t i = 0; i < n; i++)
        strcat(host, "#pragma halo declarations\n");
    strcat(host, "out vec4 c;\nvoid main() { c = vec4(1.0); }\n");
    halo_scene *scene = halo_scene_create(library);
    SETUP(scene);
    size_t limits[] = {HALO_DIAGNOSTICS_DEFAULT_LIMIT, 7, 0};
    for (size_t k = 0; k < 3; k++) {
        halo_diagnostics_clear(d);
        if (k)
            halo_diagnostics_set_limit(d, limits[k]);
        CHECK_INT_EQ(halo_diagnostics_describe(d).limit, limits[k]);
        halo_program *p = halo_link(&(halo_link_desc){.library = library, .scene = scene, .host_source = host}, d);
        CHECK(p == NULL);
        size_t kept = limits[k] ? limits[k] : n - 1;
        CHECK_INT_EQ(halo_diagnostics_describe(d).count, kept);
        CHECK_INT_EQ(halo_diagnostics_describe(d).errors, n - 1); /* every error counted */
        CHECK_INT_EQ(halo_diagnostics_describe(d).dropped, n - 1 - kept);
        CHECK(halo_diagnostics_has(d, HALO_MSG_HOST_MARKER_DUPLICATE));
        char *text = NULL;
        size_t text_len = 0;
        FILE *out = open_memstream(&text, &text_len);
        SETUP(out);
        halo_diagnostics_print(d, out);
        fclose(out);
        char expected[64];
        snprintf(expected, sizeof expected, "\n%zu more errors not shown", n - 1 - kept);
        if (limits[k])
            CHECK_STR_CONTAINS(text, expected);
        else
            CHECK_STR_NOT_CONTAINS(text, "more errors not shown");
        free(text);
    }
    /* clearing forgets what was left out */
    halo_diagnostics_clear(d);
    CHECK_INT_EQ(halo_diagnostics_describe(d).errors, 0);
    CHECK_INT_EQ(halo_diagnostics_describe(d).dropped, 0);
    CHECK(!halo_diagnostics_has(d, HALO_MSG_HOST_MARKER_DUPLICATE));
    halo_scene_destroy(scene);
    free(host);
    halo_diagnostics_destroy(d);
    /* NULL is no list: nothing to do, nothing to crash */
    halo_diagnostics_set_limit(NULL, 3);
    CHECK_INT_EQ(halo_diagnostics_describe(NULL).dropped, 0);
    return 0;
}

int main(void)
{
    static const check_test tests[] = {CHECK_TEST(test_param_beyond_type_range),
                                       CHECK_TEST(test_scene_value_beyond_type_range), CHECK_TEST(test_module_nul_byte),
                                       CHECK_TEST(test_diagnostics_limit)};
    return check_main_with_library(&library, &diags, tests, sizeof tests / sizeof tests[0]);
}
