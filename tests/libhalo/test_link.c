/* libhalo/link.c: which stages a scene links and in what order, resolution errors,
 * targets, and the image passes it builds (scales, when=, reach). glslang validates what
 * is linked (halo_validate). No GL. */
#include "link_fixture.h"

/* The helpers of halo_math.glsl that the linked stages call, directly or through
 * other helpers, computed from the modules' own lists. */
static int helper_needed(const halo_program *p, const halo_module *helpers, size_t chunk)
{
    unsigned char need[64] = {0};
    SETUP(helpers->chunk_count <= 64);
    for (size_t c = 0; c < helpers->chunk_count; c++)
        for (size_t s = 0; s < halo_program_reflection(p).stage_count; s++) {
            const halo_module *m = halo_library_find(library, halo_program_reflection(p).stages[s].name);
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
    size_t len = strlen(halo_program_source(p, HALO_PIECE_WHOLE)) + 1;
    for (size_t i = 0; i < halo_program_reflection(p).pass_count; i++)
        len += strlen(halo_program_reflection(p).passes[i].fragment_source) +
               strlen(halo_program_reflection(p).passes[i].vertex_source);
    char *all = malloc(len);
    SETUP(all != NULL);
    strcpy(all, halo_program_source(p, HALO_PIECE_WHOLE));
    for (size_t i = 0; i < halo_program_reflection(p).pass_count; i++) {
        strcat(all, halo_program_reflection(p).passes[i].fragment_source);
        strcat(all, halo_program_reflection(p).passes[i].vertex_source);
    }
    int status = check_only_linked_in(p, all);
    free(all);
    return status;
}

static int check_only_linked_in(const halo_program *p, const char *src)
{
    for (size_t i = 0; i < halo_library_describe(library).module_count; i++) {
        const halo_module *m = halo_library_describe(library).modules[i];
        if (m->is_library)
            continue;
        char prefix[160], comment[160];
        snprintf(prefix, sizeof prefix, "halo_%s_", halo_module_describe(m).name);
        snprintf(comment, sizeof comment, "// stage %s ", halo_module_describe(m).name);
        if (stage_index(p, halo_module_describe(m).name) >= 0) {
            CHECK_STR_CONTAINS(src, prefix);
            CHECK_STR_CONTAINS(src, comment);
        } else {
            CHECK_STR_NOT_CONTAINS(src, prefix);
            CHECK_STR_NOT_CONTAINS(src, comment);
            CHECK_STR_NOT_CONTAINS(src, halo_module_describe(m).file);
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
    CHECK_INT_EQ(halo_program_reflection(p).stage_count, 1);
    CHECK_STR_EQ(halo_program_reflection(p).stages[0].name, "opacity_power");
    if (check_only_linked(p))
        return 1;
    /* opacity_power uses halo_pow and halo_saturate, not the colour helpers. */
    CHECK_STR_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "halo_pow(");
    CHECK_STR_NOT_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "halo_rgb_to_hsv");
    CHECK_STR_NOT_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "halo_normalize");
    halo_program_destroy(p);

    p = link_valid("{\"stages\": [\"silhouette\"]}");
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_program_reflection(p).stage_count, 2); /* with gradient, which provides the normal */
    if (check_only_linked(p))
        return 1;
    CHECK_STR_NOT_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "halo_hsv_to_rgb");
    halo_program_destroy(p);

    /* Each stage alone. */
    for (size_t i = 0; i < halo_library_describe(library).module_count; i++) {
        const halo_module *m = halo_library_describe(library).modules[i];
        if (m->is_library || halo_module_describe(m).hook != HALO_HOOK_SAMPLE ||
            strncmp(halo_module_describe(m).file, "glsl/", 5))
            continue;
        char json[256];
        snprintf(json, sizeof json, "{\"stages\": [\"%s\"]}", halo_module_describe(m).name);
        p = link_valid(json);
        CHECK(p != NULL);
        CHECK(stage_index(p, halo_module_describe(m).name) >= 0);
        if (check_only_linked(p))
            return 1;
        halo_program_destroy(p);
    }

    /* A disabled stage is not linked. */
    p = link_valid("{\"stages\": [\"opacity_power\", {\"sketch\": {\"enabled\": false}}]}");
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_program_reflection(p).stage_count, 1);
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
    CHECK_STR_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "halo_unused_param_used");
    CHECK_STR_NOT_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "halo_unused_param_spare");
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
    CHECK_INT_EQ(halo_program_reflection(p).stage_count, 0);
    CHECK_INT_EQ(halo_program_reflection(p).uniform_count, 0);
    CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p}, diags), HALO_OK);
    if (check_only_linked(p))
        return 1;
    if (check_empty_apply(halo_program_source(p, HALO_PIECE_WHOLE)))
        return 1;
    CHECK_STR_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "#define HALO_LINKED");
    CHECK_STR_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "struct halo_sample");
    CHECK_STR_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "halo_make_sample");
    CHECK_STR_NOT_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "halo_pow");
    CHECK_STR_NOT_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "halo_saturate");
    CHECK_STR_NOT_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "uniform");
    /* No provided fields either. */
    CHECK_STR_NOT_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "gradient_magnitude");
    char *empty_scene_text = strdup(halo_program_source(p, HALO_PIECE_WHOLE));
    halo_program_destroy(p);

    halo_scene *scene = scene_of("{\"stages\": [{\"boundary\": {\"enabled\": false}}]}");
    p = link_with(scene, host_source, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_program_reflection(p).stage_count, 0);
    if (check_empty_apply(halo_program_source(p, HALO_PIECE_WHOLE)))
        return 1;
    /* An empty scene and a scene of disabled stages link to the same text. */
    CHECK_STR_EQ(halo_program_source(p, HALO_PIECE_WHOLE), empty_scene_text);
    free(empty_scene_text);
    halo_program_destroy(p);
    return 0;
}


