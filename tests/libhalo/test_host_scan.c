/* Hosts that used to link silently wrong (issue 13, "no silent failures"): each gets a
 * diagnostic at the host's own file:line. The marker commented out or in a branch not
 * taken, no halo_apply or halo_finish that a compiler sees, #line, host macros that
 * rewrite the declarations, outputs without a location. No GL. */
#include "check.h"
#include "internal.h"

static halo_library *library;
static halo_diagnostics *diags;

static const char sample_scene[] = "{\"stages\": [\"boundary\"]}";
static const char seed_scene[] = "{\"stages\": [\"halo_seed\", \"halo_generate\", \"halo_map\"]}";

/* Links host (file "test.frag") with the scene (NULL: none) for the target. */
static halo_program *link_host(const char *scene_json, const char *host, halo_target target)
{
    halo_diagnostics_clear(diags);
    halo_scene *scene = NULL;
    if (scene_json && !(scene = halo_scene_load("test.json", scene_json, library, diags))) {
        check_print_diags(diags);
        SETUP_FAIL("scene rejected: %s", scene_json);
    }
    halo_diagnostics_clear(diags);
    halo_program *p = halo_link(
        &(halo_link_desc){
            .library = library, .scene = scene, .host_source = host, .host_file = "test.frag", .target = target},
        diags);
    halo_scene_destroy(scene);
    return p;
}

/* The link fails with id at file:line (and column, when not 0). */
static int expect_error_at(const char *file, const char *scene_json, const char *host, halo_target target,
                           halo_message_id id, int line, int column)
{
    halo_program *p = link_host(scene_json, host, target);
    if (p) {
        halo_program_destroy(p);
        CHECK_FAIL_AT("host accepted for target %s:\n%s", halo_target_name(target), host);
    }
    const halo_diagnostic *g = check_find_diag(diags, id, line);
    if (!g) {
        check_print_diags(diags);
        CHECK_FAIL_AT("no %s at line %d for host:\n%s", halo_message_name(id), line, host);
    }
    CHECK_STR_EQ(g->file, file);
    if (column)
        CHECK_INT_EQ(g->column, column);
    CHECK(g->source_line != NULL);
    return 0;
}

static int expect_error(const char *scene_json, const char *host, halo_target target, halo_message_id id, int line,
                        int column)
{
    return expect_error_at("test.frag", scene_json, host, target, id, line, column);
}

/* The host links and validates for the target. */
static int expect_valid(const char *scene_json, const char *host, halo_target target)
{
    halo_program *p = link_host(scene_json, host, target);
    if (!p || halo_validate(&(halo_validate_desc){.program = p}, diags) != HALO_OK) {
        check_print_diags(diags);
        halo_program_destroy(p);
        CHECK_FAIL_AT("host rejected for target %s:\n%s", halo_target_name(target), host);
    }
    halo_program_destroy(p);
    return 0;
}

#define HOST_BODY                                                                                 \
    "out vec4 c;\n"                                                                               \
    "void main() {\n"                                                                             \
    "    vec4 color = vec4(0.5);\n"                                                               \
    "#ifdef HALO_LINKED\n"                                                                        \
    "    halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.1), vec3(0.0, 0.0, 1.0), 0.5,\n" \
    "                                     gl_FragCoord.xy, color.rgb, color.a);\n"                \
    "    halo_apply(s);\n"                                                                        \
    "    color = vec4(s.color, s.opacity);\n"                                                     \
    "#endif\n"                                                                                    \
    "    c = color;\n"                                                                            \
    "}\n"

/* (1) A marker in a comment is no marker: say so at its line, not "no marker". */
static int test_marker_commented(void)
{
    if (expect_error(sample_scene, "#version 330 core\n// #pragma halo declarations\n" HOST_BODY, HALO_TARGET_GLSL330,
                     HALO_MSG_HOST_MARKER_INACTIVE, 2, 0))
        return 1;
    CHECK_INT_EQ(check_count_diag(diags, HALO_MSG_HOST_MARKER_MISSING), 0);
    if (expect_error(sample_scene, "#version 330 core\n/* #pragma halo declarations */\n" HOST_BODY,
                     HALO_TARGET_GLSL330, HALO_MSG_HOST_MARKER_INACTIVE, 2, 0))
        return 1;
    /* Inside a block comment the line itself looks like a marker. */
    if (expect_error(sample_scene, "#version 330 core\n/*\n#pragma halo declarations\n*/\n" HOST_BODY,
                     HALO_TARGET_GLSL330, HALO_MSG_HOST_MARKER_INACTIVE, 3, 0))
        return 1;
    /* A comment that mentions the marker beside a real one is fine. */
    return expect_valid(sample_scene,
                        "#version 330 core\n// #pragma halo declarations\n#pragma halo declarations\n" HOST_BODY,
                        HALO_TARGET_GLSL330);
}

