/* Lifetimes and bounds in the API (issue 26): sizes and counts a caller or a module
 * can make absurd are refused or clamped without overflow, and names of any length are
 * renamed as short ones are. Message ids, never wording. No GL; no glslang. */
#include "check.h"

#include <limits.h>

static halo_library *library;
static halo_diagnostics *diags;

/* Links the scene text (stages of the library) into the sample host; NULL on errors. */
static halo_program *link_scene(const char *json)
{
    halo_diagnostics_clear(diags);
    halo_scene *scene = halo_scene_load("bounds.json", json, library, diags);
    if (!scene)
        return NULL;
    halo_program *p = halo_link(
        &(halo_link_desc){
            .library = library, .scene = scene, .host_source = check_sample_host, .host_file = "host.frag"},
        diags);
    halo_scene_destroy(scene);
    return p;
}

static int test_emu_frame_size(void)
{
    halo_program *p = link_scene("{\"halo_scene\": 1, \"stages\": []}");
    SETUP(p != NULL);
    static const int sizes[][2] = {{INT_MAX, INT_MAX}, {HALO_MAX_FRAME_SIDE + 1, 1}, {1, INT_MAX}, {0, 4}, {4, -1}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        halo_diagnostics_clear(diags);
        halo_emu_frame *f = halo_emu_frame_create(p, sizes[i][0], sizes[i][1], diags);
        if (f) {
            halo_emu_frame_destroy(f);
            halo_program_destroy(p);
            CHECK_FAIL_AT("halo_emu_frame_create(%d, %d) made a frame", sizes[i][0], sizes[i][1]);
        }
        if (!halo_diagnostics_has(diags, HALO_MSG_USAGE)) {
            check_print_diags(diags);
            halo_program_destroy(p);
            CHECK_FAIL_AT("halo_emu_frame_create(%d, %d): no USAGE diagnostic", sizes[i][0], sizes[i][1]);
        }
    }
    halo_emu_frame *ok = halo_emu_frame_create(p, 8, 8, diags);
    halo_emu_frame_destroy(ok);
    halo_program_destroy(p);
    CHECK(ok != NULL);
    return 0;
}

/* An image module whose pass repeats `n` times and reaches 2^(m - i) pixels. */
static halo_status add_pass_module(const char *name, const char *n_param, const char *m_param)
{
    char source[2048];
    snprintf(source, sizeof source,
             "#pragma halo module %s\n"
             "#pragma halo hook image\n"
             "#pragma halo provides %s_field image\n"
             "#pragma halo image %s_field\n"
             "#pragma halo param n int %s \"repetitions\"\n"
             "#pragma halo param m int %s \"reach exponent\"\n"
             "#pragma halo pass grow entry=grow_pass inputs=previous output=%s_field repeat=n reach=2^(m-i)\n"
             "halo_channels grow_pass(ivec2 p) { return halo_input(0, p); }\n",
             name, name, name, n_param, m_param, name);
    halo_diagnostics_clear(diags);
    return halo_library_add(library, name, source, HALO_ADD_NEW, diags);
}

static int test_repeat_bound(void)
{
    /* no max, or one past the bound: 2147483647 draws a generation would pass */
    CHECK_INT_EQ(add_pass_module("unbounded_repeat", "default=2", "default=1"), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_PASS_INVALID);
    CHECK_INT_EQ(add_pass_module("huge_repeat", "default=2 min=1 max=2147483647", "default=1"), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_PASS_INVALID);
    CHECK_INT_EQ(add_pass_module("bounded_repeat", "default=2 min=1 max=8", "default=1 min=-4 max=40"), HALO_OK);
    CHECK_NO_ERRORS(diags);
    return 0;
}

static int test_pass_reach(void)
{
    /* exponents and repetitions far past 2^30: clamped, never an overflow (before: 0) */
    halo_pass_info pass = {.reach = 0, .reach_exponent = INT_MAX, .reach_factor = 1, .reach_base = 4};
    CHECK_INT_EQ(halo_pass_reach(&pass, 0), 1 << 30);
    CHECK_INT_EQ(halo_pass_reach(&pass, INT_MIN), 1 << 30);
    pass.reach_base = 2;
    pass.reach_exponent = 0;
    CHECK_INT_EQ(halo_pass_reach(&pass, INT_MIN), 1 << 30);
    CHECK_INT_EQ(halo_pass_reach(&pass, INT_MAX), 1);
    pass.reach_exponent = 31;
    CHECK_INT_EQ(halo_pass_reach(&pass, 0), 1 << 30);
    pass = (halo_pass_info){.reach = INT_MAX, .reach_exponent = 30, .reach_factor = INT_MAX, .reach_base = 4};
    CHECK_INT_EQ(halo_pass_reach(&pass, 1), 1 << 30);
    pass = (halo_pass_info){.reach = 3, .reach_exponent = 4, .reach_factor = 1, .reach_base = 2};
    CHECK_INT_EQ(halo_pass_reach(&pass, 1), 3 + 8);

    /* a reach exponent parameter of -1 is B^0 = 1, not "no exponent" (before: the reach was K = 0) */
    SETUP(add_pass_module("reach_minus_one", "default=1 min=1 max=8", "default=1 min=-4 max=40") == HALO_OK);
    halo_program *p = link_scene("{\"halo_scene\": 1, \"stages\": [{\"reach_minus_one\": {\"m\": -1}}]}");
    if (!p)
        check_print_diags(diags);
    CHECK(p != NULL);
    const halo_pass_info *grow = NULL;
    for (size_t i = 0; i < halo_program_reflection(p).pass_count; i++)
        if (!strcmp(halo_program_reflection(p).passes[i].name, "grow"))
            grow = &halo_program_reflection(p).passes[i];
    int reach = grow ? halo_pass_reach(grow, 1) : -2, exponent = grow ? grow->reach_exponent : -2;
    halo_program_destroy(p);
    CHECK(grow != NULL);
    CHECK_INT_EQ(reach, 1);
    CHECK_INT_NE(exponent, -1);
    return 0;
}