/* (e) Dependencies are enabled and ordered; the output is deterministic. */
static int test_order(void)
{
    halo_program *p = link_valid("{\"stages\": [\"silhouette\"]}");
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_program_reflection(p).stage_count, 2);
    CHECK_STR_EQ(halo_program_reflection(p).stages[0].name, "gradient");
    CHECK_STR_EQ(halo_program_reflection(p).stages[1].name, "silhouette");
    const char *src = halo_program_source(p, HALO_PIECE_WHOLE);
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
        for (size_t k = 0; k < halo_program_reflection(p).stage_count; k++) {
            const halo_module *m = halo_library_find(library, halo_program_reflection(p).stages[k].name);
            for (size_t a = 0; a < m->after.count; a++) {
                int before = stage_index(p, m->after.items[a]);
                if (before >= 0 && before > (int)k)
                    CHECK_FAIL_AT("%s runs before %s, which it must follow", m->name, m->after.items[a]);
            }
            if (m->needs.count)
                CHECK(stage_index(p, "gradient") < (int)k);
        }
        src = halo_program_source(p, HALO_PIECE_WHOLE);
        CHECK(line_containing(src, "halo_tone_shading_apply(s);") <
              line_containing(src, "halo_distance_blend_apply(s);"));
        /* Deterministic: linking again gives the same text. */
        halo_scene *scene = scene_of(scenes[i]);
        halo_program *again = link_with(scene, host_source, HALO_TARGET_DEFAULT, 0);
        halo_scene_destroy(scene);
        CHECK(again != NULL);
        CHECK_STR_EQ(halo_program_source(again, HALO_PIECE_WHOLE), halo_program_source(p, HALO_PIECE_WHOLE));
        halo_program_destroy(again);
        halo_program_destroy(p);
    }
    /* The two scene orders of the same stages give the same program. */
    halo_scene *a = scene_of(scenes[0]);
    halo_program *pa = link_with(a, host_source, HALO_TARGET_DEFAULT, 0);
    halo_scene *b = scene_of(scenes[1]);
    halo_program *pb = link_with(b, host_source, HALO_TARGET_DEFAULT, 0);
    CHECK(pa && pb);
    CHECK_STR_EQ(halo_program_source(pa, HALO_PIECE_WHOLE), halo_program_source(pb, HALO_PIECE_WHOLE));
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
    CHECK_STR_EQ(halo_program_reflection(p).stages[0].name, "provider_b");
    CHECK_STR_EQ(halo_program_reflection(p).stages[1].name, "needs_thing");
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


