/* The linker (halo_link) with hosts given as strings, and glslang validation of what
 * it emits (halo_validate). No GL. */
#include "check.h"
#include "internal.h"
#include "strbuf.h"

static halo_library *library;
static halo_diagnostics *diags;

/* A host following the contract: #version, the marker, one sample through halo_apply. */
static const char host_source[] =
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

static halo_scene *scene_of(const char *json)
{
    halo_diagnostics_clear(diags);
    halo_scene *s = halo_scene_parse(json, "test.json", library, diags);
    if (!s) {
        check_print_diags(diags);
        SETUP_FAIL("scene rejected: %s", json);
    }
    return s;
}

static halo_program *link_with(const halo_scene *scene, const char *host, halo_target target, int all_live)
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
static halo_program *link_valid(const char *json)
{
    halo_scene *scene = scene_of(json);
    halo_program *p = link_with(scene, host_source, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    if (!p || halo_validate(&(halo_validate_desc){.program = p}, diags) != HALO_OK) {
        fprintf(stderr, "link or validation failed for %s\n", json);
        check_print_diags(diags);
        if (p)
            fprintf(stderr, "%s", halo_program_source(p));
        halo_program_destroy(p);
        return NULL;
    }
    return p;
}

static int stage_index(const halo_program *p, const char *stage)
{
    for (size_t i = 0; i < halo_program_stage_count(p); i++)
        if (!strcmp(halo_program_stage(p, i), stage))
            return (int)i;
    return -1;
}

/* 1-based line number of the first line of text containing needle, or 0. */
static int line_containing(const char *text, const char *needle)
{
    const char *hit = strstr(text, needle);
    if (!hit)
        return 0;
    int line = 1;
    for (const char *c = text; c < hit; c++)
        line += *c == '\n';
    return line;
}

/* The helpers of halo_math.glsl that the linked stages call, directly or through
 * other helpers, computed from the modules' own lists. */
static int helper_needed(const halo_program *p, const halo_module *helpers, size_t chunk)
{
    unsigned char need[64] = {0};
    SETUP(helpers->chunk_count <= 64);
    for (size_t c = 0; c < helpers->chunk_count; c++)
        for (size_t s = 0; s < halo_program_stage_count(p); s++) {
            const halo_module *m = halo_library_find(library, halo_program_stage(p, s));
            if (halo_name_list_has(&m->calls, helpers->chunks[c].name))
                need[c] = 1;
        }
    for (int changed = 1; changed;) {
        changed = 0;
        for (size_t c = 0; c < helpers->chunk_count; c++)
            for (size_t d = 0; need[c] && d < helpers->chunk_count; d++)
                if (!need[d] && halo_name_list_has(&helpers->chunks[c].calls, helpers->chunks[d].name))
                    need[d] = changed = 1;
    }
    return need[chunk];
}

/* The source holds code of the linked stages only, and exactly the helpers they use. */
static int check_only_linked_in(const halo_program *p, const char *src);
/* The program's text: the host's source and every image pass's programs. */
static int check_only_linked(const halo_program *p)
{
    size_t len = strlen(halo_program_source(p)) + 1;
    for (size_t i = 0; i < halo_program_pass_count(p); i++)
        len += strlen(halo_program_pass(p, i)->fragment_source) + strlen(halo_program_pass(p, i)->vertex_source);
    char *all = malloc(len);
    SETUP(all != NULL);
    strcpy(all, halo_program_source(p));
    for (size_t i = 0; i < halo_program_pass_count(p); i++) {
        strcat(all, halo_program_pass(p, i)->fragment_source);
        strcat(all, halo_program_pass(p, i)->vertex_source);
    }
    int status = check_only_linked_in(p, all);
    free(all);
    return status;
}

static int check_only_linked_in(const halo_program *p, const char *src)
{
    for (size_t i = 0; i < halo_library_module_count(library); i++) {
        const halo_module *m = halo_library_module(library, i);
        if (m->is_library)
            continue;
        char prefix[160], comment[160];
        snprintf(prefix, sizeof prefix, "halo_%s_", halo_module_name(m));
        snprintf(comment, sizeof comment, "// stage %s ", halo_module_name(m));
        if (stage_index(p, halo_module_name(m)) >= 0) {
            CHECK_STR_CONTAINS(src, prefix);
            CHECK_STR_CONTAINS(src, comment);
        } else {
            CHECK_STR_NOT_CONTAINS(src, prefix);
            CHECK_STR_NOT_CONTAINS(src, comment);
            CHECK_STR_NOT_CONTAINS(src, halo_module_file(m));
        }
    }
    const halo_module *helpers = halo_library_find(library, "halo_math");
    SETUP(helpers && helpers->chunk_count > 0);
    for (size_t c = 0; c < helpers->chunk_count; c++) {
        char call[160];
        snprintf(call, sizeof call, "%s(", helpers->chunks[c].name);
        if (helper_needed(p, helpers, c))
            CHECK_STR_CONTAINS(src, call);
        else
            CHECK_STR_NOT_CONTAINS(src, call);
    }
    return 0;
}

/* (a) A one-stage scene emits that stage (and what it needs) and nothing else. */
static int test_only_enabled_code(void)
{
    halo_program *p = link_valid("{\"stages\": [\"opacity_power\"]}");
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_program_stage_count(p), 1);
    CHECK_STR_EQ(halo_program_stage(p, 0), "opacity_power");
    if (check_only_linked(p))
        return 1;
    /* opacity_power uses halo_pow and halo_saturate, not the colour helpers. */
    CHECK_STR_CONTAINS(halo_program_source(p), "halo_pow(");
    CHECK_STR_NOT_CONTAINS(halo_program_source(p), "halo_rgb_to_hsv");
    CHECK_STR_NOT_CONTAINS(halo_program_source(p), "halo_normalize");
    halo_program_destroy(p);

    p = link_valid("{\"stages\": [\"silhouette\"]}");
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_program_stage_count(p), 2); /* with gradient, which provides the normal */
    if (check_only_linked(p))
        return 1;
    CHECK_STR_NOT_CONTAINS(halo_program_source(p), "halo_hsv_to_rgb");
    halo_program_destroy(p);

    /* Each stage alone. */
    for (size_t i = 0; i < halo_library_module_count(library); i++) {
        const halo_module *m = halo_library_module(library, i);
        if (m->is_library || halo_module_hook(m) != HALO_HOOK_SAMPLE || strncmp(halo_module_file(m), "glsl/", 5))
            continue;
        char json[256];
        snprintf(json, sizeof json, "{\"stages\": [\"%s\"]}", halo_module_name(m));
        p = link_valid(json);
        CHECK(p != NULL);
        CHECK(stage_index(p, halo_module_name(m)) >= 0);
        if (check_only_linked(p))
            return 1;
        halo_program_destroy(p);
    }

    /* A disabled stage is not linked. */
    p = link_valid("{\"stages\": [\"opacity_power\", {\"sketch\": {\"enabled\": false}}]}");
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_program_stage_count(p), 1);
    if (check_only_linked(p))
        return 1;
    halo_program_destroy(p);
    return 0;
}

