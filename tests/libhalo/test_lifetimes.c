/* Object lifetimes (halo.h, "Lifetimes"): a scene or program keeps its library alive,
 * a scene links only with the library it was read against, a module used by a scene
 * cannot be replaced under it, and validation before halo_setup is a USAGE error, not
 * a crash inside glslang. Freed memory is filled with a pattern (glibc's
 * malloc.perturb tunable) so that a use after free reads garbage even without
 * AddressSanitizer. */
#include "check.h"

#include <unistd.h>

static const char scene_json[] = "{\"halo_scene\": 1, \"stages\": [{\"boundary\": {\"k_gs\": 10}}]}";

/* A boundary module whose k_gs default (7) differs from the built-in one. */
static const char other_boundary[] =
    "#pragma halo module boundary\n"
    "#pragma halo hook sample\n"
    "#pragma halo param k_gs float default=7 min=0 max=100 \"a stand-in\"\n"
    "void apply(inout halo_sample s) { s.opacity *= k_gs; }\n";

/* check_library_setup, then scene_json read against that library. */
static halo_scene *scene_setup(halo_library **lib, halo_diagnostics **d)
{
    *lib = check_library_setup(d);
    halo_scene *scene = halo_scene_load("scene.json", scene_json, *lib, *d);
    if (!scene) {
        check_print_diags(*d);
        SETUP_FAIL("scene_json rejected");
    }
    return scene;
}

/* Blocks of the sizes just freed, allocated so that a use after free reads them. */
enum { FILLER_BLOCKS = 64 };
static void filler_take(void *filler[FILLER_BLOCKS])
{
    for (int i = 0; i < FILLER_BLOCKS; i++)
        filler[i] = malloc(64 * (size_t)(i % 8 + 1));
}
static void filler_free(void *filler[FILLER_BLOCKS])
{
    for (int i = 0; i < FILLER_BLOCKS; i++)
        free(filler[i]);
}

static int test_validate_before_setup(void)
{
    halo_diagnostics *d = halo_diagnostics_create();
    CHECK(d != NULL);
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.source = "#version 330 core\nvoid main() {}\n",
                                                     .file = "plain.frag",
                                                     .kind = HALO_SHADER_FRAGMENT,
                                                     .target = HALO_TARGET_GLSL330},
                               d),
                 HALO_ERROR_INPUT);
    CHECK_DIAG(d, HALO_MSG_USAGE);
    CHECK_INT_EQ(halo_diagnostics_describe(d).count, 1);
    CHECK_STR_CONTAINS(halo_diagnostics_get(d, 0)->text, "halo_setup");
    halo_diagnostics_clear(d);
    /* A library and a program need no setup; their validation does. */
    halo_library *lib = halo_library_create(d);
    CHECK(lib != NULL);
    halo_program *p = halo_link(&(halo_link_desc){.library = lib, .host_source = check_sample_host}, d);
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p}, d), HALO_ERROR_INPUT);
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.module = halo_library_find(lib, "boundary"),
                                                     .library = lib,
                                                     .target = HALO_TARGET_GLSL330},
                               d),
                 HALO_ERROR_INPUT);
    CHECK_INT_EQ(check_count_diag(d, HALO_MSG_USAGE), 2);
    /* After a setup and its shutdown, the same again. */
    CHECK_INT_EQ(halo_setup(NULL), HALO_OK);
    halo_diagnostics_clear(d);
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p}, d), HALO_OK);
    halo_shutdown();
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p}, d), HALO_ERROR_INPUT);
    CHECK_DIAG(d, HALO_MSG_USAGE);
    halo_program_destroy(p);
    halo_library_destroy(lib);
    halo_diagnostics_destroy(d);
    return 0;
}

/* The library destroyed first: its scene and program still work, and the last of
 * them frees it (ASan and the leak check see a use after free or a leak). */
static int test_library_destroyed_first(void)
{
    halo_diagnostics *d;
    halo_library *lib;
    halo_scene *scene = scene_setup(&lib, &d);
    halo_program *p = halo_link(
        &(halo_link_desc){.library = lib, .scene = scene, .host_source = check_sample_host, .all_live = 1}, d);
    CHECK(p != NULL);
    halo_library_destroy(lib);
    void *filler[FILLER_BLOCKS]; /* reuse the freed blocks, if they were freed */
    filler_take(filler);
    CHECK_INT_EQ(halo_scene_enable(scene, "silhouette", 1, d), HALO_OK);
    CHECK_INT_EQ(halo_scene_set(scene, "boundary", "k_gs", (const double[]){12}, 1, 0, d), HALO_OK);
    CHECK_STR_EQ(halo_scene_describe(scene).stages[1], "silhouette");
    const halo_uniform_info *u = halo_program_find_uniform(p, "boundary", "k_gs");
    CHECK(u != NULL);
    CHECK_STR_EQ(u->info->name, "k_gs");
    CHECK_INT_EQ(halo_program_set(p, "boundary", "k_gs", (const double[]){11}, 1, d), HALO_OK);
    halo_emu_sample s = {.value = 0.5,
                         .gradient = {0.1, 0.2, 0.3},
                         .view = {0, 0, 1},
                         .depth = 0.5,
                         .color = {0.8, 0.6, 0.4},
                         .opacity = 0.5};
    CHECK_INT_EQ(halo_emu_apply(p, NULL, &s, d), HALO_OK);
    CHECK_FINITE(s.opacity);
    filler_free(filler);
    halo_scene_destroy(scene);
    CHECK_STR_EQ(halo_program_reflection(p).stages[0].name, "gradient"); /* the program still holds the library */
    halo_program_destroy(p);
    CHECK_NO_ERRORS(d);
    halo_diagnostics_destroy(d);
    return 0;
}