/* (1) A marker in a branch not taken under the target's predefined macros and the
 * host's own: #if 0, #ifdef, #if defined(), #elif, #else, __VERSION__, GL_ES. */
static int test_marker_dead_branch(void)
{
    static const char *const dead[] = {
        "#if 0\n#pragma halo declarations\n#endif\n",
        "#ifdef GL_ES\n#pragma halo declarations\n#endif\n",
        "#if defined(GL_ES) || __VERSION__ >= 450\n#pragma halo declarations\n#endif\n",
        "#ifndef GL_core_profile\n#pragma halo declarations\n#endif\n",
        "#define USE_HALOS 0\n#if USE_HALOS\n#pragma halo declarations\n#endif\n",
        "#define LEVEL 2\n#if defined(LEVEL) && LEVEL > 2\n#pragma halo declarations\n#endif\n",
        "#define FLAG\n#undef FLAG\n#ifdef FLAG\n#pragma halo declarations\n#endif\n",
        "#if 1\n#elif 1\n#pragma halo declarations\n#endif\n",
        "#if !(1 + 1 == 2)\n#else\n#if 0\n#else\n#endif\n#if (3 <= 2) || !defined GL_core_profile\n"
        "#pragma halo declarations\n#endif\n#endif\n",
        "#ifdef HALO_LINKED\n#pragma halo declarations\n#endif\n",
    };
    for (size_t i = 0; i < sizeof dead / sizeof dead[0]; i++) {
        char host[1024];
        snprintf(host, sizeof host, "#version 330 core\n%s" HOST_BODY, dead[i]);
        int marker = 0, line = 1;
        for (const char *c = host; *c && !marker; c++) {
            if (!strncmp(c, "#pragma", 7))
                marker = line;
            line += *c == '\n';
        }
        if (expect_error(sample_scene, host, HALO_TARGET_GLSL330, HALO_MSG_HOST_MARKER_INACTIVE, marker, 1))
            return 1;
        CHECK_INT_EQ(check_count_diag(diags, HALO_MSG_HOST_MARKER_MISSING), 0);
    }
    /* The same branches taken for another target, or with the host's macros. */
    if (expect_valid(sample_scene, "#version 300 es\n#ifdef GL_ES\n#pragma halo declarations\n#endif\n" HOST_BODY,
                     HALO_TARGET_ES300) ||
        expect_valid(sample_scene,
                     "#version 450 core\n#if __VERSION__ >= 450\n#pragma halo declarations\n#endif\n" HOST_BODY,
                     HALO_TARGET_GLSL450) ||
        expect_valid(sample_scene,
                     "#define LEVEL 3\n#if defined(LEVEL) && LEVEL > 2\n#pragma halo declarations\n#endif\n" HOST_BODY,
                     HALO_TARGET_GLSL330) ||
        expect_valid(sample_scene,
                     "#if 0\n#elif 2 * 3 == 6 && 7 % 4 == 3\n#pragma halo declarations\n#endif\n" HOST_BODY,
                     HALO_TARGET_GLSL330))
        return 1;
    /* What the evaluator cannot decide counts as taken: the link goes on (glslang may
     * then reject the condition itself). */
    static const char *const unknown[] = {"#if SET_BY_THE_APPLICATION > 1\n", "#if 1.5 > 1\n", "#if 1 / 0\n",
                                          "#if defined(\n", "#define F(x) x\n#if F(0)\n"};
    for (size_t i = 0; i < sizeof unknown / sizeof unknown[0]; i++) {
        char host[1024];
        snprintf(host, sizeof host, "#version 330 core\n%s#pragma halo declarations\n#endif\n" HOST_BODY, unknown[i]);
        halo_program *p = link_host(sample_scene, host, HALO_TARGET_GLSL330);
        if (!p)
            check_print_diags(diags);
        CHECK(p != NULL);
        halo_program_destroy(p);
    }
    return 0;
}

