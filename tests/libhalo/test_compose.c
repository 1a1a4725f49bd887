/* Link modes for shader composers (libhalo/compose.c, docs/composers.md): pieces
 * without host text, a template composed here in the style of a tag-replacing engine
 * (written for this test), validation of the composed shader with errors mapped back,
 * engine-declared uniforms, GLSL 150, and the #version modes. No GL. */
#include "check.h"
#include "internal.h"

static halo_library *library;
static halo_diagnostics *diags;

/* An engine's template: its own declarations, then tags it replaces with code. */
static const char engine_template[] =
    "#version 150\n"                                                        /* 1 */
    "uniform sampler3D volume_textures[2];\n"                               /* 2 */
    "uniform vec3 step_size;\n"                                             /* 3 */
    "out vec4 frag_output_0;\n"                                             /* 4 */
    "//ENGINE::Uniforms\n"                                                  /* 5 */
    "//ENGINE::Declarations\n"                                              /* 6 */
    "void main() {\n"                                                       /* 7 */
    "    vec3 ray_position = vec3(0.5);\n"                                  /* 8 */
    "    vec4 sample_color = vec4(0.0);\n"                                  /* 9 */
    "    for (int i = 0; i < 8; ++i) {\n"                                   /* 10 */
    "        float scalar = texture(volume_textures[0], ray_position).r;\n" /* 11 */
    "        sample_color = vec4(scalar, scalar, scalar, 0.1);\n"           /* 12 */
    "//ENGINE::Sample\n"                                                    /* 13 */
    "        ray_position += step_size;\n"                                  /* 14 */
    "    }\n"                                                               /* 15 */
    "//ENGINE::Finish\n"                                                    /* 16 */
    "    frag_output_0 = sample_color;\n"                                   /* 17 */
    "}\n";

static const halo_pieces_desc engine_names = {
    .position = "ray_position", .value = "scalar", .color = "sample_color", .volume = "volume_textures[0]"};

/* A per-sample user module with a bool, an array and a vector parameter. */
static const char user_module[] =
    "#pragma halo module engine_test\n"
    "#pragma halo hook sample\n"
    "#pragma halo param enabled bool default=1\n"
    "#pragma halo param weights float[4] default=[0.5,0.25] min=0 max=1\n"
    "#pragma halo param tint vec3 default=[1,0.5,0.25] min=0 max=1\n"
    "void apply(inout halo_sample s) {\n"
    "    if (!enabled) return;\n"
    "    for (int i = 0; i < weights_count; ++i) s.opacity *= weights[i];\n"
    "    s.color *= tint;\n"
    "}\n";

/* Replaces the line holding tag (the whole line) by text. */
static char *replace_tag(const char *source, const char *tag, const char *text)
{
    const char *at = strstr(source, tag);
    if (!at)
        return NULL;
    const char *end = strchr(at, '\n');
    end = end ? end + 1 : at + strlen(at);
    size_t n = strlen(source) - (size_t)(end - at) + strlen(text) + 1;
    char *out = malloc(n);
    if (!out)
        return NULL;
    snprintf(out, n, "%.*s%s%s", (int)(at - source), source, text, end);
    return out;
}

/* Composes the engine's shader from the template, the program's pieces and uniforms. */
static char *compose(const halo_program *p, const char *uniforms, const char *template_text)
{
    char *a = replace_tag(template_text, "//ENGINE::Uniforms", uniforms);
    char *b = a ? replace_tag(a, "//ENGINE::Declarations", halo_program_source(p, HALO_PIECE_DECLARATIONS)) : NULL;
    char *c = b ? replace_tag(b, "//ENGINE::Sample", halo_program_source(p, HALO_PIECE_SAMPLE)) : NULL;
    char *d = c ? replace_tag(c, "//ENGINE::Finish", halo_program_source(p, HALO_PIECE_FINISH)) : NULL;
    free(a);
    free(b);
    free(c);
    return d;
}

