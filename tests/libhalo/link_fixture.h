/* The linker's test fixture, shared by the tests of the linker's rooms: test_link.c
 * (libhalo/link.c: resolution, order, image passes, targets), test_emit.c (libhalo/emit.c:
 * the emitted text, names, constants and uniforms, the line map), test_program.c
 * (libhalo/program.c: the linked program's parameters and stage information) and
 * test_host_check.c (libhalo/host_check.c: the host contract). A library with the user
 * modules below; hosts are given as strings. No GL. */
#ifndef HALO_TEST_LINK_FIXTURE_H
#define HALO_TEST_LINK_FIXTURE_H

#include "check.h"
#include "internal.h"
#include "strbuf.h"

#define FIXTURE_UNUSED __attribute__((unused))

static FIXTURE_UNUSED halo_library *library;
static FIXTURE_UNUSED halo_diagnostics *diags;

/* A host following the contract: #version, the marker, one sample through halo_apply. */
static FIXTURE_UNUSED const char host_source[] =
    "#version 330 core\n"                             /* 1 */
    "// a test host\n"                                /* 2 */
    "#pragma halo declarations\n"                     /* 3 */
    "layout(location = 0) out vec4 fragment_color;\n" /* 4 */
    "void main()\n"                                   /* 5 */
    "{\n"                                             /* 6 */
    "    vec4 color = vec4(0.8, 0.6, 0.4, 0.5);\n"    /* 7 */
    "#ifdef HALO_LINKED\n"                            /* 8 */
    "    halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.1, 0.2, 0.3), vec3(0.0, 0.0, 1.0), 0.5,\n"
    "                                     gl_FragCoord.xy, color.rgb, color.a);\n" /* 10 */
    "    halo_apply(s);\n"                                                         /* 11 */
    "    color = vec4(s.color, s.opacity); halo_finish();\n"                       /* 12 */
    "#endif\n"                                                                     /* 13 */
    "    fragment_color = color;\n"                                                /* 14 */
    "}\n";

static FIXTURE_UNUSED halo_scene *scene_of(const char *json)
{
    halo_diagnostics_clear(diags);
    halo_scene *s = halo_scene_load("test.json", json, library, diags);
    if (!s) {
        check_print_diags(diags);
        SETUP_FAIL("scene rejected: %s", json);
    }
    return s;
}

static FIXTURE_UNUSED halo_program *link_with(const halo_scene *scene, const char *host, halo_target target,
                                              int all_live)
{
    halo_diagnostics_clear(diags);
    return halo_link(&(halo_link_desc){.library = library,
                                       .scene = scene,
                                       .host_source = host,
                                       .host_file = "test.frag",
                                       .target = target,
                                       .all_live = all_live},
                     diags);
}