/* Unused parameters produce no code. */
static int test_unused_param(void)
{
    halo_program *p = link_valid("{\"stages\": [\"unused_param\"]}");
    CHECK(p != NULL);
    CHECK_STR_CONTAINS(halo_program_source(p), "halo_unused_param_used");
    CHECK_STR_NOT_CONTAINS(halo_program_source(p), "halo_unused_param_spare");
    halo_program_destroy(p);
    return 0;
}

/* The body of halo_apply: between its braces, only white space. */
static int check_empty_apply(const char *src)
{
    const char *at = strstr(src, "void halo_apply(inout halo_sample s)");
    CHECK(at != NULL);
    const char *open = strchr(at, '{'), *close = open ? strchr(open, '}') : NULL;
    CHECK(open && close);
    for (const char *c = open + 1; c < close; c++)
        if (*c != ' ' && *c != '\n' && *c != '\t')
            CHECK_FAIL_AT("halo_apply is not empty: %.*s", (int)(close - open + 1), open);
    return 0;
}

/* (b) No stage: an empty halo_apply, no stage code, no helpers. */
static int test_empty_scene(void)
{
    halo_program *p = link_with(NULL, host_source, HALO_TARGET_DEFAULT, 0);
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_program_stage_count(p), 0);
    CHECK_INT_EQ(halo_program_uniform_count(p), 0);
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p}, diags), HALO_OK);
    if (check_only_linked(p))
        return 1;
    if (check_empty_apply(halo_program_source(p)))
        return 1;
    CHECK_STR_CONTAINS(halo_program_source(p), "#define HALO_LINKED");
    CHECK_STR_CONTAINS(halo_program_source(p), "struct halo_sample");
    CHECK_STR_CONTAINS(halo_program_source(p), "halo_make_sample");
    CHECK_STR_NOT_CONTAINS(halo_program_source(p), "halo_pow");
    CHECK_STR_NOT_CONTAINS(halo_program_source(p), "halo_saturate");
    CHECK_STR_NOT_CONTAINS(halo_program_source(p), "uniform");
    /* No provided fields either. */
    CHECK_STR_NOT_CONTAINS(halo_program_source(p), "gradient_magnitude");
    char *empty_scene_text = strdup(halo_program_source(p));
    halo_program_destroy(p);

    halo_scene *scene = scene_of("{\"stages\": [{\"boundary\": {\"enabled\": false}}]}");
    p = link_with(scene, host_source, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_program_stage_count(p), 0);
    if (check_empty_apply(halo_program_source(p)))
        return 1;
    /* An empty scene and a scene of disabled stages link to the same text. */
    CHECK_STR_EQ(halo_program_source(p), empty_scene_text);
    free(empty_scene_text);
    halo_program_destroy(p);
    return 0;
}

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
            fprintf(stderr, "%s", halo_program_source(p));
            CHECK_FAIL_AT("renamed program does not validate (all_live = %d)", live);
        }
        CHECK_STR_CONTAINS(halo_program_source(p), "halo_distance_cue_depth_map(");
        CHECK_STR_CONTAINS(halo_program_source(p), "halo_weight_a_weight(");
        CHECK_STR_CONTAINS(halo_program_source(p), "halo_weight_b_weight(");
        CHECK_STR_CONTAINS(halo_program_source(p), "halo_boundary_apply(s);");
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
    const char *src = halo_program_source(p);
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
    src = halo_program_source(p);
    CHECK_STR_NOT_CONTAINS(src, "const float halo_");
    CHECK_STR_NOT_CONTAINS(src, "const int halo_");
    CHECK_STR_NOT_CONTAINS(src, "const vec3 halo_");
    CHECK_STR_CONTAINS(src, "uniform float halo_boundary_k_gs;");
    CHECK_STR_CONTAINS(src, "uniform vec3 halo_tone_shading_lights[4];");
    CHECK_STR_CONTAINS(src, "uniform int halo_tone_shading_lights_count;");
    CHECK(halo_program_uniform_count(p) >= 3 + 5 + 0);
    for (size_t i = 0; i < halo_program_uniform_count(p); i++) {
        const halo_uniform_info *w = halo_program_uniform(p, i);
        CHECK_INT_EQ(w->live, 1);
        CHECK(w->info != NULL);
    }
    CHECK_NEAR(halo_program_find_uniform(p, "boundary", "k_gs")->value[0], 12.5, 0);
    halo_program_destroy(p);
    return 0;
}

/* (e) Dependencies are enabled and ordered; the output is deterministic. */
static int test_order(void)
{
    halo_program *p = link_valid("{\"stages\": [\"silhouette\"]}");
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_program_stage_count(p), 2);
    CHECK_STR_EQ(halo_program_stage(p, 0), "gradient");
    CHECK_STR_EQ(halo_program_stage(p, 1), "silhouette");
    const char *src = halo_program_source(p);
    int g = line_containing(src, "halo_gradient_apply(s);"), s = line_containing(src, "halo_silhouette_apply(s);");
    CHECK(g > 0 && s > 0);
    CHECK(g < s);
    halo_program_destroy(p);

    /* tone_shading before distance_blend, whatever the scene's order. */
    static const char *const scenes[] = {
        "{\"stages\": [\"distance_blend\", \"tone_shading\"]}", "{\"stages\": [\"tone_shading\", \"distance_blend\"]}",
        "{\"stages\": [\"distance_cue\", \"distance_blend\", \"sketch\", \"tone_shading\","
        " \"orientation_fade\", \"boundary\", \"silhouette\", \"opacity_power\"]}"};
    for (size_t i = 0; i < 3; i++) {
        p = link_valid(scenes[i]);
        CHECK(p != NULL);
        int tone = stage_index(p, "tone_shading"), blend = stage_index(p, "distance_blend");
        CHECK(tone >= 0 && blend >= 0);
        CHECK(tone < blend);
        /* Every stage runs after the stages it names in `after` and those providing what it needs. */
        for (size_t k = 0; k < halo_program_stage_count(p); k++) {
            const halo_module *m = halo_library_find(library, halo_program_stage(p, k));
            for (size_t a = 0; a < m->after.count; a++) {
                int before = stage_index(p, m->after.items[a]);
                if (before >= 0 && before > (int)k)
                    CHECK_FAIL_AT("%s runs before %s, which it must follow", m->name, m->after.items[a]);
            }
            if (m->needs.count)
                CHECK(stage_index(p, "gradient") < (int)k);
        }
        src = halo_program_source(p);
        CHECK(line_containing(src, "halo_tone_shading_apply(s);") <
              line_containing(src, "halo_distance_blend_apply(s);"));
        /* Deterministic: linking again gives the same text. */
        halo_scene *scene = scene_of(scenes[i]);
        halo_program *again = link_with(scene, host_source, HALO_TARGET_DEFAULT, 0);
        halo_scene_destroy(scene);
        CHECK(again != NULL);
        CHECK_STR_EQ(halo_program_source(again), halo_program_source(p));
        halo_program_destroy(again);
        halo_program_destroy(p);
    }
    /* The two scene orders of the same stages give the same program. */
    halo_scene *a = scene_of(scenes[0]);
    halo_program *pa = link_with(a, host_source, HALO_TARGET_DEFAULT, 0);
    halo_scene *b = scene_of(scenes[1]);
    halo_program *pb = link_with(b, host_source, HALO_TARGET_DEFAULT, 0);
    CHECK(pa && pb);
    CHECK_STR_EQ(halo_program_source(pa), halo_program_source(pb));
    halo_program_destroy(pa);
    halo_program_destroy(pb);
    halo_scene_destroy(a);
    halo_scene_destroy(b);
    return 0;
}