/* The declarations an engine writes from the reflection (halo_reflection.declarations). */
static char *engine_uniform_declarations(const halo_program *p, int *count)
{
    static char buf[4096];
    size_t len = 0;
    *count = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < halo_program_reflection(p).declaration_count; ++i) {
        const halo_uniform_decl u = halo_program_reflection(p).declarations[i];
        (*count)++;
        if (u.name && u.array_size)
            len += (size_t)snprintf(buf + len, sizeof buf - len, "uniform %s %s[%d];\n", u.glsl_type, u.name,
                                    u.array_size);
        else if (u.name)
            len += (size_t)snprintf(buf + len, sizeof buf - len, "uniform %s %s;\n", u.glsl_type, u.name);
        if (u.count_name)
            len += (size_t)snprintf(buf + len, sizeof buf - len, "uniform int %s;\n", u.count_name);
    }
    return buf;
}

static halo_program *link_pieces(const char *json, const halo_pieces_desc *names, halo_target target, int engine)
{
    halo_diagnostics_clear(diags);
    halo_scene *scene = halo_scene_load("compose.json", json, library, diags);
    if (!scene) {
        check_print_diags(diags);
        return NULL;
    }
    halo_program *p = halo_link(
        &(halo_link_desc){
            .library = library, .scene = scene, .pieces = names, .target = target, .engine_uniforms = engine},
        diags);
    halo_scene_destroy(scene);
    if (!p)
        check_print_diags(diags);
    return p;
}

static const char per_sample_scene[] =
    "{\"halo_scene\": 1, \"stages\": [{\"boundary\": {}}, {\"silhouette\": {}}, {\"tone_shading\": {}},"
    " {\"distance_blend\": {}}]}";

/* Pieces link, validate alone (the pieces host), compose into the engine's template and
 * validate there; derived inputs are used where the engine gives none. */
static int test_pieces_compose(void)
{
    halo_program *p = link_pieces(per_sample_scene, &engine_names, HALO_TARGET_GLSL150, 0);
    CHECK(p != NULL);
    CHECK(halo_validate(&(halo_validate_desc){.program = p}, diags) == HALO_OK);
    const char *decl = halo_program_source(p, HALO_PIECE_DECLARATIONS);
    const char *sample = halo_program_source(p, HALO_PIECE_SAMPLE);
    CHECK(decl && sample && halo_program_source(p, HALO_PIECE_FINISH));
    CHECK(!strstr(decl, "#version"));
    CHECK(strstr(decl, "texture(volume_textures[0]") != NULL); /* the derived gradient reads the engine's volume */
    CHECK(!strstr(decl, "piece_volume"));
    CHECK(strstr(sample, "halo_make_sample(ray_position, scalar, halo_gradient_at(ray_position)") != NULL);
    CHECK(strstr(sample, "halo_view_at(ray_position)") && strstr(sample, "halo_depth_at(ray_position)"));
    CHECK(strstr(sample, "sample_color = vec4(") != NULL);
    /* a piece's line map reaches the module's own lines */
    int mapped = 0;
    for (int line = 1; line < 400; line++) {
        const char *file = NULL;
        int origin = 0;
        if (halo_program_map_line(p, HALO_PIECE_DECLARATIONS, line, &file, &origin) && strstr(file, "boundary.glsl") &&
            origin > 0)
            mapped++;
    }
    CHECK(mapped > 0);
    CHECK_INT_EQ(halo_program_source(p, HALO_PIECE_COUNT) == NULL, 1);
    int n = 0;
    char *composed = compose(p, engine_uniform_declarations(p, &n), engine_template);
    CHECK(composed != NULL);
    halo_diagnostics_clear(diags);
    halo_status st = halo_validate(&(halo_validate_desc){.program = p,
                                                         .composed = composed,
                                                         .composed_file = "engine.frag",
                                                         .composer_pieces = NULL,
                                                         .composer_piece_count = 0},
                                   diags);
    if (st != HALO_OK) {
        check_print_diags(diags);
        fprintf(stderr, "%s", composed);
    }
    CHECK_INT_EQ(st, HALO_OK);
    free(composed);
    halo_program_destroy(p);
    return 0;
}

/* An error in the engine's own piece is reported at that piece's line; an error in an
 * expression the engine gave, at the composed shader's line; the template's own lines
 * at the composed file. */
