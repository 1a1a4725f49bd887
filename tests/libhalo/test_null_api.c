/* Every public function refuses NULL where it expects an object (halo.h, "NULL
 * arguments"): each one is called with NULL for each object or required argument in
 * turn, once with a diagnostics list and once without, and must return its error value
 * and report one USAGE diagnostic naming the function and the argument, in the list
 * (where the function takes one) and through the setup logger, without crashing.
 * Destroy functions and the halo_diagnostics_* readers take NULL silently.
 *
 * The table below has one row per HALO_API function of halo.h and halo_feature.h;
 * test_table_matches_headers reads the headers and fails for a function that has no
 * row, so a function added later without a NULL check is noticed here.
 *
 * Each function's calls run in a child process (fork), so that a crash names the
 * function and the others still run. The halo_gl_* and halo_feature_buffer_* calls
 * with a valid runtime need a headless context; without one only their NULL-runtime
 * and NULL-frame calls run (the rest is reported as skipped). */
#include "check.h"
#include "halo_feature.h"
#include "halo_gl_loader.h"
#include "gl/headless.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

/* ---- What the setup logger saw ---- */

static struct {
    int count;
    halo_message_id id;
    char text[512];
} logged;

static void logger(const halo_diagnostic *g, void *user_data)
{
    (void)user_data;
    if (logged.count++ == 0) {
        logged.id = g->id;
        snprintf(logged.text, sizeof logged.text, "%s", g->text);
    }
}

static void refuse_begin(halo_diagnostics *d)
{
    halo_diagnostics_clear(d);
    logged.count = 0;
    logged.text[0] = '\0';
}

/* One USAGE diagnostic naming the function and the argument, through the logger and,
 * when the function takes the list d, in d too. */
static int refuse_reported(const char *fn, const char *argument, halo_diagnostics *d, int takes_list)
{
    if (logged.count != 1 || logged.id != HALO_MSG_USAGE || !strstr(logged.text, fn) ||
        !strstr(logged.text, argument)) {
        fprintf(stderr,
                "    %s with %s NULL: the logger saw %d diagnostic%s, the first [%s] \"%s\"; want one USAGE "
                "naming %s and %s\n",
                fn, argument, logged.count, logged.count == 1 ? "" : "s",
                logged.count ? halo_message_name(logged.id) : "-", logged.text, fn, argument);
        return 0;
    }
    if (takes_list && d && (halo_diagnostics_describe(d).count != 1 || !halo_diagnostics_has(d, HALO_MSG_USAGE))) {
        fprintf(stderr, "    %s with %s NULL: the list holds %zu diagnostics, want one USAGE\n", fn, argument,
                halo_diagnostics_describe(d).count);
        check_print_diags(d);
        return 0;
    }
    return 1;
}

/* ok: the call, compared with its error value ("halo_x(NULL) == NULL"). REFUSES for a
 * function without a halo_diagnostics argument, REFUSES_D for one that is passed d. */
