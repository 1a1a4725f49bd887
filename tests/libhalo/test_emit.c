/* libhalo/emit.c: the text the linker writes into the host: the names modules use
 * privately, fixed parameters as constants and live ones as uniforms, and the line map
 * that brings every line (and glslang's errors) back to its origin. No GL. */
#include "link_fixture.h"

/* (c) The host may use the names that modules use privately. */
static int test_renaming(void)
{
    static const char host[] =
        "#version 330 core\n"
        "#pragma halo declarations\n"
        "const float k_gs = 1.0;\n"                     /* a parameter of boundary */
        "const float k_ss = 2.0;\n"                     /* of silhouette */
        "uniform vec3 colors[2];\n"                     /* of distance_cue */
        "uniform vec3 background;\n"                    /* of distance_blend */
        "float apply(float x) { return x * k_gs; }\n"   /* every stage's entry */
        "vec3 depth_map(float d) { return vec3(d); }\n" /* distance_cue's private helper */
        "float weight(float x) { return x; }\n"         /* a user module's private helper */
        "out vec4 fragment_color;\n"
        "void main()\n"
        "{\n"
        "    vec4 color = vec4(depth_map(0.5) + colors[1] + background, apply(0.5) * k_ss * weight(1.0));\n"
        "    halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.1), vec3(0.0, 0.0, 1.0), 0.5,\n"
        "                                     gl_FragCoord.xy, color.rgb, color.a);\n"
        "    halo_apply(s);\n"
        "    fragment_color = vec4(s.color, s.opacity);\n"
        "}\n";
    /* The private names the host reuses must really be private names of the modules. */
    const halo_module *cue = halo_library_find(library, "distance_cue");
    SETUP(cue && halo_name_list_has(&cue->declared, "depth_map"));
    SETUP(halo_name_list_has(&halo_library_find(library, "weight_a")->declared, "weight"));
    halo_scene *scene = scene_of(
        "{\"stages\": [\"boundary\", \"silhouette\", \"distance_cue\", \"distance_blend\","
        " \"weight_a\", \"weight_b\"]}");
    for (int live = 0; live < 2; live++) {
        halo_program *p = link_with(scene, host, HALO_TARGET_DEFAULT, live);
        CHECK(p != NULL);
        CHECK_NO_ERRORS(diags);
        if (halo_validate(&(halo_validate_desc){.program = p}, diags) != HALO_OK) {
            check_print_diags(diags);
            fprintf(stderr, "%s", halo_program_source(p, HALO_PIECE_WHOLE));
            CHECK_FAIL_AT("renamed program does not validate (all_live = %d)", live);
        }
        CHECK_STR_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "halo_distance_cue_depth_map(");
        CHECK_STR_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "halo_weight_a_weight(");
        CHECK_STR_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "halo_weight_b_weight(");
        CHECK_STR_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "halo_boundary_apply(s);");
        halo_program_destroy(p);
    }
    halo_scene_destroy(scene);
    return 0;
}