/* Conditions a fuzzer would write: deep nesting, overflow, self-referencing macros. */
static int test_hostile_conditions(void)
{
    static const char *const lines[] = {"#if 9223372036854775807 + 1 < 0 || -(-9223372036854775807 - 1) * 3\n",
                                        "#if (-9223372036854775807 - 1) / -1 || 1 << 70 || -1 << 3\n",
                                        "#define A B\n#define B A\n#if A\n"};
    size_t deep = 20000, size = 2 * deep + 1024;
    char *host = malloc(size), *nested = malloc(deep + 16);
    SETUP(host && nested);
    memcpy(nested, "#if ", 4);
    memset(nested + 4, '(', deep);
    strcpy(nested + 4 + deep, "1\n");
    for (size_t i = 0; i <= sizeof lines / sizeof lines[0]; i++) {
        snprintf(host, size, "#version 330 core\n%s#pragma halo declarations\n#endif\n" HOST_BODY,
                 i < sizeof lines / sizeof lines[0] ? lines[i] : nested);
        halo_program *p = link_host(sample_scene, host, HALO_TARGET_GLSL330);
        halo_program_destroy(p);
        if (!p) {
            check_print_diags(diags);
            free(host);
            free(nested);
            CHECK_FAIL_AT("condition %zu: the link failed", i);
        }
    }
    free(host);
    free(nested);
    return 0;
}

#define HOST_NO_APPLY(call_line)                                                                  \
    "#version 330 core\n"           /* 1 */                                                       \
    "#pragma halo declarations\n"   /* 2 */                                                       \
    "out vec4 c;\n"                 /* 3 */                                                       \
    "void main() {\n"               /* 4 */                                                       \
    "    vec4 color = vec4(0.5);\n" /* 5 */                                                       \
    "#ifdef HALO_LINKED\n"          /* 6 */                                                       \
    "    halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.1), vec3(0.0, 0.0, 1.0), 0.5,\n" \
    "                                     gl_FragCoord.xy, color.rgb, color.a);\n" /* 8 */        \
        call_line                                                                  /* 9, 10 */    \
    "    color = vec4(s.color, s.opacity);\n"                                                     \
    "#endif\n"                                                                                    \
    "    c = color;\n"                                                                            \
    "}\n"

/* (2) Per-sample stages need a halo_apply call that the compiler sees. */
static int test_apply_missing(void)
{
    if (expect_error(sample_scene, HOST_NO_APPLY("\n\n"), HALO_TARGET_GLSL330, HALO_MSG_HOST_APPLY_MISSING, 4, 6))
        return 1;
    CHECK_STR_CONTAINS(check_find_diag(diags, HALO_MSG_HOST_APPLY_MISSING, 4)->text, "boundary");
    if (expect_error(sample_scene, HOST_NO_APPLY("    // halo_apply(s);\n\n"), HALO_TARGET_GLSL330,
                     HALO_MSG_HOST_APPLY_MISSING, 9, 8) ||
        expect_error(sample_scene, HOST_NO_APPLY("    /* halo_apply(s);\n */\n"), HALO_TARGET_GLSL330,
                     HALO_MSG_HOST_APPLY_MISSING, 9, 8) ||
        expect_error(sample_scene, HOST_NO_APPLY("#ifdef GL_ES\n    halo_apply(s);\n#endif\n"), HALO_TARGET_GLSL330,
                     HALO_MSG_HOST_APPLY_MISSING, 10, 5))
        return 1;
    /* A call in a taken branch counts, and so does one through a macro. */
    if (expect_valid(sample_scene, HOST_NO_APPLY("#ifdef GL_ES\n#else\n    halo_apply(s);\n#endif\n"),
                     HALO_TARGET_GLSL330) ||
        expect_valid(sample_scene, HOST_NO_APPLY("#define APPLY_HALOS halo_apply\n    APPLY_HALOS(s);\n"),
                     HALO_TARGET_GLSL330))
        return 1;
    /* No stage, no call needed (the no-halo host). */
    return expect_valid(NULL, HOST_NO_APPLY("\n\n"), HALO_TARGET_GLSL330);
}

#define SEED_HOST(finish_line)                                                                    \
    "#version 330 core\n"                /* 1 */                                                  \
    "#pragma halo declarations\n"        /* 2 */                                                  \
    "layout(location = 0) out vec4 c;\n" /* 3 */                                                  \
    "void main() {\n"                    /* 4 */                                                  \
    "    vec4 color = vec4(0.5);\n"      /* 5 */                                                  \
    "    halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.1), vec3(0.0, 0.0, 1.0), 0.5,\n" \
    "                                     gl_FragCoord.xy, color.rgb, color.a);\n" /* 7 */        \
    "    halo_apply(s);\n"                                                         /* 8 */        \
        finish_line                                                                /* 9 */        \
    "    c = vec4(s.color, s.opacity);\n"                                                         \
    "}\n"