/* (f) Resolution errors, from user modules. */
static int test_resolution_errors(void)
{
    halo_scene *scene = scene_of("{\"stages\": [\"needs_unknown\"]}");
    halo_program *p = link_with(scene, host_source, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    CHECK(p == NULL);
    CHECK_DIAG_LINE(diags, HALO_MSG_LINK_MISSING_PROVIDER, 3);
    CHECK_STR_EQ(check_find_diag(diags, HALO_MSG_LINK_MISSING_PROVIDER, 3)->file, "user/needs_unknown.glsl");

    scene = scene_of("{\"stages\": [\"provider_a\", \"provider_b\"]}");
    p = link_with(scene, host_source, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    CHECK(p == NULL);
    CHECK_DIAG(diags, HALO_MSG_LINK_DUPLICATE_PROVIDER);

    /* A stage needing what two modules provide, neither enabled: ambiguous. */
    scene = scene_of("{\"stages\": [\"needs_thing\"]}");
    p = link_with(scene, host_source, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    CHECK(p == NULL);
    CHECK_DIAG(diags, HALO_MSG_LINK_DUPLICATE_PROVIDER);
    /* Enabling one of them resolves it. */
    p = link_valid("{\"stages\": [\"needs_thing\", \"provider_b\"]}");
    CHECK(p != NULL);
    CHECK_STR_EQ(halo_program_stage(p, 0), "provider_b");
    CHECK_STR_EQ(halo_program_stage(p, 1), "needs_thing");
    halo_program_destroy(p);

    scene = scene_of("{\"stages\": [\"cycle_a\", \"cycle_b\"]}");
    p = link_with(scene, host_source, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    CHECK(p == NULL);
    CHECK_DIAG(diags, HALO_MSG_LINK_CYCLE);
    const halo_diagnostic *g = check_find_diag(diags, HALO_MSG_LINK_CYCLE, 0);
    CHECK(!strcmp(g->file, "user/cycle_a.glsl") || !strcmp(g->file, "user/cycle_b.glsl"));
    CHECK_INT_EQ(g->line, 3);
    /* One of the two alone links. */
    p = link_valid("{\"stages\": [\"cycle_a\"]}");
    CHECK(p != NULL);
    halo_program_destroy(p);
    return 0;
}

static int check_host_error(const char *host, halo_message_id id, int line, int column)
{
    halo_scene *scene = scene_of("{\"stages\": [\"boundary\"]}");
    halo_program *p = link_with(scene, host, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    if (p) {
        halo_program_destroy(p);
        CHECK_FAIL_AT("host accepted:\n%s", host);
    }
    const halo_diagnostic *g = check_find_diag(diags, id, line);
    if (!g) {
        check_print_diags(diags);
        CHECK_FAIL_AT("no %s at line %d for host:\n%s", halo_message_name(id), line, host);
    }
    CHECK_STR_EQ(g->file, "test.frag");
    if (column)
        CHECK_INT_EQ(g->column, column);
    return 0;
}

/* (g) Hosts that break the contract, reported at the host's line. */
static int test_host_errors(void)
{
    if (check_host_error("#version 330 core\n"
                         "out vec4 c;\n"
                         "void main() { c = vec4(1.0); }\n",
                         HALO_MSG_HOST_MARKER_MISSING, 1, 0))
        return 1;
    if (check_host_error("#version 330 core\n"
                         "#pragma halo declarations\n"
                         "out vec4 c;\n"
                         "#pragma halo declarations\n"
                         "void main() { c = vec4(1.0); }\n",
                         HALO_MSG_HOST_MARKER_DUPLICATE, 4, 0))
        return 1;
    if (check_host_error("#version 330 core\n"
                         "out vec4 c;\n"
                         "void main()\n"
                         "{\n"
                         "#pragma halo declarations\n"
                         "    c = vec4(1.0);\n"
                         "}\n",
                         HALO_MSG_HOST_MARKER_SCOPE, 5, 0))
        return 1;
    if (check_host_error("#version 330 core\n"
                         "#pragma halo declarations\n"
                         "float halo_foo;\n"
                         "out vec4 c;\n"
                         "void main() { c = vec4(halo_foo); }\n",
                         HALO_MSG_HOST_RESERVED_NAME, 3, 7))
        return 1;
    if (check_host_error("#version 330 core\n"
                         "#pragma halo declarations\n"
                         "out vec4 c;\n"
                         "void main() { c = vec4(HALO_SCALE); }\n",
                         HALO_MSG_HOST_RESERVED_NAME, 4, 24))
        return 1;
    /* Each problem is reported: two reserved names and a second marker. */
    halo_program *p = link_with(NULL,
                                "#pragma halo declarations\n"
                                "float halo_a;\n"
                                "float halo_b;\n"
                                "#pragma halo declarations\n"
                                "void main() {}\n",
                                HALO_TARGET_DEFAULT, 0);
    CHECK(p == NULL);
    CHECK_DIAG_LINE(diags, HALO_MSG_HOST_RESERVED_NAME, 2);
    CHECK_DIAG_LINE(diags, HALO_MSG_HOST_RESERVED_NAME, 3);
    CHECK_DIAG_LINE(diags, HALO_MSG_HOST_MARKER_DUPLICATE, 4);
    /* The contract's own names are the host's to use. */
    p = link_with(NULL,
                  "#pragma halo declarations\n"
                  "out vec4 c;\n"
                  "void main() {\n"
                  "#if defined(HALO_LINKED) && HALO_CONTRACT_VERSION == 1\n"
                  "    halo_sample s = halo_make_sample(vec3(0.0), 0.0, vec3(0.0), vec3(0.0, 0.0, 1.0), 0.0,\n"
                  "                                     gl_FragCoord.xy, vec3(1.0), 1.0);\n"
                  "    halo_apply(s);\n"
                  "    c = vec4(s.color, s.opacity);\n"
                  "#endif\n"
                  "}\n",
                  HALO_TARGET_DEFAULT, 0);
    if (!p)
        check_print_diags(diags);
    CHECK(p != NULL);
    halo_program_destroy(p);
    /* A library and a host are required. */
    halo_diagnostics_clear(diags);
    CHECK(halo_link(&(halo_link_desc){.library = library}, diags) == NULL);
    CHECK_DIAG(diags, HALO_MSG_USAGE);
    halo_diagnostics_clear(diags);
    CHECK(halo_link(&(halo_link_desc){.host_source = host_source}, diags) == NULL);
    CHECK_DIAG(diags, HALO_MSG_USAGE);
    return 0;
}

/* (h) Every emitted line maps back to its origin. */
static int test_line_map(void)
{
    halo_program *p = link_valid("{\"stages\": [\"boundary\", \"tone_shading\", \"distance_cue\"]}");
    CHECK(p != NULL);
    const char *src = halo_program_source(p);
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
        CHECK_INT_EQ(halo_program_map_line(p, out, &file, &line), 1);
        CHECK_STR_EQ(file, halo_module_file(m));
        CHECK_INT_EQ(line, module_line);
    }
    /* A parameter maps to its annotation. */
    int out = line_containing(src, "const float halo_boundary_k_gs");
    const halo_module *boundary = halo_library_find(library, "boundary");
    const char *file = NULL;
    int line = 0;
    CHECK_INT_EQ(halo_program_map_line(p, out, &file, &line), 1);
    CHECK_STR_EQ(file, "glsl/sample/boundary.glsl");
    CHECK_STR_CONTAINS(boundary->lines[line - 1], "param k_gs");
    /* A helper maps to halo_math.glsl. */
    out = line_containing(src, "float halo_pow(");
    CHECK_INT_EQ(halo_program_map_line(p, out, &file, &line), 1);
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
        if (!halo_program_map_line(p, l, &file, &line) || strcmp(file, "test.frag"))
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
    CHECK_INT_EQ(halo_program_map_line(p, line_containing(src, "struct halo_sample {"), &file, &line), 0);
    CHECK_INT_EQ(halo_program_map_line(p, 0, &file, &line), 0);
    CHECK_INT_EQ(halo_program_map_line(p, 1000000, &file, &line), 0);
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
    for (size_t i = 0; i < halo_diagnostics_count(diags); i++)
        CHECK_STR_EQ(halo_diagnostics_get(diags, i)->file, "test.frag");
    halo_program_destroy(p);
    return 0;
}

static int link_target(const halo_scene *scene, const char *host, halo_target target, int all_live)
{
    halo_program *p = link_with(scene, host, target, all_live);
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_program_target(p), target == HALO_TARGET_DEFAULT ? HALO_TARGET_GLSL330 : target);
    if (halo_validate(&(halo_validate_desc){.program = p}, diags) != HALO_OK) {
        check_print_diags(diags);
        CHECK_FAIL_AT("does not validate for target %s (all_live %d)", halo_target_name(target), all_live);
    }
    const char *src = halo_program_source(p);
    switch (target) {
    case HALO_TARGET_DEFAULT:
    case HALO_TARGET_GLSL330:
        CHECK(!strncmp(src, "#version 330 core\n", 18));
        break;
    case HALO_TARGET_GLSL450:
        CHECK(!strncmp(src, "#version 450 core\n", 18));
        break;
    case HALO_TARGET_ES300:
        CHECK(!strncmp(src, "#version 300 es\n", 16));
        CHECK_STR_CONTAINS(src, "precision highp float;");
        break;
    default:
        break;
    }
    CHECK_INT_EQ(line_containing(src, "#version"), 1);
    CHECK_STR_NOT_CONTAINS(strstr(src, "#version") + 1, "#version");
    halo_program_destroy(p);
    return 0;
}

/* (j) Every target, with every sample stage enabled, as constants and as uniforms. */
static int test_targets(void)
{
    halo_scene *scene = halo_scene_create(library);
    SETUP(scene != NULL);
    for (size_t i = 0; i < halo_library_module_count(library); i++) {
        const halo_module *m = halo_library_module(library, i);
        if (!m->is_library && halo_module_hook(m) == HALO_HOOK_SAMPLE && !strncmp(halo_module_file(m), "glsl/", 5))
            SETUP(halo_scene_enable(scene, halo_module_name(m), 1, diags) == HALO_OK);
    }
    /* A host without #version gets one; a host with one has it replaced. */
    const char *no_version = strchr(host_source, '\n') + 1;
    static const halo_target targets[] = {HALO_TARGET_DEFAULT, HALO_TARGET_GLSL330, HALO_TARGET_GLSL450,
                                          HALO_TARGET_ES300};
    for (size_t t = 0; t < 4; t++)
        for (int live = 0; live < 2; live++) {
            if (link_target(scene, host_source, targets[t], live))
                return 1;
            if (link_target(scene, no_version, targets[t], live))
                return 1;
        }
    if (link_target(NULL, host_source, HALO_TARGET_ES300, 0))
        return 1;
    halo_scene_destroy(scene);
    CHECK_STR_EQ(halo_target_name(HALO_TARGET_ES300), "es300");
    CHECK_INT_EQ(halo_target_from_name("450"), HALO_TARGET_GLSL450);
    CHECK_INT_EQ(halo_target_from_name("es310"), HALO_TARGET_COUNT);
    return 0;
}

/* Halo images at 1/scale (halo_link_desc.image_scale): the pass images are scaled, the
 * seed output is not; the per-sample read interpolates, the first pass max-downsamples;
 * a scale other than 1, 2 or 4 is a usage error. */
static int test_image_scale(void)
{
    halo_scene *scene = scene_of("{\"stages\": [\"halo_seed\", \"halo_generate\", \"halo_map\"]}");
    for (int scale = 1; scale <= 4; scale *= 2) {
        halo_diagnostics_clear(diags);
        halo_program *p = halo_link(&(halo_link_desc){.library = library,
                                                      .scene = scene,
                                                      .host_source = host_source,
                                                      .host_file = "test.frag",
                                                      .image_scale = scale},
                                    diags);
        CHECK(p != NULL);
        CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p}, diags), HALO_OK);
        CHECK_INT_EQ(halo_program_image_scale(p), scale);
        int seen = 0;
        for (size_t i = 0; i < halo_program_image_count(p); i++) {
            const halo_image_info *im = halo_program_image(p, i);
            int expected = !strcmp(im->name, "seed") ? 1 : scale;
            CHECK_INT_EQ(im->scale, expected);
            seen += !strcmp(im->name, "field") || !strcmp(im->name, "seed");
        }
        CHECK_INT_EQ(seen, 2);
        if (scale > 1) {
            CHECK_STR_CONTAINS(halo_program_source(p), "floor(at)"); /* the bilinear read */
            const halo_pass_info *gradient = NULL;
            for (size_t i = 0; i < halo_program_pass_count(p); i++)
                if (!strcmp(halo_program_pass(p, i)->name, "gradient"))
                    gradient = halo_program_pass(p, i);
            CHECK(gradient != NULL);
            CHECK_STR_CONTAINS(gradient->fragment_source, "m = max(m, halo_fetch_0"); /* seed: block max */
        } else {
            CHECK_STR_NOT_CONTAINS(halo_program_source(p), "floor(at)");
        }
        halo_program_destroy(p);
    }
    halo_diagnostics_clear(diags);
    CHECK(halo_link(&(halo_link_desc){.library = library,
                                      .scene = scene,
                                      .host_source = host_source,
                                      .host_file = "test.frag",
                                      .image_scale = 3},
                    diags) == NULL);
    CHECK_DIAG(diags, HALO_MSG_USAGE);
    halo_scene_destroy(scene);
    return 0;
}