/* An emulation frame keeps its program (and so the library) alive. */
static int test_program_destroyed_first(void)
{
    halo_diagnostics *d;
    halo_library *lib;
    halo_scene *scene = scene_setup(&lib, &d);
    halo_program *p = halo_link(&(halo_link_desc){.library = lib, .scene = scene, .host_source = check_sample_host}, d);
    CHECK(p != NULL);
    halo_emu_frame *f = halo_emu_frame_create(p, 4, 4, d);
    CHECK(f != NULL);
    halo_scene_destroy(scene);
    halo_library_destroy(lib);
    halo_program_destroy(p);
    void *filler[FILLER_BLOCKS]; /* reuse the freed blocks, if they were freed */
    filler_take(filler);
    halo_emu_frame_begin(f);
    CHECK_INT_EQ(halo_emu_frame_generate(f, d), HALO_OK);
    CHECK_INT_EQ(halo_emu_frame_post(f, d), HALO_OK);
    filler_free(filler);
    halo_emu_frame_destroy(f);
    CHECK_NO_ERRORS(d);
    halo_diagnostics_destroy(d);
    return 0;
}

/* A scene read against one library, linked with another: refused, not linked with the
 * first library's modules. */
static int test_scene_of_another_library(void)
{
    halo_diagnostics *d;
    halo_library *first = check_library_setup(&d);
    halo_library *second = halo_library_create(d);
    CHECK(second != NULL);
    CHECK_INT_EQ(halo_library_add(second, "other_boundary.glsl", other_boundary, HALO_ADD_REPLACE, d), HALO_OK);
    halo_scene *scene = halo_scene_load("s.json", "{\"halo_scene\": 1, \"stages\": [\"boundary\"]}", first, d);
    CHECK(scene != NULL);
    CHECK_NO_ERRORS(d);
    halo_program *p =
        halo_link(&(halo_link_desc){.library = second, .scene = scene, .host_source = check_sample_host}, d);
    CHECK(p == NULL);
    CHECK_DIAG(d, HALO_MSG_USAGE);
    halo_diagnostics_clear(d);
    /* with its own library it links */
    p = halo_link(&(halo_link_desc){.library = first, .scene = scene, .host_source = check_sample_host}, d);
    CHECK(p != NULL);
    halo_program_destroy(p);
    /* a module of another library is not validated as this library's module of that name */
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.module = halo_library_find(second, "boundary"),
                                                     .library = first,
                                                     .target = HALO_TARGET_GLSL330},
                               d),
                 HALO_ERROR_INPUT);
    CHECK_DIAG(d, HALO_MSG_USAGE);
    halo_scene_destroy(scene);
    halo_library_destroy(first);
    halo_library_destroy(second);
    halo_diagnostics_destroy(d);
    return 0;
}

/* Replacing a module that a scene or program points into is refused while they live. */
static int test_override_in_use(void)
{
    halo_diagnostics *d;
    halo_library *lib;
    halo_scene *scene = scene_setup(&lib, &d);
    CHECK_INT_EQ(halo_library_add(lib, "other_boundary.glsl", other_boundary, HALO_ADD_REPLACE, d), HALO_ERROR_INPUT);
    CHECK_DIAG(d, HALO_MSG_USAGE);
    CHECK_INT_EQ(halo_scene_set(scene, "boundary", "k_gs", (const double[]){50}, 1, 0, d), HALO_OK);
    halo_scene_destroy(scene);
    halo_diagnostics_clear(d);
    CHECK_INT_EQ(halo_library_add(lib, "other_boundary.glsl", other_boundary, HALO_ADD_REPLACE, d), HALO_OK);
    CHECK_INT_EQ((int)halo_module_describe(halo_library_find(lib, "boundary")).params[0].default_value[0], 7);
    halo_library_destroy(lib);
    halo_diagnostics_destroy(d);
    return 0;
}

int main(int argc, char **argv)
{
    (void)argc;
#ifdef __GLIBC__
    /* glibc fills freed memory only outside its per-thread cache: run again without it */
    if (!getenv("HALO_TEST_PERTURB")) {
        setenv("HALO_TEST_PERTURB", "1", 1);
        setenv("GLIBC_TUNABLES", "glibc.malloc.tcache_count=0:glibc.malloc.perturb=165", 1);
        execv("/proc/self/exe", argv);
    }
#endif
    RUN_TEST(test_validate_before_setup); /* first: before any halo_setup */
    SETUP(halo_setup(NULL) == HALO_OK);
    RUN_TEST(test_library_destroyed_first);
    RUN_TEST(test_program_destroyed_first);
    RUN_TEST(test_scene_of_another_library);
    RUN_TEST(test_override_in_use);
    halo_shutdown();
    return check_exit_status();
}