static int link_target(const halo_scene *scene, const char *host, halo_target target, int all_live)
{
    halo_program *p = link_with(scene, host, target, all_live);
    CHECK(p != NULL);
    CHECK_INT_EQ(halo_program_reflection(p).target, target == HALO_TARGET_DEFAULT ? HALO_TARGET_GLSL330 : target);
    if (halo_validate(&(halo_validate_desc){.program = p}, diags) != HALO_OK) {
        check_print_diags(diags);
        CHECK_FAIL_AT("does not validate for target %s (all_live %d)", halo_target_name(target), all_live);
    }
    const char *src = halo_program_source(p, HALO_PIECE_WHOLE);
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
    for (size_t i = 0; i < halo_library_describe(library).module_count; i++) {
        const halo_module *m = halo_library_describe(library).modules[i];
        if (!m->is_library && halo_module_describe(m).hook == HALO_HOOK_SAMPLE &&
            !strncmp(halo_module_describe(m).file, "glsl/", 5))
            SETUP(halo_scene_enable(scene, halo_module_describe(m).name, 1, diags) == HALO_OK);
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
        CHECK_INT_EQ(halo_program_reflection(p).image_scale, scale);
        int seen = 0;
        for (size_t i = 0; i < halo_program_reflection(p).image_count; i++) {
            const halo_image_info *im = &halo_program_reflection(p).images[i];
            int expected = !strcmp(im->name, "seed") ? 1 : scale;
            CHECK_INT_EQ(im->scale, expected);
            seen += !strcmp(im->name, "field") || !strcmp(im->name, "seed");
        }
        CHECK_INT_EQ(seen, 2);
        if (scale > 1) {
            /* the bilinear read: through the unit's filter on desktop GLSL (one fetch) */
            CHECK_STR_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "textureLod(halo_image_field, at, 0.0)");
            CHECK_STR_NOT_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "floor(at)");
            /* OpenGL ES: 32-bit float images written out with four fetches (ES 3.0 filters
             * them only with OES_texture_float_linear), 16-bit ones filtered */
            for (int precision = 16; precision <= 32; precision += 16) {
                halo_program *es = halo_link(&(halo_link_desc){.library = library,
                                                               .scene = scene,
                                                               .host_source = host_source,
                                                               .host_file = "test.frag",
                                                               .target = HALO_TARGET_ES300,
                                                               .image_precision = precision,
                                                               .image_scale = scale},
                                             diags);
                CHECK(es != NULL);
                if (es)
                    CHECK_INT_EQ(strstr(halo_program_source(es, HALO_PIECE_WHOLE), "floor(at)") != NULL,
                                 precision == 32);
                halo_program_destroy(es);
            }
            const halo_pass_info *gradient = NULL;
            for (size_t i = 0; i < halo_program_reflection(p).pass_count; i++)
                if (!strcmp(halo_program_reflection(p).passes[i].name, "gradient"))
                    gradient = &halo_program_reflection(p).passes[i];
            CHECK(gradient != NULL);
            CHECK_STR_CONTAINS(gradient->fragment_source, "m = max(m, halo_fetch_0"); /* seed: block max */
        } else {
            CHECK_STR_NOT_CONTAINS(halo_program_source(p, HALO_PIECE_WHOLE), "floor(at)");
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
    for (size_t i = 0; i < halo_program_reflection(p).pass_count; i++)
        if (!strcmp(halo_program_reflection(p).passes[i].name, name))
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
        for (size_t i = 0; i < halo_program_reflection(p).pass_count; i++)
            if (!strcmp(halo_program_reflection(p).passes[i].name, "spread"))
                CHECK_INT_EQ(halo_program_reflection(p).passes[i].start, 1);
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
    for (size_t i = 0; i < halo_program_reflection(p).pass_count; i++) {
        const halo_pass_info *pass = &halo_program_reflection(p).passes[i];
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
        for (size_t i = 0; i < halo_program_reflection(p).pass_count; i++)
            snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", i ? "," : "",
                     halo_program_reflection(p).passes[i].name);
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
        for (size_t i = 0; i < halo_program_reflection(p).pass_count; i++) {
            const halo_pass_info *pass = &halo_program_reflection(p).passes[i];
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
    CHECK_INT_EQ(halo_program_reflection(p).group_count, 2);
    CHECK_INT_EQ(halo_program_reflection(p).channel_count, 4);
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
    /* the declarations an engine sets (halo_reflection.declarations) follow the group */
    int declared = 0;
    for (size_t i = 0; i < halo_program_reflection(p).declaration_count; i++) {
        const halo_uniform_decl *u = &halo_program_reflection(p).declarations[i];
        if (u->param == vmin) {
            declared = 1;
            CHECK(u->value != NULL && u->count == 1);
            CHECK_NEAR(u->value[0], 0.5, 0);
            CHECK_NEAR(u->value[3], 0.6, 0);
        }
    }
    CHECK(declared);
    CHECK_INT_EQ(halo_program_select_group(p, 0), HALO_OK);
    CHECK_NEAR(vmin->value[1], 0.2, 0);
    for (size_t i = 0; i < halo_program_reflection(p).declaration_count; i++)
        if (halo_program_reflection(p).declarations[i].param == vmin)
            CHECK_NEAR(halo_program_reflection(p).declarations[i].value[1], 0.2, 0);
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
    for (size_t i = 0; i < halo_program_reflection(p).pass_count; i++) {
        reduce |= !strcmp(halo_program_reflection(p).passes[i].name, "reduce") &&
                  halo_program_reflection(p).passes[i].at == HALO_PASS_AT_POST;
        final |= !strcmp(halo_program_reflection(p).passes[i].name, "compose") &&
                 halo_program_reflection(p).passes[i].at == HALO_PASS_AT_FINAL;
    }
    CHECK(reduce && final);
    halo_program_destroy(p);
    halo_scene_destroy(scene);
    /* four features: one group, parameters constant as before */
    halo_program *q =
        link_valid("{\"stages\": [{\"outline_feature\": {\"value_min\": [0.1, 0.2, 0.3, 0.4]}}, \"outlines\"]}");
    CHECK(q != NULL);
    CHECK_INT_EQ(halo_program_reflection(q).group_count, 1);
    CHECK(!halo_program_find_uniform(q, "outline_feature", "value_min")->live);
    CHECK_INT_EQ(halo_program_select_group(q, 0), HALO_OK);
    CHECK_INT_EQ(halo_program_select_group(q, 1), HALO_ERROR_INPUT);
    halo_program_destroy(q);
    /* more than 16 features, or more than four halos: the scene says no */
    halo_diagnostics_clear(diags);
    CHECK(halo_scene_load(
              "t.json",
              "{\"stages\": [{\"outline_feature\": {\"label\": [1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17]}}]}",
              library, diags) == NULL);
    halo_diagnostics_clear(diags);
    CHECK(halo_scene_load("t.json", "{\"stages\": [{\"halo_seed\": {\"alpha\": [1, 2, 3, 4, 5]}}]}", library, diags) ==
          NULL);
    halo_diagnostics_clear(diags);
    return 0;
}


int main(void)
{
    link_fixture_setup();
    RUN_TEST(test_only_enabled_code);
    RUN_TEST(test_unused_param);
    RUN_TEST(test_empty_scene);
    RUN_TEST(test_order);
    RUN_TEST(test_resolution_errors);
    RUN_TEST(test_targets);
    RUN_TEST(test_image_scale);
    RUN_TEST(test_occlusion_pass_when_occlusive);
    RUN_TEST(test_pass_reach);
    RUN_TEST(test_pass_reach_wide);
    RUN_TEST(test_generate_pass_lines);
    RUN_TEST(test_feature_groups);
    return link_fixture_finish();
}