static int test_first_output_location(void)
{
    static const int bad[] = {INT_MAX, HALO_MAX_OUTPUT_LOCATION + 1, -1, INT_MIN};
    halo_scene *scene = halo_scene_create(library);
    SETUP(scene != NULL);
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        halo_diagnostics_clear(diags);
        halo_pieces_desc pieces = {.gradient = "vec3(0.0)", .first_output_location = bad[i]};
        halo_program *p = halo_link(&(halo_link_desc){.library = library, .scene = scene, .pieces = &pieces}, diags);
        if (p) {
            halo_program_destroy(p);
            halo_scene_destroy(scene);
            CHECK_FAIL_AT("first_output_location = %d linked", bad[i]);
        }
        if (!halo_diagnostics_has(diags, HALO_MSG_USAGE)) {
            check_print_diags(diags);
            halo_scene_destroy(scene);
            CHECK_FAIL_AT("first_output_location = %d: no USAGE diagnostic", bad[i]);
        }
    }
    halo_diagnostics_clear(diags);
    halo_pieces_desc pieces = {.gradient = "vec3(0.0)", .first_output_location = HALO_MAX_OUTPUT_LOCATION};
    halo_program *ok = halo_link(&(halo_link_desc){.library = library, .scene = scene, .pieces = &pieces}, diags);
    halo_program_destroy(ok);
    halo_scene_destroy(scene);
    if (!ok)
        check_print_diags(diags);
    CHECK(ok != NULL);
    return 0;
}

/* output_locations past the enum: refused with USAGE, with host text and with pieces. */
static int test_output_locations(void)
{
    halo_scene *scene = halo_scene_create(library);
    SETUP(scene != NULL);
    static const char host[] = "#version 330 core\n#pragma halo declarations\nvoid main() {}\n";
    halo_pieces_desc pieces = {.gradient = "vec3(0.0)"};
    for (int with_pieces = 0; with_pieces < 2; ++with_pieces) {
        halo_diagnostics_clear(diags);
        halo_program *p = halo_link(&(halo_link_desc){.library = library,
                                                      .scene = scene,
                                                      .host_source = with_pieces ? NULL : host,
                                                      .pieces = with_pieces ? &pieces : NULL,
                                                      .output_locations = HALO_LOCATIONS_COUNT},
                                    diags);
        halo_program_destroy(p);
        CHECK(p == NULL);
        CHECK_DIAG(diags, HALO_MSG_USAGE);
    }
    halo_scene_destroy(scene);
    return 0;
}

/* A global and an array parameter with names of 150 characters: renamed as short ones are. */
static int test_long_identifiers(void)
{
    char global[151], array[151], source[4096], json[512];
    memset(global, 'g', 150);
    global[150] = '\0';
    memset(array, 'a', 150);
    array[150] = '\0';
    snprintf(source, sizeof source,
             "#pragma halo module long_names\n"
             "#pragma halo hook sample\n"
             "#pragma halo param %s float[4] default=[0.25, 0.5] min=0 max=1 \"weights\"\n"
             "float %s = 0.5;\n"
             "void apply(inout halo_sample s) { s.opacity *= %s * %s[%s_count - 1]; }\n",
             array, global, global, array, array);
    halo_diagnostics_clear(diags);
    SETUP(halo_library_add(library, "long_names.glsl", source, HALO_ADD_NEW, diags) == HALO_OK);
    snprintf(json, sizeof json, "{\"halo_scene\": 1, \"stages\": [\"long_names\"]}");
    halo_program *p = link_scene(json);
    if (!p)
        check_print_diags(diags);
    CHECK(p != NULL);
    const char *text = halo_program_source(p, HALO_PIECE_WHOLE);
    char want[512]; /* two names of up to 150 bytes and the text around them */
    int failed = 0;
    snprintf(want, sizeof want, "float halo_long_names_%s = 0.5;", global);
    if (!strstr(text, want))
        failed = 1; /* the global stays private */
    snprintf(want, sizeof want, "const int halo_long_names_%s_count = 2;", array);
    if (!strstr(text, want))
        failed |= 2; /* the array keeps its _count */
    snprintf(want, sizeof want, "halo_long_names_%s[halo_long_names_%s_count - 1]", array, array);
    if (!strstr(text, want))
        failed |= 4;
    if (failed)
        fprintf(stderr, "%s\n", text);
    halo_program_destroy(p);
    if (failed)
        CHECK_FAIL_AT("long names not renamed (mask %d: 1 the global, 2 the _count, 4 the use)", failed);
    return 0;
}

int main(void)
{
    static const check_test tests[] = {
        CHECK_TEST(test_emu_frame_size),        CHECK_TEST(test_repeat_bound),     CHECK_TEST(test_pass_reach),
        CHECK_TEST(test_first_output_location), CHECK_TEST(test_output_locations), CHECK_TEST(test_long_identifiers),
    };
    return check_main_with_library(&library, &diags, tests, sizeof tests / sizeof tests[0]);
}