static int test_composed_errors_mapped(void)
{
    halo_program *p = link_pieces(per_sample_scene, &engine_names, HALO_TARGET_GLSL150, 0);
    CHECK(p != NULL);
    int n = 0;
    char *composed = compose(p, engine_uniform_declarations(p, &n), engine_template);
    CHECK(composed != NULL);
    /* the engine's piece, with an undeclared name on its second line */
    static const char bad_piece[] = "        sample_color.rgb *= 0.9;\n        sample_color.a *= no_such_factor;\n";
    char *with_piece = replace_tag(composed, "        ray_position += step_size;\n", bad_piece);
    CHECK(with_piece != NULL);
    halo_diagnostics_clear(diags);
    halo_composer_piece pieces[] = {{"//ENGINE::Shading", bad_piece}};
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p,
                                                     .composed = with_piece,
                                                     .composed_file = "engine.frag",
                                                     .composer_pieces = pieces,
                                                     .composer_piece_count = 1},
                               diags),
                 HALO_ERROR_INPUT);
    const halo_diagnostic *g = check_find_diag(diags, HALO_MSG_GLSL_ERROR, 2);
    CHECK(g != NULL);
    CHECK_STR_EQ(g->file, "//ENGINE::Shading");
    CHECK(g->column > 1);
    free(with_piece);
    /* a template line of its own: composed file, composed line */
    char *bad_template =
        replace_tag(engine_template, "    vec3 ray_position = vec3(0.5);\n", "    vec3 ray_position = vec2(0.5);\n");
    char *composed2 = bad_template ? compose(p, engine_uniform_declarations(p, &n), bad_template) : NULL;
    CHECK(composed2 != NULL);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p,
                                                     .composed = composed2,
                                                     .composed_file = "engine.frag",
                                                     .composer_pieces = NULL,
                                                     .composer_piece_count = 0},
                               diags),
                 HALO_ERROR_INPUT);
    g = check_find_diag(diags, HALO_MSG_GLSL_ERROR, 0);
    CHECK(g != NULL);
    CHECK_STR_EQ(g->file, "engine.frag");
    int line = 1;
    for (const char *c = composed2; c < strstr(composed2, "vec2(0.5)"); c++)
        line += *c == '\n';
    CHECK_INT_EQ(g->line, line);
    free(bad_template);
    free(composed2);
    free(composed);
    halo_program_destroy(p);
    /* the engine's value expression names nothing: the error sits in the sample piece */
    halo_pieces_desc wrong = engine_names;
    wrong.value = "scalar_value";
    p = link_pieces(per_sample_scene, &wrong, HALO_TARGET_GLSL150, 0);
    CHECK(p != NULL);
    composed = compose(p, "", engine_template);
    CHECK(composed != NULL);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p,
                                                     .composed = composed,
                                                     .composed_file = "engine.frag",
                                                     .composer_pieces = NULL,
                                                     .composer_piece_count = 0},
                               diags),
                 HALO_ERROR_INPUT);
    g = check_find_diag(diags, HALO_MSG_GLSL_ERROR, 0);
    CHECK(g != NULL && strstr(g->text, "scalar_value"));
    CHECK_STR_EQ(g->file, "engine.frag");
    free(composed);
    halo_program_destroy(p);
    return 0;
}

/* Live parameters for an engine that declares uniforms: none declared by libhalo, the
 * reflection gives each with its GLSL type (bool as int), array size and count companion;
 * the composed shader validates with the engine's declarations and fails without them. */