/* (2) halo_finish in a comment used to satisfy the check (it searched the text). */
static int test_finish_missing(void)
{
    if (expect_error(seed_scene, SEED_HOST("    // halo_finish(); later\n"), HALO_TARGET_GLSL330,
                     HALO_MSG_HOST_FINISH_MISSING, 9, 8) ||
        expect_error(seed_scene, SEED_HOST("\n"), HALO_TARGET_GLSL330, HALO_MSG_HOST_FINISH_MISSING, 4, 6))
        return 1;
    return expect_valid(seed_scene, SEED_HOST("    halo_finish();\n"), HALO_TARGET_GLSL330);
}

/* The host links, and glslang's first error is at file:line. */
static int expect_glsl_error(const char *host, const char *file, int line)
{
    halo_program *p = link_host(sample_scene, host, HALO_TARGET_GLSL330);
    if (!p)
        check_print_diags(diags);
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p}, diags), HALO_ERROR_INPUT);
    halo_program_destroy(p);
    const halo_diagnostic *g = check_find_diag(diags, HALO_MSG_GLSL_ERROR, 0);
    if (!g || g->line != line)
        check_print_diags(diags);
    CHECK(g != NULL);
    CHECK_STR_EQ(g->file, file);
    CHECK_INT_EQ(g->line, line);
    CHECK_STR_CONTAINS(g->source_line, "vec2(1.0)");
    return 0;
}

/* Line of the linked source holding text (1-based), mapped back through the program. */
static int map_line_of(const halo_program *p, const char *text, const char **file)
{
    const char *src = halo_program_source(p, HALO_PIECE_WHOLE), *hit = strstr(src, text);
    int out = 1, line = 0;
    for (const char *c = src; hit && c < hit; c++)
        out += *c == '\n';
    if (!hit || !halo_program_map_line(p, HALO_PIECE_WHOLE, out, file, &line))
        return 0;
    return line;
}

/* (3) #line N, #line N "file", #line N source-string: diagnostics and the line map
 * follow the directive. */
static int test_line_directive(void)
{
    static const char host[] =
        "#version 330 core\n"         /* 1 */
        "#pragma halo declarations\n" /* 2 */
        "out vec4 c;\n"               /* 3 */
        "#line 100\n"                 /* 4 */
        "void main()\n"               /* 5: 100 */
        "{\n"                         /* 6: 101 */
        "    float y = vec2(1.0);\n"  /* 7: 102 */
        "    halo_sample s; halo_apply(s); c = vec4(y);\n"
        "}\n";
    if (expect_glsl_error(host, "test.frag", 102))
        return 1;
    halo_program *p = link_host(sample_scene, host, HALO_TARGET_GLSL330);
    CHECK(p != NULL);
    CHECK_STR_NOT_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "\n#line");
    const char *file = NULL;
    int line = map_line_of(p, "float y = vec2", &file);
    int same = file && !strcmp(file, "test.frag");
    int before = map_line_of(p, "out vec4 c;", &file);
    halo_program_destroy(p);
    CHECK(same);
    CHECK_INT_EQ(line, 102);
    CHECK_INT_EQ(before, 3);

    /* A file name (GL_GOOGLE_cpp_style_line_directive), and the linker's own diagnostics. */
#define NAMED_LINE_HOST                                        \
    "#version 330 core\n"                                      \
    "#extension GL_GOOGLE_cpp_style_line_directive : enable\n" \
    "#pragma halo declarations\n"                              \
    "#line 20 \"renderer/raycast.glsl\"\n"
    if (expect_error_at("renderer/raycast.glsl", sample_scene, NAMED_LINE_HOST "float halo_mine;\n" HOST_BODY,
                        HALO_TARGET_GLSL330, HALO_MSG_HOST_RESERVED_NAME, 20, 7) ||
        expect_glsl_error(NAMED_LINE_HOST
                          "out vec4 c;\n"
                          "void main() { float y = vec2(1.0); halo_sample s; halo_apply(s); c = vec4(y); }\n",
                          "renderer/raycast.glsl", 21))
        return 1;