/* Whether the program has a pass named name. */
static int has_pass(const halo_program *p, const char *name)
{
    for (size_t i = 0; i < halo_program_pass_count(p); i++)
        if (!strcmp(halo_program_pass(p, i)->name, name))
            return 1;
    return 0;
}

/* The occlusion pass only when a halo may be occlusive (halo_map's `image occlusion
 * read_when=mode`): not for emissive halos, for any occlusive channel or a live mode, and
 * always without halo_map (nothing says the image is unread). At the frame's size the
 * gradient pass stores H_0, then spread from repetition 1 (halo_generate's fold off). */
static int test_occlusion_pass_when_occlusive(void)
{
    static const struct {
        const char *map;
        int all_live, occlude;
    } cases[] = {
        {", \"halo_map\"", 0, 0},
        {", {\"halo_map\": {\"mode\": 1}}", 0, 1},
        {", {\"halo_map\": {\"mode\": [0, 0, 1]}}", 0, 1},
        {", {\"halo_map\": {\"mode\": [0, 0, 0]}}", 0, 0},
        {", \"halo_map\"", 1, 1},
        {"", 0, 1},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char json[256];
        snprintf(json, sizeof json, "{\"stages\": [\"halo_seed\", \"halo_generate\"%s]}", cases[k].map);
        halo_scene *scene = scene_of(json);
        halo_program *p = link_with(scene, host_source, HALO_TARGET_DEFAULT, cases[k].all_live);
        halo_scene_destroy(scene);
        CHECK(p != NULL);
        if (!p)
            continue;
        if (has_pass(p, "occlude") != cases[k].occlude)
            CHECK_FAIL_AT("%s (all_live %d): occlude pass %s", json, cases[k].all_live,
                          cases[k].occlude ? "missing" : "linked");
        /* full size, fold off: the gradient pass, then spread from 1 */
        CHECK(has_pass(p, "spread") && !has_pass(p, "spread_seed") && has_pass(p, "gradient"));
        for (size_t i = 0; i < halo_program_pass_count(p); i++)
            if (!strcmp(halo_program_pass(p, i)->name, "spread"))
                CHECK_INT_EQ(halo_program_pass(p, i)->start, 1);
        halo_program_destroy(p);
    }
    return 0;
}