/* (d) Fixed parameters are constants, live ones uniforms. */
static int test_constants_and_uniforms(void)
{
    halo_program *p = link_valid(
        "{\"stages\": [{\"boundary\": {\"k_gs\": 12.5, \"live\": [\"k_gc\"]}},"
        " {\"tone_shading\": {\"lights\": [[1,0,0],[0,1,0]]}}]}");
    CHECK(p != NULL);
    const char *src = halo_program_source(p, HALO_PIECE_WHOLE);
    CHECK_STR_CONTAINS(src, "uniform float halo_boundary_k_gc;");
    CHECK_STR_NOT_CONTAINS(src, "const float halo_boundary_k_gc");
    CHECK_STR_CONTAINS(src, "const float halo_boundary_k_gs = 12.5;");
    CHECK_STR_NOT_CONTAINS(src, "uniform float halo_boundary_k_gs");
    CHECK_STR_CONTAINS(src, "const float halo_boundary_k_ge = 2.0;");
    CHECK_STR_CONTAINS(src, "const int halo_tone_shading_lights_count = 2;");
    CHECK_STR_CONTAINS(src, "const vec3 halo_tone_shading_lights[2]");
    const halo_uniform_info *u = halo_program_find_uniform(p, "boundary", "k_gc");
    CHECK(u != NULL);
    CHECK_INT_EQ(u->live, 1);
    CHECK_STR_EQ(u->name, "halo_boundary_k_gc");
    CHECK_STR_EQ(u->stage, "boundary");
    CHECK_STR_EQ(u->param, "k_gc");
    CHECK_NEAR(u->value[0], 0.7, 0);
    u = halo_program_find_uniform(p, "boundary", "k_gs");
    CHECK(u != NULL);
    CHECK_INT_EQ(u->live, 0);
    CHECK_NEAR(u->value[0], 12.5, 0);
    u = halo_program_find_uniform(p, "tone_shading", "lights");
    CHECK_INT_EQ(u->count, 2);
    CHECK(halo_program_find_uniform(p, "boundary", "nope") == NULL);
    /* The reflection lists the live one among the uniforms. */
    char *json = halo_program_reflect_json(p);
    CHECK(json != NULL);
    CHECK_STR_CONTAINS(json, "halo_boundary_k_gc");
    free(json);
    halo_program_destroy(p);

    /* all_live: every parameter a uniform, arrays at full size with a count. */
    halo_scene *scene = scene_of("{\"stages\": [{\"boundary\": {\"k_gs\": 12.5}}, \"tone_shading\"]}");
    p = link_with(scene, host_source, HALO_TARGET_DEFAULT, 1);
    halo_scene_destroy(scene);
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p}, diags), HALO_OK);
    src = halo_program_source(p, HALO_PIECE_WHOLE);
    CHECK_STR_NOT_CONTAINS(src, "const float halo_");
    CHECK_STR_NOT_CONTAINS(src, "const int halo_");
    CHECK_STR_NOT_CONTAINS(src, "const vec3 halo_");
    CHECK_STR_CONTAINS(src, "uniform float halo_boundary_k_gs;");
    CHECK_STR_CONTAINS(src, "uniform vec3 halo_tone_shading_lights[4];");
    CHECK_STR_CONTAINS(src, "uniform int halo_tone_shading_lights_count;");
    CHECK(halo_program_reflection(p).uniform_count >= 3 + 5 + 0);
    for (size_t i = 0; i < halo_program_reflection(p).uniform_count; i++) {
        const halo_uniform_info *w = &halo_program_reflection(p).uniforms[i];
        CHECK_INT_EQ(w->live, 1);
        CHECK(w->info != NULL);
    }
    CHECK_NEAR(halo_program_find_uniform(p, "boundary", "k_gs")->value[0], 12.5, 0);
    halo_program_destroy(p);
    return 0;
}