#undef NAMED_LINE_HOST
    /* A source-string number keeps the host's file; a #line in a branch not taken is no #line. */
    return expect_glsl_error(
        "#version 330 core\n#pragma halo declarations\n#line 50 3\nout vec4 c;\n#if 0\n#line 7\n"
        "#endif\nvoid main() { float y = vec2(1.0); halo_sample s; halo_apply(s); c = vec4(y); }\n",
        "test.frag", 54);
}

/* (4) A host macro still defined at the marker rewrites libhalo's declarations. */
static int test_macro_clash(void)
{
    static const char *const clashes[][2] = {
        {"#define opacity a*1.0\n", "opacity"}, /* a halo_sample field */
        {"#define color vec3(1.0)\n", "color"},
        {"#define value 0.5\n", "value"},
        {"#define s sample_state\n", "s"}, /* the halo_sample variable of libhalo's code */
    };
    for (size_t i = 0; i < sizeof clashes / sizeof clashes[0]; i++) {
        char host[1024];
        snprintf(host, sizeof host, "#version 330 core\n%s#pragma halo declarations\n" HOST_BODY, clashes[i][0]);
        if (expect_error(sample_scene, host, HALO_TARGET_GLSL330, HALO_MSG_HOST_MACRO_CLASH, 2, 9))
            return 1;
        CHECK_STR_CONTAINS(check_find_diag(diags, HALO_MSG_HOST_MACRO_CLASH, 2)->text, clashes[i][1]);
        CHECK_STR_CONTAINS(check_find_diag(diags, HALO_MSG_HOST_MACRO_CLASH, 2)->text, "#undef");
    }
    /* #undef before the marker, a define after it, in a branch not taken, or of a name
     * libhalo does not use: no clash. */
    return expect_valid(sample_scene,
                        "#version 330 core\n#define opacity a\n#undef opacity\n#if 0\n#define color x\n#endif\n"
                        "#define MY_STEP 0.01\n#pragma halo declarations\n#define value 0.5\n" HOST_BODY,
                        HALO_TARGET_GLSL330);
}

/* (5) Outputs without layout(location) beside libhalo's extra outputs. */
static int test_output_location(void)
{
    static const char host[] =
        "#version 330 core\n"              /* 1 */
        "#pragma halo declarations\n"      /* 2 */
        "uniform float k;\n"               /* 3 */
        "out vec4 c;\n"                    /* 4 */
        "void f(out float x) { x = k; }\n" /* 5 */
        "void main() {\n"
        "    halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.1), vec3(0.0, 0.0, 1.0), "
        "0.5, gl_FragCoord.xy, vec3(0.5), 0.5);\n"
        "    halo_apply(s);\n"
        "    halo_finish();\n"
        "    c = vec4(s.color, s.opacity);\n"
        "}\n";
    if (expect_error(seed_scene, host, HALO_TARGET_GLSL330, HALO_MSG_HOST_OUTPUT_LOCATION, 4, 1))
        return 1;
    CHECK_INT_EQ(check_count_diag(diags, HALO_MSG_HOST_OUTPUT_LOCATION), 1);
    CHECK_STR_CONTAINS(check_find_diag(diags, HALO_MSG_HOST_OUTPUT_LOCATION, 4)->text, "layout(location = 0)");
    /* Without extra outputs the compiler's placement is the host's business. */
    if (expect_valid(sample_scene, host, HALO_TARGET_GLSL330))
        return 1;
    char located[1024];
    static const char fixed[] =
        "#version 330 core\n#pragma halo declarations\nuniform float k;\n"
        "layout(location = 0)\n    out vec4 c;\nvoid f(out float x) { x = k; }\n";
    snprintf(located, sizeof located, "%s%s", fixed, strstr(host, "void main"));
    return expect_valid(seed_scene, located, HALO_TARGET_GLSL330);
}

int main(void)
{
    SETUP(halo_setup(&(halo_setup_desc){0}) == HALO_OK);
    library = check_library_setup(&diags);
    RUN_TEST(test_marker_commented);
    RUN_TEST(test_marker_dead_branch);
    RUN_TEST(test_hostile_conditions);
    RUN_TEST(test_apply_missing);
    RUN_TEST(test_finish_missing);
    RUN_TEST(test_line_directive);
    RUN_TEST(test_macro_clash);
    RUN_TEST(test_output_location);
    halo_library_destroy(library);
    halo_diagnostics_destroy(diags);
    halo_shutdown();
    return check_exit_status();
}