/* Links the scene into the test host and validates it; NULL (and a message) on failure. */
static FIXTURE_UNUSED halo_program *link_valid(const char *json)
{
    halo_scene *scene = scene_of(json);
    halo_program *p = link_with(scene, host_source, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    if (!p || halo_validate(&(halo_validate_desc){.program = p}, diags) != HALO_OK) {
        fprintf(stderr, "link or validation failed for %s\n", json);
        check_print_diags(diags);
        if (p)
            fprintf(stderr, "%s", halo_program_source(p, HALO_PIECE_WHOLE));
        halo_program_destroy(p);
        return NULL;
    }
    return p;
}

static FIXTURE_UNUSED int stage_index(const halo_program *p, const char *stage)
{
    for (size_t i = 0; i < halo_program_reflection(p).stage_count; i++)
        if (!strcmp(halo_program_reflection(p).stages[i].name, stage))
            return (int)i;
    return -1;
}

/* 1-based line number of the first line of text containing needle, or 0. */
static FIXTURE_UNUSED int line_containing(const char *text, const char *needle)
{
    const char *hit = strstr(text, needle);
    if (!hit)
        return 0;
    int line = 1;
    for (const char *c = text; c < hit; c++)
        line += *c == '\n';
    return line;
}

/* User modules for the tests above, added to the library once. */
static FIXTURE_UNUSED const char *const user_modules[][2] = {
    {"user/unused_param.glsl",
     "#pragma halo module unused_param\n"
     "#pragma halo hook sample\n"
     "#pragma halo param used float default=0.5 min=0 max=1\n"
     "#pragma halo param spare float default=0.5 min=0 max=1\n"
     "void apply(inout halo_sample s) { s.opacity *= used; }\n"},
    {"user/weight_a.glsl",
     "#pragma halo module weight_a\n"
     "#pragma halo hook sample\n"
     "float weight(float x) { return x * 0.5; }\n"
     "void apply(inout halo_sample s) { s.opacity = weight(s.opacity); }\n"},
    {"user/weight_b.glsl",
     "#pragma halo module weight_b\n"
     "#pragma halo hook sample\n"
     "const float k_gs = 3.0;\n"
     "float weight(float x) { return x * k_gs; }\n"
     "void apply(inout halo_sample s) { s.opacity = halo_saturate(weight(s.opacity)); }\n"},
    {"user/needs_unknown.glsl",
     "#pragma halo module needs_unknown\n"
     "#pragma halo hook sample\n"
     "#pragma halo needs curvature\n"
     "void apply(inout halo_sample s) {}\n"},
    {"user/provider_a.glsl",
     "#pragma halo module provider_a\n"
     "#pragma halo hook sample\n"
     "#pragma halo provides thing float\n"
     "void apply(inout halo_sample s) { s.thing = 1.0; }\n"},
    {"user/provider_b.glsl",
     "#pragma halo module provider_b\n"
     "#pragma halo hook sample\n"
     "#pragma halo provides thing float\n"
     "void apply(inout halo_sample s) { s.thing = 2.0; }\n"},
    {"user/needs_thing.glsl",
     "#pragma halo module needs_thing\n"
     "#pragma halo hook sample\n"
     "#pragma halo needs thing\n"
     "void apply(inout halo_sample s) { s.opacity *= s.thing; }\n"},
    {"user/cycle_a.glsl",
     "#pragma halo module cycle_a\n"
     "#pragma halo hook sample\n"
     "#pragma halo after cycle_b\n"
     "void apply(inout halo_sample s) {}\n"},
    {"user/cycle_b.glsl",
     "#pragma halo module cycle_b\n"
     "#pragma halo hook sample\n"
     "#pragma halo after cycle_a\n"
     "void apply(inout halo_sample s) {}\n"},
    {"user/type_error.glsl",
     "#pragma halo module type_error\n" /* 1 */
     "#pragma halo hook sample\n"       /* 2 */
     "// a stage with a type error on line 7\n"
     "\n"                                /* 4 */
     "void apply(inout halo_sample s)\n" /* 5 */
     "{\n"                               /* 6 */
     "    float x = vec3(1.0);\n"        /* 7 */
     "    s.opacity = x;\n"              /* 8 */
     "}\n"},
};


/* halo_setup, the library and the user modules; exits on failure. */
static FIXTURE_UNUSED void link_fixture_setup(void)
{
    SETUP(halo_setup(&(halo_setup_desc){0}) == HALO_OK);
    library = check_library_setup(&diags);
    for (size_t i = 0; i < sizeof user_modules / sizeof user_modules[0]; i++)
        if (halo_library_add(library, user_modules[i][0], user_modules[i][1], HALO_ADD_NEW, diags) != HALO_OK) {
            check_print_diags(diags);
            SETUP_FAIL("cannot add %s", user_modules[i][0]);
        }
}

/* Frees the fixture; the test program's exit status. */
static FIXTURE_UNUSED int link_fixture_finish(void)
{
    halo_library_destroy(library);
    halo_diagnostics_destroy(diags);
    halo_shutdown();
    return check_exit_status();
}

#endif