/* (h) Every emitted line maps back to its origin. */
static int test_line_map(void)
{
    halo_program *p = link_valid("{\"stages\": [\"boundary\", \"tone_shading\", \"distance_cue\"]}");
    CHECK(p != NULL);
    const char *src = halo_program_source(p, HALO_PIECE_WHOLE);
    static const char *const statements[][2] = {
        {"boundary", "s.opacity = halo_saturate(s.opacity * enhancement);"},
        {"tone_shading", "float toward = (1.0 + n_dot_l) * 0.5;"},
        {"distance_cue", "if (i > "},
    };
    for (size_t i = 0; i < 3; i++) {
        const halo_module *m = halo_library_find(library, statements[i][0]);
        int module_line = 0;
        for (int l = 0; l < m->line_count && !module_line; l++)
            if (strstr(m->lines[l], statements[i][1]))
                module_line = l + 1;
        SETUP(module_line > 0);
        int out = line_containing(src, statements[i][1]);
        CHECK(out > 0);
        const char *file = NULL;
        int line = 0;
        CHECK_INT_EQ(halo_program_map_line(p, HALO_PIECE_WHOLE, out, &file, &line), 1);
        CHECK_STR_EQ(file, halo_module_describe(m).file);
        CHECK_INT_EQ(line, module_line);
    }
    /* A parameter maps to its annotation. */
    int out = line_containing(src, "const float halo_boundary_k_gs");
    const halo_module *boundary = halo_library_find(library, "boundary");
    const char *file = NULL;
    int line = 0;
    CHECK_INT_EQ(halo_program_map_line(p, HALO_PIECE_WHOLE, out, &file, &line), 1);
    CHECK_STR_EQ(file, "glsl/sample/boundary.glsl");
    CHECK_STR_CONTAINS(boundary->lines[line - 1], "param k_gs");
    /* A helper maps to halo_math.glsl. */
    out = line_containing(src, "float halo_pow(");
    CHECK_INT_EQ(halo_program_map_line(p, HALO_PIECE_WHOLE, out, &file, &line), 1);
    CHECK_STR_EQ(file, "glsl/halo_math.glsl");
    CHECK_STR_CONTAINS(halo_library_find(library, "halo_math")->lines[line - 1], "float halo_pow(");
    /* Host lines map to themselves, with the same text (but #version and the marker). */
    char *host_copy = strdup(host_source), *text_copy = strdup(src);
    char **host_lines = NULL, **lines = NULL;
    int host_count = halo_split_lines(host_copy, &host_lines), count = halo_split_lines(text_copy, &lines);
    SETUP(host_count > 0 && count > 0);
    unsigned char seen[64] = {0};
    SETUP(host_count < 64);
    for (int l = 1; l <= count; l++) {
        if (!halo_program_map_line(p, HALO_PIECE_WHOLE, l, &file, &line) || strcmp(file, "test.frag"))
            continue;
        CHECK(line >= 1 && line <= host_count);
        seen[line] = 1;
        if (line == 1 || line == 3)
            continue;
        CHECK_STR_EQ(lines[l - 1], host_lines[line - 1]);
    }
    for (int l = 1; l <= host_count; l++)
        if (!seen[l] && host_lines[l - 1][0])
            CHECK_FAIL_AT("host line %d is not in the linked text", l);
    free(host_lines);
    free(lines);
    free(host_copy);
    free(text_copy);
    /* Generated lines have no origin; out-of-range lines neither. */
    CHECK_INT_EQ(halo_program_map_line(p, HALO_PIECE_WHOLE, line_containing(src, "struct halo_sample {"), &file, &line),
                 0);
    CHECK_INT_EQ(halo_program_map_line(p, HALO_PIECE_WHOLE, 0, &file, &line), 0);
    CHECK_INT_EQ(halo_program_map_line(p, HALO_PIECE_WHOLE, 1000000, &file, &line), 0);
    halo_program_destroy(p);
    return 0;
}


/* (i) glslang's errors come back at the module's or the host's own line. */
static int test_glsl_errors_mapped(void)
{
    halo_scene *scene = scene_of("{\"stages\": [\"type_error\"]}");
    halo_program *p = link_with(scene, host_source, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p}, diags), HALO_ERROR_INPUT);
    const halo_diagnostic *g = check_find_diag(diags, HALO_MSG_GLSL_ERROR, 7);
    if (!g)
        check_print_diags(diags);
    CHECK(g != NULL);
    CHECK_STR_EQ(g->file, "user/type_error.glsl");
    CHECK(g->column >= 1);
    CHECK(g->source_line != NULL);
    CHECK_STR_CONTAINS(g->source_line, "vec3(1.0)");
    halo_program_destroy(p);

    static const char host[] =
        "#version 330 core\n"                              /* 1 */
        "#pragma halo declarations\n"                      /* 2 */
        "out vec4 c;\n"                                    /* 3 */
        "void main()\n"                                    /* 4 */
        "{\n"                                              /* 5 */
        "    float y = vec2(1.0);\n"                       /* 6 */
        "    halo_sample s; halo_apply(s); c = vec4(y);\n" /* 7 */
        "}\n";
    scene = scene_of("{\"stages\": [\"boundary\", \"tone_shading\"]}");
    p = link_with(scene, host, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p}, diags), HALO_ERROR_INPUT);
    g = check_find_diag(diags, HALO_MSG_GLSL_ERROR, 6);
    if (!g)
        check_print_diags(diags);
    CHECK(g != NULL);
    CHECK_STR_EQ(g->file, "test.frag");
    /* Every error is at the host's or a module's line, none at the linked text's. */
    for (size_t i = 0; i < halo_diagnostics_describe(diags).count; i++)
        CHECK_STR_EQ(halo_diagnostics_get(diags, i)->file, "test.frag");
    halo_program_destroy(p);
    return 0;
}


int main(void)
{
    link_fixture_setup();
    RUN_TEST(test_renaming);
    RUN_TEST(test_constants_and_uniforms);
    RUN_TEST(test_line_map);
    RUN_TEST(test_glsl_errors_mapped);
    return link_fixture_finish();
}
