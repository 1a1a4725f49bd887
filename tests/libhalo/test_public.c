/* The public API only (halo.h), through the shared library libhalo.la as an
 * application links it: create a library, read a scene, link it into a host, validate,
 * emulate. */
#include "check.h"

#include <sys/stat.h>
#include <unistd.h>

static int test_pipeline(void)
{
    halo_diagnostics *d = halo_diagnostics_create();
    CHECK(d != NULL);
    halo_library *lib = halo_library_create(d);
    CHECK(lib != NULL);
    CHECK(halo_library_describe(lib).module_count >= 9);
    CHECK(halo_library_find(lib, "boundary") != NULL);
    halo_scene *scene = halo_scene_load("public.json",
                                        "{\"halo_scene\": 1, \"stages\": [{\"boundary\": {\"k_gs\": 10, \"live\":"
                                        " [\"k_gc\"]}}, \"silhouette\", \"tone_shading\"]}",
                                        lib, d);
    CHECK(scene != NULL);
    CHECK_INT_EQ(halo_scene_describe(scene).stage_count, 3);
    for (int t = HALO_TARGET_GLSL330; t < HALO_TARGET_COUNT; t++) {
        halo_program *p = halo_link(&(halo_link_desc){.library = lib,
                                                      .scene = scene,
                                                      .host_source = check_sample_host,
                                                      .host_file = "public.frag",
                                                      .target = (halo_target)t},
                                    d);
        CHECK(p != NULL);
        if (halo_validate(&(halo_validate_desc){.program = p}, d) != HALO_OK) {
            check_print_diags(d);
            CHECK_FAIL_AT("does not validate for %s", halo_target_name((halo_target)t));
        }
        CHECK_INT_EQ(halo_program_reflection(p).stage_count, 4); /* with gradient */
        CHECK_STR_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "uniform float halo_boundary_k_gc;");
        const halo_uniform_info *u = halo_program_find_uniform(p, "boundary", "k_gc");
        CHECK(u && u->live);
        halo_emu_sample s = {.value = 0.5,
                             .gradient = {0.1, 0.2, 0.3},
                             .view = {0, 0, 1},
                             .depth = 0.5,
                             .color = {0.8, 0.6, 0.4},
                             .opacity = 0.5};
        CHECK_INT_EQ(halo_emu_apply(p, NULL, &s, d), HALO_OK);
        CHECK_FINITE(s.opacity);
        char *json = halo_program_reflect_json(p);
        CHECK(json != NULL);
        CHECK_STR_CONTAINS(json, "halo_boundary_k_gc");
        free(json);
        halo_program_destroy(p);
    }
    CHECK_INT_EQ(halo_diagnostics_describe(d).errors, 0);
    /* Errors come back as ids. */
    halo_scene *bad = halo_scene_load("bad.json", "{\"stages\": [\"nope\"]}", lib, d);
    CHECK(bad == NULL);
    CHECK_DIAG(d, HALO_MSG_SCENE_STAGE_UNKNOWN);
    CHECK_STR_EQ(halo_message_name(HALO_MSG_SCENE_STAGE_UNKNOWN), "SCENE_STAGE_UNKNOWN");
    halo_scene_destroy(scene);
    halo_library_destroy(lib);
    halo_diagnostics_destroy(d);
    return 0;
}

static int logged;
static void logger(const halo_diagnostic *g, void *user_data)
{
    (void)g;
    *(int *)user_data += 1;
}

static int test_logger(void)
{
    logged = 0;
    halo_diagnostics *d = halo_diagnostics_create();
    halo_library *lib = halo_library_create(d);
    CHECK(lib != NULL);
    CHECK(halo_scene_load("bad.json", "not json", lib, d) == NULL);
    CHECK_INT_EQ(logged, 1);
    CHECK_INT_EQ(halo_diagnostics_describe(d).count, 1);
    halo_library_destroy(lib);
    halo_diagnostics_destroy(d);
    return 0;
}

/* Writes text to root/name; 0 on success. */
static int write_file(const char *root, const char *name, const char *text)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", root, name);
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    int ok = fputs(text, f) >= 0;
    return fclose(f) == 0 && ok ? 0 : -1;
}