/* halo_generate's approximation wide at N = 2: the gradient pass stores H_0 (reach 1), then
 * spread_wide twice, reaching 3 * 4^(N - i): 12 and 3; none of the exact spreading passes. */
static int test_pass_reach_wide(void)
{
    halo_program *p = link_valid(
        "{\"stages\": [\"halo_seed\", {\"halo_generate\": {\"passes\": 2, \"wide\": true}},"
        " \"halo_map\"]}");
    CHECK(p != NULL);
    char names[256] = "";
    if (!p)
        return 0;
    for (size_t i = 0; i < halo_program_pass_count(p); i++) {
        const halo_pass_info *pass = halo_program_pass(p, i);
        snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", i ? "," : "", pass->name);
        if (!strcmp(pass->name, "gradient"))
            CHECK_INT_EQ(halo_pass_reach(pass, 1), 1);
        if (!strcmp(pass->name, "spread_wide")) {
            CHECK_INT_EQ(pass->repeat, 2);
            CHECK_INT_EQ(halo_pass_reach(pass, 1), 12);
            CHECK_INT_EQ(halo_pass_reach(pass, 2), 3);
        }
    }
    CHECK_STR_EQ(names, "gradient,spread_wide");
    halo_program_destroy(p);
    return 0;
}

/* halo_generate's passes for each combination of fold, wide and the halo image size:
 * exactly one gradient pass (none only with fold at full size without wide) and one
 * family of spreading passes. */
static int test_generate_pass_lines(void)
{
    static const struct {
        const char *params;
        int scale;
        const char *names;
    } cases[] = {
        {"", 1, "gradient,spread"},
        {"\"fold\": true", 1, "spread_seed,spread"},
        {"\"wide\": true", 1, "gradient,spread_wide"},
        {"\"fold\": true, \"wide\": true", 1, "gradient,spread_wide"},
        {"", 2, "gradient,spread"},
        {"\"fold\": true", 2, "gradient,spread"},
        {"\"wide\": true", 4, "gradient,spread_wide"},
        {"\"fold\": true, \"wide\": true", 4, "gradient,spread_wide"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char json[256], names[256] = "";
        snprintf(json, sizeof json, "{\"stages\": [\"halo_seed\", {\"halo_generate\": {%s}}, \"halo_map\"]}",
                 cases[k].params);
        halo_scene *scene = scene_of(json);
        halo_diagnostics_clear(diags);
        halo_program *p = halo_link(&(halo_link_desc){.library = library,
                                                      .scene = scene,
                                                      .host_source = host_source,
                                                      .host_file = "test.frag",
                                                      .image_scale = cases[k].scale},
                                    diags);
        halo_scene_destroy(scene);
        CHECK(p != NULL);
        if (!p)
            continue;
        for (size_t i = 0; i < halo_program_pass_count(p); i++)
            snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", i ? "," : "",
                     halo_program_pass(p, i)->name);
        if (strcmp(names, cases[k].names))
            CHECK_FAIL_AT("%s at 1/%d: passes %s, expected %s", json, cases[k].scale, names, cases[k].names);
        halo_program_destroy(p);
    }
    return 0;
}