#define REFUSES_AS(ok, argument, takes_list)                                               \
    do {                                                                                   \
        refuse_begin(d);                                                                   \
        if (!(ok))                                                                         \
            CHECK_FAIL_AT("%s with %s NULL: not its error value (%s)", fn, argument, #ok); \
        if (!refuse_reported(fn, argument, d, takes_list))                                 \
            CHECK_FAIL_AT("%s: no USAGE diagnostic", fn);                                  \
    } while (0)
#define REFUSES(ok, argument)   REFUSES_AS(ok, argument, 0)
#define REFUSES_D(ok, argument) REFUSES_AS(ok, argument, 1)
/* NULL is a valid value here: no diagnostic at all. */
#define ACCEPTS(ok)                                                                         \
    do {                                                                                    \
        refuse_begin(d);                                                                    \
        if (!(ok))                                                                          \
            CHECK_FAIL_AT("%s: %s failed", fn, #ok);                                        \
        if (logged.count)                                                                   \
            CHECK_FAIL_AT("%s: a diagnostic for a NULL it takes: \"%s\"", fn, logged.text); \
    } while (0)
/* A void call as an expression. */
#define DONE(call) ((call), 1)

/* ---- Valid objects for the arguments that are not NULL ---- */

static const char vertex_source[] =
    "#version 330 core\n"
    "layout(location = 0) in vec2 position;\n"
    "void main() { gl_Position = vec4(position, 0.0, 1.0); }\n";

static char module_path[1024], scene_path[1024];
static halo_library *lib;
static const halo_module *module;
static halo_scene *scene;
static halo_program *program;
static halo_emu_frame *emu_frame;
static const double values[4] = {1, 1, 1, 1};
static const int dims[3] = {4, 4, 4};
static float volume[64], floats_out[64 * 4];
static double doubles_out[64];
static const double view[3] = {0, 0, 1};

/* A runtime in a headless context, made in the child on first use; NULL when there is
 * no context (those calls are skipped). */
static struct {
    int tried;
    halo_gl *gl;
    halo_gl_frame *frame;
    halo_feature_buffer *buffer;
} gl_fixture;
static int gl_skipped;

static halo_gl *fixture_gl(void)
{
    if (!gl_fixture.tried) {
        gl_fixture.tried = 1;
        char err[256] = "";
        if (halo_headless_create(16, 16, err, sizeof err)) {
            gl_fixture.gl = halo_gl_create(&(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address}, NULL);
            if (gl_fixture.gl) {
                gl_fixture.frame = halo_gl_frame_create(gl_fixture.gl, program, 4, 4, NULL);
                gl_fixture.buffer = halo_feature_buffer_create(gl_fixture.gl, volume, dims, NULL, NULL);
            }
        } else {
            fprintf(stderr, "    no headless context (%s)\n", err);
        }
        if (!gl_fixture.gl || !gl_fixture.frame || !gl_fixture.buffer)
            gl_fixture.gl = NULL;
    }
    if (!gl_fixture.gl)
        gl_skipped = 1;
    return gl_fixture.gl;
}

/* ---- One case per function: fn is its name, d a list or NULL ---- */

#define CASE(name) static int case_##name(const char *fn, halo_diagnostics *d)

// clang-format off: one line a case, the table of the API (each one call and its refusal)
CASE(halo_diagnostics_destroy)
{
    ACCEPTS(DONE(halo_diagnostics_destroy(NULL)));
    return 0;
}
CASE(halo_diagnostics_describe)
{
    halo_diagnostics_info info = halo_diagnostics_describe(NULL);
    ACCEPTS(info.count == 0 && info.errors == 0 && info.dropped == 0 && info.limit == HALO_DIAGNOSTICS_DEFAULT_LIMIT);
    return 0;
}
CASE(halo_diagnostics_get)
{
    ACCEPTS(halo_diagnostics_get(NULL, 0) == NULL);
    return 0;
}
CASE(halo_diagnostics_has)
{
    ACCEPTS(halo_diagnostics_has(NULL, HALO_MSG_USAGE) == 0);
    return 0;
}
CASE(halo_diagnostics_clear)
{
    ACCEPTS(DONE(halo_diagnostics_clear(NULL)));
    return 0;
}
CASE(halo_diagnostics_report)
{
    /* a NULL list: the logger alone sees it; a NULL file and text are empty */
    refuse_begin(d);
    halo_diagnostics_report(NULL, HALO_SEVERITY_NOTE, HALO_MSG_GLSL_WARNING, NULL, 0, 0, NULL, NULL);
    CHECK_INT_EQ(logged.count, 1);
    CHECK_INT_EQ(logged.id, HALO_MSG_GLSL_WARNING);
    return 0;
}
CASE(halo_read_text_file)
{
    REFUSES(halo_read_text_file(NULL, "file", NULL, d) == NULL, "path");
    /* a file that is not there: NULL and one IO_READ naming it */
    halo_diagnostics *list = halo_diagnostics_create();
    SETUP(list != NULL);
    CHECK_INT_EQ(halo_read_text_file("/nonexistent/halo.txt", "host shader", NULL, list) == NULL, 1);
    CHECK_INT_EQ(halo_diagnostics_describe(list).count, 1);
    CHECK_INT_EQ(halo_diagnostics_has(list, HALO_MSG_IO_READ), 1);
    /* a NUL byte: no text; NULL and INPUT_NUL_BYTE at its line and column */
    char path[] = "/tmp/halo_nul_XXXXXX";
    int fd = mkstemp(path);
    SETUP(fd >= 0);
    SETUP(write(fd, "ab\n c\0d\n", 8) == 8);
    close(fd);
    halo_diagnostics_clear(list);
    size_t len = 99;
    CHECK(halo_read_text_file(path, "host shader", &len, list) == NULL);
    unlink(path);
    CHECK_INT_EQ(halo_diagnostics_describe(list).count, 1);
    CHECK(halo_diagnostics_get(list, 0) && halo_diagnostics_get(list, 0)->id == HALO_MSG_INPUT_NUL_BYTE);
    CHECK_INT_EQ(halo_diagnostics_get(list, 0)->line, 2);
    CHECK_INT_EQ(halo_diagnostics_get(list, 0)->column, 3);
    halo_diagnostics_destroy(list);
    return 0;
}
CASE(halo_diagnostics_print)
{
    ACCEPTS(DONE(halo_diagnostics_print(NULL, stderr)));
    halo_diagnostics *list = halo_diagnostics_create();
    SETUP(list != NULL);
    halo_diagnostics_report(list, HALO_SEVERITY_NOTE, HALO_MSG_GLSL_WARNING, "f", 1, 1, NULL, "%s", "text");
    REFUSES(DONE(halo_diagnostics_print(list, NULL)), "out");
    halo_diagnostics_destroy(list);
    return 0;
}
CASE(halo_diagnostics_set_limit)
{
    ACCEPTS(DONE(halo_diagnostics_set_limit(NULL, 5)));
    return 0;
}
CASE(halo_diagnostics_set_run)
{
    ACCEPTS(DONE(halo_diagnostics_set_run(NULL, "330")));
    return 0;
}

CASE(halo_setup)
{
    /* NULL: no logger change, default settings */
    ACCEPTS(halo_setup(NULL) == HALO_OK);
    halo_shutdown();
    return 0;
}
CASE(halo_target_from_name)
{
    REFUSES(halo_target_from_name(NULL) == HALO_TARGET_COUNT, "name");
    return 0;
}

CASE(halo_library_create)
{
    halo_library *l;
    ACCEPTS((l = halo_library_create(NULL)) != NULL);
    halo_library_destroy(l);
    return 0;
}
CASE(halo_library_destroy)
{
    ACCEPTS(DONE(halo_library_destroy(NULL)));
    return 0;
}
CASE(halo_library_add)
{
    REFUSES_D(halo_library_add(NULL, module_path, NULL, HALO_ADD_NEW, d) == HALO_ERROR_INPUT, "library");
    REFUSES_D(halo_library_add(lib, NULL, NULL, HALO_ADD_NEW, d) == HALO_ERROR_INPUT, "file");
    REFUSES_D(halo_library_add(lib, NULL, NULL, HALO_ADD_REPLACE, d) == HALO_ERROR_INPUT, "file");
    REFUSES_D(halo_library_add(lib, "m.glsl", "x", (halo_add_mode)2, d) == HALO_ERROR_INPUT, "mode");
    return 0;
}
CASE(halo_library_describe)
{
    REFUSES(halo_library_describe(NULL).modules == NULL, "library");
    return 0;
}
CASE(halo_library_find)
{
    REFUSES(halo_library_find(NULL, "boundary") == NULL, "library");
    REFUSES(halo_library_find(lib, NULL) == NULL, "name");
    return 0;
}

CASE(halo_module_describe)
{
    /* NULL is a module with nothing: zero fields, hook HALO_HOOK_COUNT */
    ACCEPTS(halo_module_describe(NULL).name == NULL && halo_module_describe(NULL).param_count == 0 &&
            halo_module_describe(NULL).hook == HALO_HOOK_COUNT && !halo_module_describe(NULL).has_emulation);
    return 0;
}
CASE(halo_module_find_param)
{
    REFUSES(halo_module_find_param(NULL, "k_gs") == NULL, "module");
    REFUSES(halo_module_find_param(module, NULL) == NULL, "name");
    return 0;
}

CASE(halo_scene_load)
{
    REFUSES_D(halo_scene_load(NULL, NULL, lib, d) == NULL, "file (or json_text)");
    REFUSES_D(halo_scene_load(scene_path, NULL, NULL, d) == NULL, "library");
    REFUSES_D(halo_scene_load("s.json", "{\"stages\": [\"boundary\"]}", NULL, d) == NULL, "library");
    return 0;
}
CASE(halo_scene_create)
{
    REFUSES(halo_scene_create(NULL) == NULL, "library");
    return 0;
}
CASE(halo_scene_destroy)
{
    ACCEPTS(DONE(halo_scene_destroy(NULL)));
    return 0;
}
CASE(halo_scene_enable)
{
    REFUSES_D(halo_scene_enable(NULL, "boundary", 1, d) == HALO_ERROR_INPUT, "scene");
    REFUSES_D(halo_scene_enable(scene, NULL, 1, d) == HALO_ERROR_INPUT, "stage");
    return 0;
}
CASE(halo_scene_set)
{
    REFUSES_D(halo_scene_set(NULL, "boundary", "k_gs", values, 1, 0, d) == HALO_ERROR_INPUT, "scene");
    REFUSES_D(halo_scene_set(scene, NULL, "k_gs", values, 1, 0, d) == HALO_ERROR_INPUT, "stage");
    REFUSES_D(halo_scene_set(scene, "boundary", NULL, values, 1, 0, d) == HALO_ERROR_INPUT, "param");
    REFUSES_D(halo_scene_set(scene, "boundary", "k_gs", NULL, 1, 0, d) == HALO_ERROR_INPUT, "values");
    return 0;
}
CASE(halo_scene_describe)
{
    REFUSES(halo_scene_describe(NULL).render == NULL, "scene");
    return 0;
}
CASE(halo_scene_set_render)
{
    REFUSES(DONE(halo_scene_set_render(NULL, &(halo_render_settings){0})), "scene");
    halo_library *lib = halo_library_create(NULL);
    halo_scene *scene = lib ? halo_scene_create(lib) : NULL;
    SETUP(scene != NULL);
    REFUSES(DONE(halo_scene_set_render(scene, NULL)), "render");
    halo_scene_destroy(scene);
    halo_library_destroy(lib);
    return 0;
}

CASE(halo_link)
{
    REFUSES_D(halo_link(NULL, d) == NULL, "desc");
    REFUSES_D(halo_link(&(halo_link_desc){.scene = scene, .host_source = check_sample_host}, d) == NULL, "library");
    REFUSES_D(halo_link(&(halo_link_desc){.library = lib, .scene = scene}, d) == NULL, "host_source");
    REFUSES_D(halo_link(&(halo_link_desc){.scene = scene, .pieces = &(halo_pieces_desc){.volume = "v"}}, d) == NULL,
              "library");
    return 0;
}
CASE(halo_program_destroy)
{
    ACCEPTS(DONE(halo_program_destroy(NULL)));
    return 0;
}
CASE(halo_program_source)
{
    REFUSES(halo_program_source(NULL, HALO_PIECE_WHOLE) == NULL, "program");
    REFUSES(halo_program_source(NULL, HALO_PIECE_SAMPLE) == NULL, "program");
    return 0;
}
CASE(halo_program_map_line)
{
    const char *file;
    int line;
    REFUSES(halo_program_map_line(NULL, HALO_PIECE_WHOLE, 1, &file, &line) == 0, "program");
    REFUSES(halo_program_map_line(NULL, HALO_PIECE_SAMPLE, 1, &file, &line) == 0, "program");
    return 0;
}
CASE(halo_program_reflection)
{
    /* NULL is a program with nothing: every count 0 */
    ACCEPTS(halo_program_reflection(NULL).stage_count == 0 && halo_program_reflection(NULL).uniform_count == 0 &&
            halo_program_reflection(NULL).uniforms == NULL && halo_program_reflection(NULL).output_count == 0 &&
            halo_program_reflection(NULL).pass_count == 0 && halo_program_reflection(NULL).image_count == 0 &&
            halo_program_reflection(NULL).sampler_count == 0 && halo_program_reflection(NULL).host_uniform_count == 0 &&
            halo_program_reflection(NULL).channel_count == 0 && halo_program_reflection(NULL).segment_location == 0 &&
            halo_program_reflection(NULL).target == HALO_TARGET_COUNT &&
            halo_program_reflection(NULL).group_count == 0 && halo_program_reflection(NULL).interval == 0 &&
            halo_program_reflection(NULL).reads_labels == 0);
    return 0;
}
CASE(halo_program_find_uniform)
{
    REFUSES(halo_program_find_uniform(NULL, "boundary", "k_gs") == NULL, "program");
    REFUSES(halo_program_find_uniform(program, NULL, "k_gs") == NULL, "stage");
    REFUSES(halo_program_find_uniform(program, "boundary", NULL) == NULL, "param");
    return 0;
}
CASE(halo_program_set)
{
    REFUSES_D(halo_program_set(NULL, "boundary", "k_gc", values, 1, d) == HALO_ERROR_INPUT, "program");
    REFUSES_D(halo_program_set(program, NULL, "k_gc", values, 1, d) == HALO_ERROR_INPUT, "stage");
    REFUSES_D(halo_program_set(program, "boundary", NULL, values, 1, d) == HALO_ERROR_INPUT, "param");
    REFUSES_D(halo_program_set(program, "boundary", "k_gc", NULL, 1, d) == HALO_ERROR_INPUT, "values");
    return 0;
}
CASE(halo_pass_reach)
{
    REFUSES(halo_pass_reach(NULL, 1) == -1, "pass");
    return 0;
}
CASE(halo_program_select_group)
{
    REFUSES(halo_program_select_group(NULL, 0) == HALO_ERROR_INPUT, "program");
    return 0;
}
CASE(halo_program_reflect_json)
{
    REFUSES(halo_program_reflect_json(NULL) == NULL, "program");
    return 0;
}

CASE(halo_validate)
{
    const char *composed = halo_program_source(program, HALO_PIECE_WHOLE);
    REFUSES_D(halo_validate(NULL, d) == HALO_ERROR_INPUT, "desc");
    REFUSES_D(halo_validate(&(halo_validate_desc){0}, d) == HALO_ERROR_INPUT, "program");
    REFUSES_D(halo_validate(&(halo_validate_desc){.composed = composed, .composed_file = "c.frag"}, d) ==
                  HALO_ERROR_INPUT,
              "program");
    REFUSES_D(halo_validate(&(halo_validate_desc){.program = program, .composer_piece_count = 1}, d) ==
                  HALO_ERROR_INPUT,
              "composed");
    REFUSES_D(halo_validate(&(halo_validate_desc){.program = program, .composed = composed, .composer_piece_count = 1},
                            d) == HALO_ERROR_INPUT,
              "pieces");
    REFUSES_D(halo_validate(&(halo_validate_desc){.program = program, .source = composed}, d) == HALO_ERROR_INPUT,
              "more than one");
    REFUSES_D(halo_validate(&(halo_validate_desc){.module = module}, d) == HALO_ERROR_INPUT, "library");
    REFUSES_D(halo_validate(&(halo_validate_desc){.source = composed, .composed = composed}, d) == HALO_ERROR_INPUT,
              "composed fields");
    REFUSES_D(halo_validate(&(halo_validate_desc){.program = program, .library = lib}, d) == HALO_ERROR_INPUT,
              "library");
    return 0;
}
CASE(halo_source_kind_of)
{
    REFUSES(halo_source_kind_of(NULL) == HALO_SOURCE_SHADER, "source");
    return 0;
}
CASE(halo_emu_apply)
{
    halo_emu_sample s = {.value = 0.5, .view = {0, 0, 1}};
    REFUSES_D(halo_emu_apply(NULL, NULL, &s, d) == HALO_ERROR_INPUT, "program");
    REFUSES_D(halo_emu_apply(program, NULL, NULL, d) == HALO_ERROR_INPUT, "sample");
    return 0;
}
CASE(halo_emu_frame_create)
{
    REFUSES_D(halo_emu_frame_create(NULL, 4, 4, d) == NULL, "program");
    return 0;
}
CASE(halo_emu_frame_destroy)
{
    ACCEPTS(DONE(halo_emu_frame_destroy(NULL)));
    return 0;
}
CASE(halo_emu_frame_image)
{
    REFUSES(halo_emu_frame_image(NULL, "seed") == NULL, "frame");
    REFUSES(halo_emu_frame_image(emu_frame, NULL) == NULL, "name");
    return 0;
}
CASE(halo_emu_frame_set_host_uniform)
{
    REFUSES(halo_emu_frame_set_host_uniform(NULL, "screen_right", values, 3) == HALO_ERROR_INPUT, "frame");
    REFUSES(halo_emu_frame_set_host_uniform(emu_frame, NULL, values, 3) == HALO_ERROR_INPUT, "name");
    REFUSES(halo_emu_frame_set_host_uniform(emu_frame, "screen_right", NULL, 3) == HALO_ERROR_INPUT, "values");
    return 0;
}
CASE(halo_emu_frame_begin)
{
    REFUSES(DONE(halo_emu_frame_begin(NULL)), "frame");
    return 0;
}
CASE(halo_emu_frame_begin_group)
{
    REFUSES(DONE(halo_emu_frame_begin_group(NULL)), "frame");
    return 0;
}
CASE(halo_emu_frame_end_group)
{
    REFUSES_D(halo_emu_frame_end_group(NULL, d) == HALO_ERROR_INPUT, "frame");
    return 0;
}
CASE(halo_emu_frame_finish)
{
    halo_emu_sample s = {.value = 0.5};
    REFUSES(DONE(halo_emu_frame_finish(NULL, &s)), "frame");
    REFUSES(DONE(halo_emu_frame_finish(emu_frame, NULL)), "sample");
    return 0;
}
CASE(halo_emu_frame_generate)
{
    REFUSES_D(halo_emu_frame_generate(NULL, d) == HALO_ERROR_INPUT, "frame");
    return 0;
}
CASE(halo_emu_frame_post)
{
    REFUSES_D(halo_emu_frame_post(NULL, d) == HALO_ERROR_INPUT, "frame");
    return 0;
}
CASE(halo_emu_frame_set_volume)
{
    REFUSES(halo_emu_frame_set_volume(NULL, "labels", volume, 4, 4, 4) == HALO_ERROR_INPUT, "frame");
    REFUSES(halo_emu_frame_set_volume(emu_frame, NULL, volume, 4, 4, 4) == HALO_ERROR_INPUT, "name");
    REFUSES(halo_emu_frame_set_volume(emu_frame, "labels", NULL, 4, 4, 4) == HALO_ERROR_INPUT, "data");
    return 0;
}
CASE(halo_budget_choose)
{
    const halo_budget_row rows[1] = {{1.0, 0.1}};
    size_t chosen;
    REFUSES_D(halo_budget_choose(NULL, 1, 1.0, &chosen, d) == HALO_ERROR_INPUT, "rows");
    REFUSES_D(halo_budget_choose(rows, 1, 1.0, NULL, d) == HALO_ERROR_INPUT, "chosen");
    return 0;
}

/* No diagnostics list: the loader says what it missed through missing_name. */
CASE(halo_glfuncs_load)
{
    const char *missing = NULL;
    halo_glfuncs f;
    ACCEPTS(halo_glfuncs_load(NULL, sizeof f, halo_headless_get_proc_address, &missing) == 0 && !strcmp(missing, "f"));
    ACCEPTS(halo_glfuncs_load(&f, sizeof f, NULL, &missing) == 0 && !strcmp(missing, "get_proc_address"));
    ACCEPTS(halo_glfuncs_load(NULL, 0, NULL, NULL) == 0);
    /* a table of another header's size is not written */
    memset(&f, 0x5a, sizeof f);
    ACCEPTS(halo_glfuncs_load(&f, sizeof f - sizeof(void (*)(void)), halo_headless_get_proc_address, &missing) == 0 &&
            !strncmp(missing, "size", 4) && ((const unsigned char *)&f)[0] == 0x5a);
    return 0;
}
CASE(halo_gl_create)
{
    REFUSES_D(halo_gl_create(NULL, d) == NULL, "desc");
    REFUSES_D(halo_gl_create(&(halo_gl_desc){0}, d) == NULL, "get_proc_address");
    return 0;
}
CASE(halo_gl_destroy)
{
    ACCEPTS(DONE(halo_gl_destroy(NULL)));
    return 0;
}
CASE(halo_gl_es_version)
{
    ACCEPTS(halo_gl_es_version(NULL) == 0);
    return 0;
}
CASE(halo_gl_program_build)
{
    REFUSES_D(halo_gl_program_build(NULL, program, vertex_source, "v.vert", NULL, d) == 0, "gl");
    halo_gl *gl = fixture_gl();
    if (!gl)
        return 0;
    REFUSES_D(halo_gl_program_build(gl, NULL, vertex_source, "v.vert", NULL, d) == 0, "program");
    REFUSES_D(halo_gl_program_build(gl, program, NULL, "v.vert", NULL, d) == 0, "vertex_source");
    return 0;
}
CASE(halo_gl_program_upload)
{
    REFUSES(DONE(halo_gl_program_upload(NULL, program, 1)), "gl");
    halo_gl *gl = fixture_gl();
    if (!gl)
        return 0;
    REFUSES(DONE(halo_gl_program_upload(gl, NULL, 1)), "program");
    return 0;
}
CASE(halo_gl_set_host_uniform)
{
    const float v[3] = {1, 0, 0};
    REFUSES(halo_gl_set_host_uniform(NULL, 1, "screen_right", v, 3) == HALO_ERROR_INPUT, "gl");
    halo_gl *gl = fixture_gl();
    if (!gl)
        return 0;
    REFUSES(halo_gl_set_host_uniform(gl, 1, NULL, v, 3) == HALO_ERROR_INPUT, "name");
    REFUSES(halo_gl_set_host_uniform(gl, 1, "screen_right", NULL, 3) == HALO_ERROR_INPUT, "values");
    return 0;
}
CASE(halo_gl_frame_create)
{
    REFUSES_D(halo_gl_frame_create(NULL, program, 4, 4, d) == NULL, "gl");
    halo_gl *gl = fixture_gl();
    if (!gl)
        return 0;
    REFUSES_D(halo_gl_frame_create(gl, NULL, 4, 4, d) == NULL, "program");
    return 0;
}
CASE(halo_gl_frame_destroy)
{
    ACCEPTS(DONE(halo_gl_frame_destroy(NULL)));
    return 0;
}
CASE(halo_gl_frame_begin)
{
    REFUSES(DONE(halo_gl_frame_begin(NULL)), "frame");
    return 0;
}
CASE(halo_gl_frame_begin_group)
{
    REFUSES(DONE(halo_gl_frame_begin_group(NULL)), "frame");
    return 0;
}
CASE(halo_gl_frame_end_group)
{
    REFUSES(DONE(halo_gl_frame_end_group(NULL)), "frame");
    return 0;
}
CASE(halo_gl_frame_attach)
{
    REFUSES(DONE(halo_gl_frame_attach(NULL, 0)), "frame");
    return 0;
}
CASE(halo_gl_frame_bind)
{
    REFUSES(DONE(halo_gl_frame_bind(NULL, 1, 0)), "frame");
    return 0;
}
CASE(halo_gl_frame_generate)
{
    REFUSES(DONE(halo_gl_frame_generate(NULL)), "frame");
    return 0;
}
CASE(halo_gl_frame_drawn_region)
{
    REFUSES(DONE(halo_gl_frame_drawn_region(NULL, 0, 0, 1, 1)), "frame");
    return 0;
}
CASE(halo_gl_frame_plan_slice)
{
    int section[4] = {0, 0, 4, 4};
    halo_gl_slice_plan plan;
    REFUSES(halo_gl_frame_plan_slice(NULL, section, 0, &plan) == 0, "frame");
    if (!fixture_gl())
        return 0;
    REFUSES(halo_gl_frame_plan_slice(gl_fixture.frame, NULL, 0, &plan) == 0, "section");
    REFUSES(halo_gl_frame_plan_slice(gl_fixture.frame, section, 0, NULL) == 0, "plan");
    return 0;
}
CASE(halo_gl_frame_describe)
{
    halo_gl_frame_info i;
    REFUSES((i = halo_gl_frame_describe(NULL),
             i.pass_draws == 0 && i.segment_count == 0 && i.read_any == 0 && i.read_box[2] == 0),
            "frame");
    return 0;
}
CASE(halo_gl_frame_set_readback_bounds)
{
    REFUSES(DONE(halo_gl_frame_set_readback_bounds(NULL, 1)), "frame");
    return 0;
}
CASE(halo_gl_frame_post)
{
    REFUSES(DONE(halo_gl_frame_post(NULL, 0)), "frame");
    return 0;
}
CASE(halo_gl_frame_texture)
{
    REFUSES(halo_gl_frame_texture(NULL, "final") == 0, "frame");
    if (!fixture_gl())
        return 0;
    REFUSES(halo_gl_frame_texture(gl_fixture.frame, NULL) == 0, "image");
    return 0;
}
CASE(halo_gl_frame_read)
{
    REFUSES(halo_gl_frame_read(NULL, "final", floats_out) == HALO_ERROR_INPUT, "frame");
    if (!fixture_gl())
        return 0;
    REFUSES(halo_gl_frame_read(gl_fixture.frame, NULL, floats_out) == HALO_ERROR_INPUT, "image");
    REFUSES(halo_gl_frame_read(gl_fixture.frame, "final", NULL) == HALO_ERROR_INPUT, "out");
    return 0;
}
static const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
CASE(halo_gl_set_camera)
{
    const halo_gl_segments_desc desc = {.inverse_view_projection = identity, .step = 0.01f};
    REFUSES_D(halo_gl_set_camera(NULL, 1, &desc, d) == HALO_ERROR_INPUT, "gl");
    halo_gl *gl = fixture_gl();
    if (!gl)
        return 0;
    REFUSES_D(halo_gl_set_camera(gl, 1, NULL, d) == HALO_ERROR_INPUT, "desc");
    REFUSES_D(halo_gl_set_camera(gl, 1, &(halo_gl_segments_desc){.step = 0.01f}, d) == HALO_ERROR_INPUT,
              "inverse_view_projection");
    return 0;
}
CASE(halo_gl_frame_draw)
{
    const halo_gl_segments_desc desc = {.inverse_view_projection = identity, .step = 0.01f};
    REFUSES_D(halo_gl_frame_draw(NULL, 1, &desc, d) == HALO_ERROR_INPUT, "frame");
    if (!fixture_gl())
        return 0;
    REFUSES_D(halo_gl_frame_draw(gl_fixture.frame, 1, NULL, d) == HALO_ERROR_INPUT, "desc");
    return 0;
}
CASE(halo_feature_desc_layout)
{
    /* NULL desc and dims are the defaults and no buffer */
    halo_feature_layout layout;
    ACCEPTS((layout = halo_feature_desc_layout(NULL, NULL)).desc.splat_size == 5);
    CHECK_INT_EQ(layout.buffer_dims[0], 0);
    CHECK_INT_EQ(layout.splat_radius, 2);
    CHECK(layout.splat_weight_sum > 0.0);
    return 0;
}
CASE(halo_feature_desc_from_program)
{
    halo_feature_desc out;
    REFUSES(halo_feature_desc_from_program(NULL, &out) == HALO_ERROR_INPUT, "program");
    REFUSES(halo_feature_desc_from_program(program, NULL) == HALO_ERROR_INPUT, "out");
    return 0;
}
CASE(halo_feature_gradient_magnitudes)
{
    REFUSES(halo_feature_gradient_magnitudes(NULL, dims, floats_out) == HALO_ERROR_INPUT, "values");
    REFUSES(halo_feature_gradient_magnitudes(volume, NULL, floats_out) == HALO_ERROR_INPUT, "dims");
    REFUSES(halo_feature_gradient_magnitudes(volume, dims, NULL) == HALO_ERROR_INPUT, "out");
    return 0;
}
CASE(halo_feature_compute)
{
    for (int r = HALO_FEATURE_REFERENCE; r <= HALO_FEATURE_EMULATED_BUFFER; ++r) {
        REFUSES(halo_feature_compute(r, NULL, dims, NULL, view, doubles_out) == HALO_ERROR_INPUT, "values");
        REFUSES(halo_feature_compute(r, volume, NULL, NULL, view, doubles_out) == HALO_ERROR_INPUT, "dims");
        REFUSES(halo_feature_compute(r, volume, dims, NULL, NULL, doubles_out) == HALO_ERROR_INPUT, "view");
        REFUSES(halo_feature_compute(r, volume, dims, NULL, view, NULL) == HALO_ERROR_INPUT, "out");
    }
    return 0;
}
CASE(halo_feature_buffer_lookup)
{
    const double position[3] = {0.5, 0.5, 0.5};
    REFUSES(halo_feature_buffer_lookup(NULL, dims, position) == 0.0, "buffer");
    REFUSES(halo_feature_buffer_lookup(doubles_out, NULL, position) == 0.0, "dims");
    REFUSES(halo_feature_buffer_lookup(doubles_out, dims, NULL) == 0.0, "position");
    return 0;
}
CASE(halo_feature_buffer_create)
{
    REFUSES_D(halo_feature_buffer_create(NULL, volume, dims, NULL, d) == NULL, "gl");
    halo_gl *gl = fixture_gl();
    if (!gl)
        return 0;
    REFUSES_D(halo_feature_buffer_create(gl, NULL, dims, NULL, d) == NULL, "values");
    REFUSES_D(halo_feature_buffer_create(gl, volume, NULL, NULL, d) == NULL, "dims");
    return 0;
}
CASE(halo_feature_buffer_destroy)
{
    ACCEPTS(DONE(halo_feature_buffer_destroy(NULL)));
    return 0;
}
CASE(halo_feature_buffer_build)
{
    REFUSES(halo_feature_buffer_build(NULL, view) == HALO_ERROR_INPUT, "buffer");
    if (!fixture_gl())
        return 0;
    REFUSES(halo_feature_buffer_build(gl_fixture.buffer, NULL) == HALO_ERROR_INPUT, "view");
    return 0;
}
CASE(halo_feature_buffer_describe)
{
    halo_feature_buffer_info i;
    REFUSES((i = halo_feature_buffer_describe(NULL),
             i.texture == 0 && i.dims[0] == 0 && i.qualified == 0 && i.points_drawn == 0),
            "buffer");
    return 0;
}
CASE(halo_feature_buffer_read)
{
    REFUSES(halo_feature_buffer_read(NULL, floats_out) == HALO_ERROR_INPUT, "buffer");
    if (!fixture_gl())
        return 0;
    REFUSES(halo_feature_buffer_read(gl_fixture.buffer, NULL) == HALO_ERROR_INPUT, "out");
    return 0;
}
// clang-format on

/* ---- The table: every HALO_API function, in the headers' order ---- */

typedef int (*case_fn)(const char *fn, halo_diagnostics *d);
typedef struct api_case {
    const char *name;
    case_fn run; /* NULL: the function takes no pointer */
} api_case;

#define ROW(name)          \
    {                      \
#name, case_##name \
    }
#define NO_POINTER(name) \
    {                    \
#name, NULL      \
    }

static const api_case cases[] = {
    NO_POINTER(halo_diagnostics_create),
    ROW(halo_diagnostics_destroy),
    ROW(halo_diagnostics_describe),
    ROW(halo_diagnostics_get),
    ROW(halo_diagnostics_has),
    ROW(halo_diagnostics_clear),
    ROW(halo_diagnostics_report),
    ROW(halo_read_text_file),
    ROW(halo_diagnostics_print),
    NO_POINTER(halo_message_name),
    ROW(halo_diagnostics_set_limit),
    ROW(halo_diagnostics_set_run),
    ROW(halo_setup),
    NO_POINTER(halo_shutdown),
    NO_POINTER(halo_version),
    NO_POINTER(halo_target_name),
    ROW(halo_target_from_name),
    ROW(halo_library_create),
    ROW(halo_library_destroy),
    ROW(halo_library_add),
    ROW(halo_library_describe),
    ROW(halo_library_find),
    ROW(halo_module_describe),
    ROW(halo_module_find_param),
    ROW(halo_scene_load),
    ROW(halo_scene_create),
    ROW(halo_scene_destroy),
    ROW(halo_scene_enable),
    ROW(halo_scene_set),
    ROW(halo_scene_describe),
    ROW(halo_scene_set_render),
    ROW(halo_link),
    ROW(halo_program_destroy),
    ROW(halo_program_source),
    ROW(halo_program_map_line),
    ROW(halo_program_reflection),
    ROW(halo_program_find_uniform),
    ROW(halo_program_set),
    ROW(halo_pass_reach),
    ROW(halo_program_select_group),
    ROW(halo_program_reflect_json),
    ROW(halo_validate),
    ROW(halo_source_kind_of),
    ROW(halo_emu_apply),
    ROW(halo_emu_frame_create),
    ROW(halo_emu_frame_destroy),
    ROW(halo_emu_frame_image),
    ROW(halo_emu_frame_set_host_uniform),
    ROW(halo_emu_frame_begin),
    ROW(halo_emu_frame_begin_group),
    ROW(halo_emu_frame_end_group),
    ROW(halo_emu_frame_finish),
    ROW(halo_emu_frame_generate),
    ROW(halo_emu_frame_post),
    ROW(halo_emu_frame_set_volume),
    ROW(halo_budget_choose),
    ROW(halo_glfuncs_load),
    ROW(halo_gl_create),
    ROW(halo_gl_destroy),
    ROW(halo_gl_es_version),
    ROW(halo_gl_program_build),
    ROW(halo_gl_program_upload),
    ROW(halo_gl_set_host_uniform),
    ROW(halo_gl_frame_create),
    ROW(halo_gl_frame_destroy),
    ROW(halo_gl_frame_begin),
    ROW(halo_gl_frame_begin_group),
    ROW(halo_gl_frame_end_group),
    ROW(halo_gl_frame_attach),
    ROW(halo_gl_frame_bind),
    ROW(halo_gl_frame_generate),
    ROW(halo_gl_frame_drawn_region),
    ROW(halo_gl_frame_describe),
    ROW(halo_gl_frame_plan_slice),
    ROW(halo_gl_frame_set_readback_bounds),
    ROW(halo_gl_frame_post),
    ROW(halo_gl_frame_texture),
    ROW(halo_gl_frame_read),
    ROW(halo_gl_set_camera),
    ROW(halo_gl_frame_draw),
    ROW(halo_feature_desc_layout),
    ROW(halo_feature_desc_from_program),
    ROW(halo_feature_gradient_magnitudes),
    ROW(halo_feature_compute),
    ROW(halo_feature_buffer_lookup),
    ROW(halo_feature_buffer_create),
    ROW(halo_feature_buffer_destroy),
    ROW(halo_feature_buffer_build),
    ROW(halo_feature_buffer_describe),
    ROW(halo_feature_buffer_read),
};
#define CASE_COUNT (sizeof cases / sizeof cases[0])

/* ---- The table against the headers ---- */

static const api_case *find_case(const char *name)
{
    for (size_t i = 0; i < CASE_COUNT; i++)
        if (!strcmp(cases[i].name, name))
            return &cases[i];
    return NULL;
}

/* Appends the name of each function declared HALO_API in path (the first halo_
 * identifier followed by '(' on a HALO_API line) to names; returns how many, -1 when
 * the file cannot be read. */
static int header_functions(const char *path, char names[][64], int max)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    char line[1024];
    int n = 0;
    while (fgets(line, sizeof line, f)) {
        const char *api = strstr(line, "HALO_API");
        if (!api || line[strspn(line, " \t")] == '#')
            continue;
        for (const char *p = api; (p = strstr(p, "halo_")); p++) {
            size_t len = strspn(p, "abcdefghijklmnopqrstuvwxyz0123456789_");
            if (p[len] == '(' && (p == line || !strchr("abcdefghijklmnopqrstuvwxyz0123456789_", p[-1]))) {
                if (n < max)
                    snprintf(names[n], sizeof names[n], "%.*s", (int)len, p);
                n++;
                break;
            }
        }
    }
    fclose(f);
    return n;
}

static char names[2 * CASE_COUNT + 64][64];

static int test_table_matches_headers(void)
{
    const char *srcdir = getenv("srcdir");
    if (!srcdir)
        srcdir = ".";
    static const char *const headers[] = {"libhalo/halo.h", "libhalo/halo_feature.h", "libhalo/halo_gl_loader.h"};
    int total = 0, max = (int)(sizeof names / sizeof names[0]);
    for (size_t h = 0; h < sizeof headers / sizeof headers[0]; h++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", srcdir, headers[h]);
        int n = header_functions(path, names + total, max - total);
        if (n < 0)
            SETUP_FAIL("cannot read %s", path);
        total += n;
    }
    int missing = 0;
    for (int i = 0; i < total && i < max; i++)
        if (!find_case(names[i])) {
            fprintf(stderr, "    %s is public but has no row in this test's table: add its NULL cases\n", names[i]);
            missing++;
        }
    for (size_t c = 0; c < CASE_COUNT; c++) {
        int found = 0;
        for (int i = 0; i < total && i < max && !found; i++)
            found = !strcmp(names[i], cases[c].name);
        if (!found) {
            fprintf(stderr, "    %s has a row but is not declared HALO_API in the headers\n", cases[c].name);
            missing++;
        }
    }
    printf("     %d public functions in the headers, %zu rows in the table\n", total, CASE_COUNT);
    CHECK_INT_EQ(missing, 0);
    CHECK_INT_EQ(total, (long long)CASE_COUNT);
    return 0;
}

/* ---- Running the rows ---- */

static int run_case_here(const api_case *c)
{
    halo_diagnostics *d = halo_diagnostics_create();
    SETUP(d != NULL);
    int failed = c->run(c->name, d) || c->run(c->name, NULL);
    halo_diagnostics_destroy(d);
    return failed;
}

static int test_every_function_refuses_null(void)
{
    int failed = 0, crashed = 0, checked = 0, skipped = 0;
    for (size_t i = 0; i < CASE_COUNT; i++) {
        const api_case *c = &cases[i];
        if (!c->run)
            continue;
        checked++;
        fflush(stdout);
        fflush(stderr);
        pid_t pid = fork();
        if (pid < 0)
            SETUP_FAIL("fork failed");
        if (pid == 0) {
            int r = run_case_here(c);
            fflush(stdout);
            fflush(stderr);
            _exit(r ? 1 : gl_skipped ? 77 : 0);
        }
        int status = 0;
        if (waitpid(pid, &status, 0) != pid)
            SETUP_FAIL("waitpid failed");
        if (WIFSIGNALED(status)) {
            printf("CRASH %s (signal %d: %s)\n", c->name, WTERMSIG(status), strsignal(WTERMSIG(status)));
            crashed++;
        } else if (WEXITSTATUS(status) == 77) {
            printf("ok   %s (calls with a valid GL runtime skipped: no headless context)\n", c->name);
            skipped++;
        } else if (WEXITSTATUS(status)) {
            printf("FAIL %s (exit %d)\n", c->name, WEXITSTATUS(status));
            failed++;
        }
    }
    printf("     %d functions with pointer arguments called: %d failed, %d crashed, %d without GL calls\n", checked,
           failed, crashed, skipped);
    CHECK_INT_EQ(failed + crashed, 0);
    return 0;
}

int main(void)
{
    const char *srcdir = getenv("srcdir");
    if (!srcdir)
        srcdir = ".";
    snprintf(module_path, sizeof module_path, "%s/glsl/sample/boundary.glsl", srcdir);
    snprintf(scene_path, sizeof scene_path, "%s/examples/scenes/boundary-silhouette.json", srcdir);
    SETUP(halo_setup(&(halo_setup_desc){.logger = logger}) == HALO_OK);
    halo_diagnostics *d;
    lib = check_library_setup(&d);
    module = halo_library_find(lib, "boundary");
    SETUP(module != NULL);
    scene = halo_scene_load("null.json", "{\"halo_scene\": 1, \"stages\": [{\"boundary\": {\"live\": [\"k_gc\"]}}]}",
                            lib, d);
    SETUP(scene != NULL);
    program = halo_link(&(halo_link_desc){.library = lib, .scene = scene, .host_source = check_sample_host}, d);
    SETUP(program != NULL);
    emu_frame = halo_emu_frame_create(program, 4, 4, d);
    SETUP(emu_frame != NULL);
    for (int i = 0; i < 64; i++)
        volume[i] = (float)(i % 4) / 3.0f;
    RUN_TEST(test_table_matches_headers);
    RUN_TEST(test_every_function_refuses_null);
    halo_emu_frame_destroy(emu_frame);
    halo_program_destroy(program);
    halo_scene_destroy(scene);
    halo_library_destroy(lib);
    halo_diagnostics_destroy(d);
    halo_shutdown();
    return check_exit_status();
}