/* '#include "name"' resolves against the including file's folder, as glslangValidator
 * does, whatever the working directory: here the working directory holds a part.h that
 * is no GLSL, beside the shaders/ folder with the right one. A header included by a
 * header looks in that header's folder, then outward (tone.h is in shaders/); an error
 * in a header is at its own file:line. */
static int test_include_beside_file(void)
{
    const char *tmp = getenv("TMPDIR");
    char root[4096], cwd[4096];
    snprintf(root, sizeof root, "%s/halo-include-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    CHECK(mkdtemp(root) != NULL);
    CHECK(getcwd(cwd, sizeof cwd) != NULL);
    char dir[4200];
    snprintf(dir, sizeof dir, "%s/shaders", root);
    CHECK(mkdir(dir, 0700) == 0);
    snprintf(dir, sizeof dir, "%s/shaders/more", root);
    CHECK(mkdir(dir, 0700) == 0);
    static const char shader[] =
        "#version 330\n"
        "#extension GL_GOOGLE_include_directive : require\n"
        "#include \"part.h\"\n"
        "out vec4 color;\n"
        "void main() { color = part_color(); }\n";
    static const char broken[] =
        "#version 330\n"
        "#extension GL_GOOGLE_include_directive : require\n"
        "#include \"more/broken.h\"\n"
        "out vec4 color;\n"
        "void main() { color = vec4(1.0); }\n";
    CHECK(write_file(root, "part.h", "this is not GLSL\n") == 0);
    CHECK(write_file(root, "shaders/part.h", "#include \"more/inner.h\"\nvec4 part_color() { return inner(); }\n") ==
          0);
    CHECK(write_file(root, "shaders/more/inner.h", "#include \"tone.h\"\nvec4 inner() { return vec4(tone); }\n") == 0);
    CHECK(write_file(root, "shaders/tone.h", "const float tone = 0.5;\n") == 0);
    CHECK(write_file(root, "shaders/more/broken.h", "float fine = 1.0;\nfloat bad = missing;\n") == 0);
    CHECK(chdir(root) == 0);
    halo_diagnostics *d = halo_diagnostics_create();
    halo_status ok = halo_validate(
        &(halo_validate_desc){
            .source = shader, .file = "shaders/main.frag", .kind = HALO_SHADER_FRAGMENT, .target = HALO_TARGET_DEFAULT},
        d);
    if (ok != HALO_OK)
        check_print_diags(d);
    halo_diagnostics_clear(d);
    halo_status bad = halo_validate(
        &(halo_validate_desc){
            .source = broken, .file = "shaders/main.frag", .kind = HALO_SHADER_FRAGMENT, .target = HALO_TARGET_DEFAULT},
        d);
    const halo_diagnostic *g = check_find_diag(d, HALO_MSG_GLSL_ERROR, 0);
    int back = chdir(cwd);
    const char *names[] = {"shaders/more/broken.h",
                           "shaders/tone.h",
                           "shaders/more/inner.h",
                           "shaders/part.h",
                           "part.h",
                           "shaders/more",
                           "shaders",
                           ""};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char path[8300];
        snprintf(path, sizeof path, "%s/%s", root, names[i]);
        remove(path);
    }
    CHECK_INT_EQ(back, 0);
    CHECK_INT_EQ(ok, HALO_OK);
    CHECK_INT_EQ(bad, HALO_ERROR_INPUT);
    CHECK(g != NULL);
    CHECK_STR_EQ(g->file, "shaders/more/broken.h");
    CHECK_INT_EQ(g->line, 2);
    halo_diagnostics_destroy(d);
    return 0;
}

int main(void)
{
    SETUP(halo_setup(&(halo_setup_desc){.logger = logger, .user_data = &logged}) == HALO_OK);
    CHECK_STR_EQ(halo_version(), PACKAGE_VERSION);
    RUN_TEST(test_pipeline);
    RUN_TEST(test_logger);
    RUN_TEST(test_include_beside_file);
    halo_shutdown();
    return check_exit_status();
}