/* reach= (docs/modules.md): how far a pass's repetition writes beyond its inputs' nonzero
 * pixels, with the parameter's value: halo_generate at N = 3 stores H_0 (reach 1), then
 * spreads 4, 2 and 1; with fold, its first spreading pass reaches 4 + 1 (the seed
 * gradient's taps), then 2 and 1; its occlusion pass 0. */
static int test_pass_reach(void)
{
    for (int fold = 0; fold <= 1; fold++) {
        char json[256];
        snprintf(json, sizeof json,
                 "{\"stages\": [\"halo_seed\", {\"halo_generate\": {\"passes\": 3, \"fold\": %s}},"
                 " {\"halo_map\": {\"mode\": 1}}]}",
                 fold ? "true" : "false");
        halo_scene *scene = scene_of(json);
        halo_program *p = link_with(scene, host_source, HALO_TARGET_DEFAULT, 0);
        halo_scene_destroy(scene);
        CHECK(p != NULL);
        if (!p)
            return 0;
        char names[256] = "";
        for (size_t i = 0; i < halo_program_pass_count(p); i++) {
            const halo_pass_info *pass = halo_program_pass(p, i);
            snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", i ? "," : "", pass->name);
            if (!strcmp(pass->name, "gradient")) {
                CHECK_INT_EQ(halo_pass_reach(pass, 1), 1);
            } else if (!strcmp(pass->name, "spread_seed")) {
                CHECK_INT_EQ(halo_pass_reach(pass, 1), 5);
            } else if (!strcmp(pass->name, "spread")) {
                CHECK_INT_EQ(pass->start, fold ? 2 : 1);
                if (!fold)
                    CHECK_INT_EQ(halo_pass_reach(pass, 1), 4);
                CHECK_INT_EQ(halo_pass_reach(pass, 2), 2);
                CHECK_INT_EQ(halo_pass_reach(pass, 3), 1);
            } else if (!strcmp(pass->name, "occlude")) {
                CHECK_INT_EQ(halo_pass_reach(pass, 1), 0);
            }
        }
        CHECK_STR_EQ(names, fold ? "spread_seed,spread,occlude" : "gradient,spread,occlude");
        halo_program_destroy(p);
    }
    return 0;
}

/* Feature groups: more than four features of a grouped stage (outline_feature,
 * outlines) link in groups of four, their channels parameters live, group g's values
 * current after halo_program_select_group; other stages keep the limit of four. */
static int test_feature_groups(void)
{
    halo_scene *scene = scene_of(
        "{\"stages\": [{\"outline_feature\": {\"value_min\": [0.1, 0.2, 0.3, 0.4, 0.5, 0.6],"
        " \"value_max\": [0.15, 0.25, 0.35, 0.45, 0.55, 0.65]}},"
        " {\"outlines\": {\"lambda\": [1, 2, 3, 4, 5]}}]}");
    halo_diagnostics_clear(diags);
    halo_program *p = halo_link(
        &(halo_link_desc){.library = library, .scene = scene, .host_source = host_source, .host_file = "test.frag"},
        diags);
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p}, diags), HALO_OK);
    CHECK_INT_EQ(halo_program_group_count(p), 2);
    CHECK_INT_EQ(halo_program_channel_count(p), 4);
    const halo_uniform_info *vmin = halo_program_find_uniform(p, "outline_feature", "value_min");
    const halo_uniform_info *lambda = halo_program_find_uniform(p, "outlines", "lambda");
    CHECK(vmin && lambda && vmin->live && lambda->live);
    CHECK_INT_EQ(vmin->count, 4);
    CHECK_NEAR(vmin->value[0], 0.1, 0);
    CHECK_NEAR(vmin->value[3], 0.4, 0);
    CHECK_INT_EQ(halo_program_select_group(p, 1), HALO_OK);
    /* group 1: features 4, 5, then the last repeated */
    CHECK_NEAR(vmin->value[0], 0.5, 0);
    CHECK_NEAR(vmin->value[1], 0.6, 0);
    CHECK_NEAR(vmin->value[3], 0.6, 0);
    CHECK_NEAR(lambda->value[0], 5, 0); /* a list of five: its last for the rest */
    CHECK_NEAR(lambda->value[2], 5, 0);
    CHECK_INT_EQ(halo_program_select_group(p, 0), HALO_OK);
    CHECK_NEAR(vmin->value[1], 0.2, 0);
    /* halo_program_set takes the whole list; the selected group's values follow */
    const double more[7] = {0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07};
    CHECK_INT_EQ(halo_program_select_group(p, 1), HALO_OK);
    CHECK_INT_EQ(halo_program_set(p, "outline_feature", "value_min", more, 7, diags), HALO_OK);
    CHECK_NEAR(vmin->value[0], 0.05, 0);
    CHECK_NEAR(vmin->value[2], 0.07, 0);
    CHECK_INT_EQ(halo_program_select_group(p, 0), HALO_OK);
    CHECK_NEAR(vmin->value[3], 0.04, 0);
    const double nine[9] = {0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1};
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_program_set(p, "outline_feature", "value_min", nine, 9, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_USAGE);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_program_select_group(p, 2), HALO_ERROR_INPUT);
    CHECK_INT_EQ(halo_program_select_group(p, -1), HALO_ERROR_INPUT);
    /* an at=post reduce pass into the frame's accumulator, at=final compose */
    int reduce = 0, final = 0;
    for (size_t i = 0; i < halo_program_pass_count(p); i++) {
        reduce |= !strcmp(halo_program_pass(p, i)->name, "reduce") && halo_program_pass(p, i)->at == HALO_PASS_AT_POST;
        final |= !strcmp(halo_program_pass(p, i)->name, "compose") && halo_program_pass(p, i)->at == HALO_PASS_AT_FINAL;
    }
    CHECK(reduce && final);
    halo_program_destroy(p);
    halo_scene_destroy(scene);
    /* four features: one group, parameters constant as before */
    halo_program *q =
        link_valid("{\"stages\": [{\"outline_feature\": {\"value_min\": [0.1, 0.2, 0.3, 0.4]}}, \"outlines\"]}");
    CHECK(q != NULL);
    CHECK_INT_EQ(halo_program_group_count(q), 1);
    CHECK(!halo_program_find_uniform(q, "outline_feature", "value_min")->live);
    CHECK_INT_EQ(halo_program_select_group(q, 0), HALO_OK);
    CHECK_INT_EQ(halo_program_select_group(q, 1), HALO_ERROR_INPUT);
    halo_program_destroy(q);
    /* more than 16 features, or more than four halos: the scene says no */
    halo_diagnostics_clear(diags);
    CHECK(halo_scene_parse(
              "{\"stages\": [{\"outline_feature\": {\"label\": [1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17]}}]}",
              "t.json", library, diags) == NULL);
    halo_diagnostics_clear(diags);
    CHECK(halo_scene_parse("{\"stages\": [{\"halo_seed\": {\"alpha\": [1, 2, 3, 4, 5]}}]}", "t.json", library, diags) ==
          NULL);
    halo_diagnostics_clear(diags);
    return 0;
}