static int test_engine_uniforms(void)
{
    halo_program *p = link_pieces(
        "{\"halo_scene\": 1, \"stages\": [{\"engine_test\": {\"live\": true}},"
        " {\"boundary\": {\"live\": [\"k_gs\"]}}]}",
        &engine_names, HALO_TARGET_GLSL150, 1);
    CHECK(p != NULL);
    const char *decl = halo_program_source(p, HALO_PIECE_DECLARATIONS);
    CHECK(!strstr(decl, "\nuniform float halo_boundary_k_gs"));
    CHECK(!strstr(decl, "\nuniform int halo_engine_test_enabled") && !strstr(decl, "\nuniform bool"));
    CHECK(strstr(decl, "(halo_engine_test_enabled != 0)") != NULL);
    CHECK(strstr(decl, "const float halo_boundary_k_gc") != NULL); /* a constant stays a constant */
    /* the pieces host declares them as the engine would: it validates */
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p}, diags), HALO_OK);
    int seen = 0;
    for (size_t i = 0; i < halo_program_reflection(p).declaration_count; ++i) {
        const halo_uniform_decl u = halo_program_reflection(p).declarations[i];
        if (u.name && !strcmp(u.name, "halo_engine_test_enabled")) {
            CHECK_STR_EQ(u.glsl_type, "int");
            CHECK(u.value[0] == 1.0);
            seen |= 1;
        } else if (u.name && !strcmp(u.name, "halo_engine_test_weights")) {
            CHECK_STR_EQ(u.glsl_type, "float");
            CHECK_INT_EQ(u.array_size, 4);
            CHECK_INT_EQ(u.count, 2);
            CHECK_STR_EQ(u.count_name, "halo_engine_test_weights_count");
            CHECK(u.value[0] == 0.5 && u.value[1] == 0.25);
            seen |= 2;
        } else if (u.name && !strcmp(u.name, "halo_engine_test_tint")) {
            CHECK_STR_EQ(u.glsl_type, "vec3");
            CHECK_INT_EQ(u.components, 3);
            seen |= 4;
        } else if (u.name && !strcmp(u.name, "halo_boundary_k_gs")) {
            CHECK_STR_EQ(u.glsl_type, "float");
            seen |= 8;
        } else {
            CHECK_FAIL_AT("unexpected engine uniform %s", u.name ? u.name : "(companion)");
        }
    }
    CHECK_INT_EQ(seen, 15);
    int n = 0;
    char *composed = compose(p, engine_uniform_declarations(p, &n), engine_template);
    CHECK(composed != NULL);
    halo_diagnostics_clear(diags);
    halo_status st = halo_validate(&(halo_validate_desc){.program = p,
                                                         .composed = composed,
                                                         .composed_file = "engine.frag",
                                                         .composer_pieces = NULL,
                                                         .composer_piece_count = 0},
                                   diags);
    if (st != HALO_OK)
        check_print_diags(diags);
    CHECK_INT_EQ(st, HALO_OK);
    free(composed);
    /* without the engine's declarations: undeclared, mapped to the module's line */
    composed = compose(p, "", engine_template);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p,
                                                     .composed = composed,
                                                     .composed_file = "engine.frag",
                                                     .composer_pieces = NULL,
                                                     .composer_piece_count = 0},
                               diags),
                 HALO_ERROR_INPUT);
    const halo_diagnostic *g = check_find_diag(diags, HALO_MSG_GLSL_ERROR, 0);
    CHECK(g != NULL);
    CHECK(strstr(g->file, "engine_test.glsl") != NULL);
    free(composed);
    halo_program_destroy(p);
    return 0;
}

/* Pieces with image passes: outputs with no layout(location) under GLSL 150 (bound by
 * name at the reflection's location), a first location the engine chooses, and a
 * single-pass link of a halo scene refused with the stages named. */