/* (k) Changing parameters of a linked program. */
static int test_program_set(void)
{
    halo_program *p = link_valid(
        "{\"stages\": [{\"boundary\": {\"live\": [\"k_gs\"]}},"
        " {\"tone_shading\": {\"live\": [\"lights\"]}}]}");
    CHECK(p != NULL);
    double v = 20;
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_program_set(p, "boundary", "k_gs", &v, 1, diags), HALO_OK);
    CHECK_NO_ERRORS(diags);
    CHECK_NEAR(halo_program_find_uniform(p, "boundary", "k_gs")->value[0], 20, 0);
    v = 1001;
    CHECK_INT_EQ(halo_program_set(p, "boundary", "k_gs", &v, 1, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_SCENE_VALUE_ABOVE_MAX);
    v = NAN;
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_program_set(p, "boundary", "k_gs", &v, 1, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_SCENE_VALUE_NONFINITE);
    CHECK_NEAR(halo_program_find_uniform(p, "boundary", "k_gs")->value[0], 20, 0);
    /* A live parameter that schedules image passes (halo_generate.passes: repeat= and
     * reach=; median: when=) cannot change without a new link; its linked value can be set. */
    halo_program *h = link_valid(
        "{\"stages\": [{\"halo_seed\": {}}, {\"halo_generate\": {\"live\": [\"passes\","
        " \"median\", \"delta\"]}}, {\"halo_map\": {}}]}");
    CHECK(h != NULL);
    double passes = 5, linked = 4, on = 1, delta = 0.5;
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_program_set(h, "halo_generate", "passes", &passes, 1, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_USAGE);
    CHECK_NEAR(halo_program_find_uniform(h, "halo_generate", "passes")->value[0], 4, 0);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_program_set(h, "halo_generate", "median", &on, 1, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_USAGE);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_program_set(h, "halo_generate", "passes", &linked, 1, diags), HALO_OK);
    CHECK_INT_EQ(halo_program_set(h, "halo_generate", "delta", &delta, 1, diags), HALO_OK);
    CHECK_NO_ERRORS(diags);
    halo_program_destroy(h);
    /* A constant cannot change: it is compiled in. */
    v = 1;
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_program_set(p, "boundary", "k_ge", &v, 1, diags), HALO_ERROR_INPUT);
    CHECK(halo_diagnostics_errors(diags) >= 1);
    CHECK_NEAR(halo_program_find_uniform(p, "boundary", "k_ge")->value[0], 2, 0);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_program_set(p, "boundary", "k_zz", &v, 1, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_SCENE_PARAM_UNKNOWN);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_program_set(p, "sketch", "k_le", &v, 1, diags), HALO_ERROR_INPUT);
    CHECK(halo_diagnostics_errors(diags) >= 1);
    /* Arrays: the count changes with the values. */
    const double lights[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_program_set(p, "tone_shading", "lights", lights, 3, diags), HALO_OK);
    const halo_uniform_info *u = halo_program_find_uniform(p, "tone_shading", "lights");
    CHECK_INT_EQ(u->count, 3);
    CHECK_NEAR(u->value[8], 1, 0);
    double too_many[15] = {0};
    CHECK_INT_EQ(halo_program_set(p, "tone_shading", "lights", too_many, 5, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_SCENE_VALUE_COUNT);
    CHECK_INT_EQ(halo_program_find_uniform(p, "tone_shading", "lights")->count, 3);
    halo_program_destroy(p);
    return 0;
}

/* Vertex hosts take no sample stages. */
static int test_hook_mismatch(void)
{
    halo_scene *scene = scene_of("{\"stages\": [\"boundary\"]}");
    halo_diagnostics_clear(diags);
    halo_program *p = halo_link(&(halo_link_desc){.library = library,
                                                  .scene = scene,
                                                  .host_source = "#pragma halo declarations\nvoid main() {}\n",
                                                  .kind = HALO_SHADER_VERTEX},
                                diags);
    halo_scene_destroy(scene);
    CHECK(p == NULL);
    CHECK_DIAG(diags, HALO_MSG_LINK_HOOK_MISMATCH);
    return 0;
}