static int test_pieces_outputs(void)
{
    static const char halo_json[] =
        "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {}}, {\"halo_generate\": {}},"
        " {\"halo_map\": {}}]}";
    halo_program *p = link_pieces(halo_json, &engine_names, HALO_TARGET_GLSL150, 0);
    CHECK(p == NULL);
    CHECK(check_find_diag(diags, HALO_MSG_HOST_SINGLE_PASS, 0) != NULL);
    halo_pieces_desc segmented = engine_names;
    segmented.segmented = 1;
    segmented.first_output_location = 3;
    p = link_pieces(halo_json, &segmented, HALO_TARGET_GLSL150, 0);
    CHECK(p != NULL);
    CHECK(halo_validate(&(halo_validate_desc){.program = p}, diags) == HALO_OK);
    const char *decl = halo_program_source(p, HALO_PIECE_DECLARATIONS);
    CHECK(!strstr(decl, "layout(location"));
    CHECK(strstr(decl, "out halo_channels halo_output_seed;") != NULL);
    CHECK(strstr(decl, "void halo_segment_begin(") != NULL);
    CHECK(halo_program_reflection(p).output_count >= 1);
    CHECK_INT_EQ(halo_program_reflection(p).outputs[0].location, 3);
    CHECK(halo_program_reflection(p).segment_location > 3);
    for (size_t i = 0; i < halo_program_reflection(p).pass_count; i++)
        CHECK(!strstr(halo_program_reflection(p).passes[i].fragment_source, "layout(location"));
    halo_program_destroy(p);
    /* GLSL 150 with GL_ARB_explicit_attrib_location: located, and the pieces host enables it */
    halo_diagnostics_clear(diags);
    halo_scene *hs = halo_scene_load("h.json", halo_json, library, diags);
    CHECK(hs != NULL);
    p = halo_link(&(halo_link_desc){.library = library,
                                    .scene = hs,
                                    .pieces = &segmented,
                                    .target = HALO_TARGET_GLSL150,
                                    .output_locations = HALO_LOCATIONS_EXTENSION},
                  diags);
    halo_scene_destroy(hs);
    CHECK(p != NULL);
    CHECK(strstr(halo_program_source(p, HALO_PIECE_DECLARATIONS), "layout(location = 3) out") != NULL);
    CHECK(strstr(halo_program_source(p, HALO_PIECE_WHOLE), "#extension GL_ARB_explicit_attrib_location : require") !=
          NULL);
    if (halo_validate(&(halo_validate_desc){.program = p}, diags) != HALO_OK)
        check_print_diags(diags);
    CHECK_INT_EQ(halo_diagnostics_describe(diags).errors, 0);
    halo_program_destroy(p);
    /* the same under 330: located outputs */
    p = link_pieces(halo_json, &segmented, HALO_TARGET_GLSL330, 0);
    CHECK(p != NULL);
    CHECK(strstr(halo_program_source(p, HALO_PIECE_DECLARATIONS), "layout(location = 3) out") != NULL);
    halo_program_destroy(p);
    /* no gradient from anywhere: refused */
    halo_pieces_desc none = {.position = "p", .value = "v", .color = "c"};
    p = link_pieces(per_sample_scene, &none, HALO_TARGET_GLSL330, 0);
    CHECK(p == NULL);
    CHECK(check_find_diag(diags, HALO_MSG_USAGE, 0) != NULL);
    return 0;
}

/* #version modes with host text: the target's, the host's own, none. */
static int test_version_modes(void)
{
    static const char host[] =
        "#version 150\n"
        "#pragma halo declarations\n"
        "out vec4 color_out;\n"
        "void main() {\n"
        "    vec4 color = vec4(0.5);\n"
        "#ifdef HALO_LINKED\n"
        "    halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.1), vec3(0.0, 0.0, 1.0),\n"
        "                                     0.5, gl_FragCoord.xy, color.rgb, color.a);\n"
        "    halo_apply(s);\n"
        "    color = vec4(s.color, s.opacity);\n"
        "    halo_finish();\n"
        "#endif\n"
        "    color_out = color;\n"
        "}\n";
    halo_scene *scene = halo_scene_load("v.json", per_sample_scene, library, diags);
    CHECK(scene != NULL);
    static const char *const first_lines[] = {"#version 150 core\n", "#version 150\n", "// #version 150 (no"};
    for (int mode = HALO_VERSION_TARGET; mode <= HALO_VERSION_NONE; mode++) {
        halo_diagnostics_clear(diags);
        halo_program *p = halo_link(&(halo_link_desc){.library = library,
                                                      .scene = scene,
                                                      .host_source = host,
                                                      .host_file = "v.frag",
                                                      .target = HALO_TARGET_GLSL150,
                                                      .version = (halo_version_mode)mode},
                                    diags);
        CHECK(p != NULL);
        CHECK(!strncmp(halo_program_source(p, HALO_PIECE_WHOLE), first_lines[mode], strlen(first_lines[mode])));
        if (mode != HALO_VERSION_NONE)
            CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p}, diags), HALO_OK);
        halo_program_destroy(p);
    }
    halo_diagnostics_clear(diags);
    CHECK(halo_link(&(halo_link_desc){.library = library,
                                      .scene = scene,
                                      .host_source = host,
                                      .target = HALO_TARGET_GLSL150,
                                      .version = (halo_version_mode)7},
                    diags) == NULL);
    CHECK(check_find_diag(diags, HALO_MSG_USAGE, 0) != NULL);
    /* host text and pieces at once: refused */
    halo_diagnostics_clear(diags);
    CHECK(halo_link(&(halo_link_desc){.library = library, .scene = scene, .host_source = host, .pieces = &engine_names},
                    diags) == NULL);
    CHECK(check_find_diag(diags, HALO_MSG_USAGE, 0) != NULL);
    halo_scene_destroy(scene);
    return 0;
}


/* Issue 26: each composer expression is one GLSL expression of its field's kind, or the
 * link fails with PIECE_EXPRESSION at "NAME=EXPR", line 1, the offending token's column
 * (before, every one of these linked and gave pieces that cannot compile or do something
 * else). */
static int test_piece_expressions(void)
{
    static const struct {
        const char *field, *text;
        int column; /* in "field=text" */
    } bad[] = {
        {"position", "p //", 12},            /* comments out the rest of libhalo's line */
        {"position", "p); discard; (p", 12}, /* statements */
        {"color", "vec4(1.0)", 7},           /* color is written back: an lvalue */
        {"position", "(p", 10},              /* unbalanced */
        {"position", "p)", 11},
        {"value", "; uniform float evil", 7},
        {"value", "x #define evil", 9},
        {"value", "a = 1.0", 9}, /* state changes: evaluated more than once */
        {"value", "x++", 8},
        {"value", "a, b", 8}, /* two arguments */
        {"value", "discard", 7},
        {"position", "p.xy", 10}, /* a vec2 where a vec3 goes */
        {"value", "vec3(1.0)", 7},
        {"volume", "texture(v, p)", 8}, /* no sampler designator */
        {"value", "", 7},
        {"value", "x /* y */", 9}, /* a block comment */
        {"value", "1.0e", 7},      /* not a number literal */
        {"value", "1..0", 7},
        {"value", "0x", 7},
        {"value", "2f", 7},             /* a float suffix without '.' or exponent */
        {"value", "09", 7},             /* not octal */
        {"color", "(a, colors[1])", 7}, /* a comma expression is no lvalue */
        {"value", "mat2(1.0)", 7},      /* constructors of no field's type (before: left to glslang) */
        {"position", "ivec3(1)", 10},
        {"value", "abs(dvec2(1.0))", 7},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        halo_pieces_desc names = engine_names;
        const char **slot = !strcmp(bad[i].field, "position") ? &names.position
                            : !strcmp(bad[i].field, "value")  ? &names.value
                            : !strcmp(bad[i].field, "color")  ? &names.color
                                                              : &names.volume;
        *slot = bad[i].text;
        halo_program *p = link_pieces(per_sample_scene, &names, HALO_TARGET_GLSL150, 0);
        if (p)
            CHECK_FAIL_AT("%s=%s linked", bad[i].field, bad[i].text);
        const halo_diagnostic *g = check_find_diag(diags, HALO_MSG_PIECE_EXPRESSION, 1);
        if (!g)
            CHECK_FAIL_AT("%s=%s: no PIECE_EXPRESSION", bad[i].field, bad[i].text);
        char file[128];
        snprintf(file, sizeof file, "%s=%s", bad[i].field, bad[i].text);
        CHECK_STR_EQ(g->file, file);
        CHECK_INT_EQ(g->column, bad[i].column);
    }
    static const halo_pieces_desc good = {.position = "a[i].xyz * 0.5 + vec3(0.25)",
                                          .value = "clamp(texture(volume_textures[0], ray_position).r, 0.0, 1.0)",
                                          .view = "-normalize(eye - (ray_position))",
                                          .depth = "x > 0.5 ? 1.0 : f(x, (y, z))",
                                          .color = "(colors[1])",
                                          .volume = "volume_textures[0]"};
    halo_program *p = link_pieces(per_sample_scene, &good, HALO_TARGET_GLSL150, 0);
    CHECK(p != NULL);
    halo_program_destroy(p);
    /* the plain designator too, and literals of every kind (0x1e-3: 0x1e minus 3) */
    halo_pieces_desc plain = good;
    plain.color = "colors[1]";
    plain.depth = "float(0x1e-3 + 07) + 1e5 + .5e-3 + 5. + float(0X1Fu) + 1.0F + 0.0";
    p = link_pieces(per_sample_scene, &plain, HALO_TARGET_GLSL150, 0);
    CHECK(p != NULL);
    halo_program_destroy(p);
    return 0;
}