/* User modules for the tests above, added to the library once. */
static const char *const user_modules[][2] = {
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

/* Host contract 2: a host that declares `#pragma halo compositing mip` composites no
 * samples, so any stage is refused at the pragma (HOST_COMPOSITING); with none it links.
 * A host whose gradient is derived from its sampler (`#pragma halo volume`) links with
 * image passes: the pass programs do not get the derived gradient's body (they have no
 * host sampler). */
static int test_compositing_mip(void)
{
    static const char mip[] =
        "#version 330 core\n"
        "#pragma halo declarations\n"
        "#pragma halo compositing mip\n"
        "out vec4 c;\n"
        "void main() { c = vec4(1.0);\n"
        "#ifdef HALO_LINKED\n"
        "    halo_finish();\n"
        "#endif\n"
        "}\n";
    halo_scene *scene = scene_of("{\"stages\": [\"boundary\", \"silhouette\"]}");
    halo_program *p = link_with(scene, mip, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    CHECK(p == NULL);
    const halo_diagnostic *g = check_find_diag(diags, HALO_MSG_HOST_COMPOSITING, 3);
    CHECK(g != NULL);
    CHECK(strstr(g->text, "boundary") && strstr(g->text, "silhouette"));
    scene = scene_of("{\"stages\": []}");
    p = link_with(scene, mip, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    CHECK(p != NULL && halo_validate(&(halo_validate_desc){.program = p}, diags) == HALO_OK);
    halo_program_destroy(p);
    if (check_host_error("#version 330 core\n#pragma halo declarations\n#pragma halo compositing max\n"
                         "out vec4 c;\nvoid main() { c = vec4(1.0); }\n",
                         HALO_MSG_ANNOTATION_SYNTAX, 3, 0))
        return 1;
    static const char volume_host[] =
        "#version 330 core\n"
        "#pragma halo declarations\n"
        "#pragma halo volume volume_texture\n"
        "uniform sampler3D volume_texture;\n"
        "in vec3 P;\n"
        "layout(location = 0) out vec4 c;\n"
        "void main() {\n"
        "    vec4 a = vec4(0.0);\n"
        "    int first = 0, end = 8;\n"
        "    halo_segment_begin(P, vec3(0.0, 0.0, 1.0), 0.0, 0.1, first, end, a);\n"
        "    for (int i = first; i < end; ++i) {\n"
        "        halo_sample s = halo_make_sample(P, texture(volume_texture, P).r, vec3(1.0), 0.1);\n"
        "        halo_apply(s);\n"
        "        a += (1.0 - a.a) * vec4(s.color * s.opacity, s.opacity);\n"
        "    }\n"
        "    halo_segment_end(a, false);\n"
        "    halo_finish();\n"
        "    c = a;\n"
        "}\n";
    scene = scene_of("{\"stages\": [\"halo_seed\", \"halo_generate\", \"halo_map\"]}");
    p = link_with(scene, volume_host, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    if (!p || halo_validate(&(halo_validate_desc){.program = p}, diags) != HALO_OK) {
        check_print_diags(diags);
        halo_program_destroy(p);
        CHECK_FAIL_AT("a '#pragma halo volume' host with image passes does not link and validate");
    }
    CHECK(halo_program_segment_location(p) > 0);
    halo_program_destroy(p);
    return 0;
}

/* What the stages are, read from their modules' '#pragma halo is' (issue 28): the slice
 * host's clipping, its generation skip and the labels check ask these instead of names. */
static int test_stage_info(void)
{
    halo_program *p = link_valid(
        "{\"halo_scene\": 1, \"stages\": [\"gradient\", \"boundary\", \"tone_shading\", "
        "\"halo_seed\", \"halo_generate\", \"halo_map\"]}");
    CHECK(p != NULL);
    if (!p)
        return 1;
    static const struct {
        const char *name;
        int keeps_empty, zero_generation;
    } expect[] = {{"gradient", 1, 0},  {"boundary", 1, 0},      {"tone_shading", 0, 0},
                  {"halo_seed", 1, 0}, {"halo_generate", 1, 1}, {"halo_map", 1, 0}};
    for (size_t k = 0; k < sizeof expect / sizeof expect[0]; k++) {
        int i = stage_index(p, expect[k].name);
        const halo_stage_info *info = i >= 0 ? halo_program_stage_info(p, (size_t)i) : NULL;
        CHECK(info != NULL);
        if (!info)
            continue;
        CHECK_STR_EQ(info->name, expect[k].name);
        CHECK_INT_EQ(info->keeps_empty, expect[k].keeps_empty);
        CHECK_INT_EQ(info->zero_generation, expect[k].zero_generation);
        CHECK(info->labels_when == NULL);
    }
    CHECK(halo_program_stage_info(p, halo_program_stage_count(p)) == NULL);
    CHECK_INT_EQ(halo_program_reads_labels(p), 0);
    /* M from the stage that says which parameter is it (halo_generate: interval, default 4) */
    int generate = stage_index(p, "halo_generate");
    const halo_stage_info *gen = generate >= 0 ? halo_program_stage_info(p, (size_t)generate) : NULL;
    CHECK(gen && gen->interval && !strcmp(gen->interval, "interval"));
    CHECK_INT_EQ(halo_program_interval(p), 4);
    char *json = halo_program_reflect_json(p);
    CHECK(json && strstr(json, "\"stage_info\"") && strstr(json, "\"zero_generation\": true"));
    free(json);
    halo_program_destroy(p);
    p = link_valid(
        "{\"halo_scene\": 1, \"stages\": [\"halo_seed\", {\"halo_generate\": {\"interval\": 7}}, "
        "\"halo_map\"]}");
    CHECK(p && halo_program_interval(p) == 7);
    halo_program_destroy(p);
    p = link_valid("{\"halo_scene\": 1, \"stages\": [\"boundary\"]}");
    CHECK(p && halo_program_interval(p) == 0);
    halo_program_destroy(p);
    /* outline_feature reads the labels only for a feature with label >= 0 */
    p = link_valid(
        "{\"halo_scene\": 1, \"stages\": [\"gradient\", {\"outline_feature\": {\"label\": [-1]}}, "
        "\"outlines\"]}");
    CHECK(p != NULL);
    if (p) {
        const halo_stage_info *info = halo_program_stage_info(p, (size_t)stage_index(p, "outline_feature"));
        CHECK(info && info->labels_when && !strcmp(info->labels_when, "label"));
        CHECK_INT_EQ(halo_program_reads_labels(p), 0);
        halo_program_destroy(p);
    }
    p = link_valid(
        "{\"halo_scene\": 1, \"stages\": [\"gradient\", {\"outline_feature\": {\"label\": [-1, 3]}}, "
        "\"outlines\"]}");
    CHECK(p != NULL);
    if (p) {
        CHECK_INT_EQ(halo_program_reads_labels(p), 1);
        halo_program_destroy(p);
    }
    return 0;
}

int main(void)
{
    SETUP(halo_setup(&(halo_setup_desc){0}) == HALO_OK);
    library = check_library_setup(&diags);
    for (size_t i = 0; i < sizeof user_modules / sizeof user_modules[0]; i++)
        if (halo_library_add(library, user_modules[i][0], user_modules[i][1], HALO_ADD_NEW, diags) != HALO_OK) {
            check_print_diags(diags);
            SETUP_FAIL("cannot add %s", user_modules[i][0]);
        }
    RUN_TEST(test_only_enabled_code);
    RUN_TEST(test_unused_param);
    RUN_TEST(test_empty_scene);
    RUN_TEST(test_renaming);
    RUN_TEST(test_constants_and_uniforms);
    RUN_TEST(test_order);
    RUN_TEST(test_resolution_errors);
    RUN_TEST(test_host_errors);
    RUN_TEST(test_line_map);
    RUN_TEST(test_glsl_errors_mapped);
    RUN_TEST(test_targets);
    RUN_TEST(test_program_set);
    RUN_TEST(test_hook_mismatch);
    RUN_TEST(test_image_scale);
    RUN_TEST(test_occlusion_pass_when_occlusive);
    RUN_TEST(test_pass_reach);
    RUN_TEST(test_pass_reach_wide);
    RUN_TEST(test_generate_pass_lines);
    RUN_TEST(test_feature_groups);
    RUN_TEST(test_compositing_mip);
    RUN_TEST(test_stage_info);
    halo_library_destroy(library);
    halo_diagnostics_destroy(diags);
    halo_shutdown();
    return check_exit_status();
}