/* Issue 26: a live channels parameter (halo_generate.delta, halo_seed.alpha) is declared by
 * the engine as the program's halo_channels (vec2 for two halos), not as an array, so
 * seed.glsl and map.glsl compile (before: "vec2 NAME[4]", and halo_channel() had no
 * overload); under GLSL ES the engine's uniforms come after the precision statements. */
static int test_engine_channels(void)
{
    static const char scene_json[] =
        "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {\"alpha\": [32, 16], \"live\": [\"alpha\"]}},"
        " {\"halo_generate\": {\"delta\": [0.9, 0.8], \"live\": [\"delta\"]}}, {\"halo_map\": {}}]}";
    static const halo_target targets[] = {HALO_TARGET_GLSL150, HALO_TARGET_GLSL330, HALO_TARGET_ES300};
    halo_diagnostics_clear(diags);
    halo_scene *scene = halo_scene_load("channels.json", scene_json, library, diags);
    CHECK(scene != NULL);
    halo_pieces_desc names = engine_names;
    names.segmented = 1;
    for (size_t t = 0; t < sizeof targets / sizeof targets[0]; t++)
        for (int all_live = 0; all_live <= 1; all_live++) {
            halo_diagnostics_clear(diags);
            halo_program *p = halo_link(&(halo_link_desc){.library = library,
                                                          .scene = scene,
                                                          .pieces = &names,
                                                          .target = targets[t],
                                                          .engine_uniforms = 1,
                                                          .all_live = all_live},
                                        diags);
            CHECK(p != NULL);
            int delta = 0;
            for (size_t i = 0; i < halo_program_reflection(p).declaration_count; ++i) {
                const halo_uniform_decl u = halo_program_reflection(p).declarations[i];
                if (u.name && strstr(u.name, "halo_generate_delta")) {
                    delta = 1;
                    CHECK_STR_EQ(u.glsl_type, "vec2");
                    CHECK_INT_EQ(u.array_size, 0);
                    CHECK_INT_EQ(u.components, 2);
                    CHECK(u.count_name == NULL);
                    CHECK(u.value[0] == 0.9 && u.value[1] == 0.8);
                }
            }
            CHECK(delta);
            /* the declarations follow halo_program_set: one value for two halos repeats */
            CHECK_INT_EQ(halo_program_set(p, "halo_generate", "delta", (const double[]){0.7}, 1, diags), HALO_OK);
            for (size_t i = 0; i < halo_program_reflection(p).declaration_count; ++i) {
                const halo_uniform_decl u = halo_program_reflection(p).declarations[i];
                if (u.name && strstr(u.name, "halo_generate_delta"))
                    CHECK(u.value[0] == 0.7 && u.value[1] == 0.7);
            }
            if (halo_validate(&(halo_validate_desc){.program = p}, diags) != HALO_OK) {
                check_print_diags(diags);
                CHECK_FAIL_AT("target %s, all_live %d: the pieces do not validate", halo_target_name(targets[t]),
                              all_live);
            }
            if (targets[t] == HALO_TARGET_ES300) {
                const char *src = halo_program_source(p, HALO_PIECE_WHOLE),
                           *precision = strstr(src, "precision highp float;");
                const char *uniform = strstr(src, "uniform vec2 halo_halo_generate_delta;");
                CHECK(precision && uniform && precision < uniform);
            }
            halo_program_destroy(p);
        }
    halo_scene_destroy(scene);
    return 0;
}

int main(void)
{
    SETUP(halo_setup(&(halo_setup_desc){0}) == HALO_OK);
    library = check_library_setup(&diags);
    if (halo_library_add(library, "user/engine_test.glsl", user_module, HALO_ADD_NEW, diags) != HALO_OK) {
        check_print_diags(diags);
        SETUP_FAIL("cannot add the test module");
    }
    RUN_TEST(test_pieces_compose);
    RUN_TEST(test_composed_errors_mapped);
    RUN_TEST(test_engine_uniforms);
    RUN_TEST(test_pieces_outputs);
    RUN_TEST(test_version_modes);
    RUN_TEST(test_piece_expressions);
    RUN_TEST(test_engine_channels);
    halo_library_destroy(library);
    halo_diagnostics_destroy(diags);
    halo_shutdown();
    return check_exit_status();
}
