/* Scenes (halo_scene_load, halo_scene_set): valid scenes, and every error with its
 * message id and the JSON path in its text. No GL, no glslang. */
#include "check.h"
#include "internal.h"

static halo_library *library;
static halo_diagnostics *diags;

static halo_scene *parse(const char *json)
{
    halo_diagnostics_clear(diags);
    return halo_scene_load("test.json", json, library, diags);
}

/* The scene's value record of stage.param (internal), or NULL. */
static const halo_param_value *value_of(const halo_scene *s, const char *stage, const char *param)
{
    for (size_t i = 0; i < s->count; i++) {
        const halo_module *m = s->stages[i].module;
        if (strcmp(halo_module_describe(m).name, stage))
            continue;
        const halo_param_info *info = halo_module_find_param(m, param);
        return info ? &s->stages[i].values[info - m->params] : NULL;
    }
    return NULL;
}

static int enabled_of(const halo_scene *s, const char *stage)
{
    for (size_t i = 0; i < s->count; i++)
        if (!strcmp(halo_module_describe(s->stages[i].module).name, stage))
            return s->stages[i].enabled;
    return -1;
}

/* The scene is rejected with ID, and the text of that diagnostic names PATH. */
#define CHECK_REJECTED(JSON, ID, PATH)                                  \
    do {                                                                \
        halo_scene *rejected_ = parse(JSON);                            \
        if (rejected_) {                                                \
            halo_scene_destroy(rejected_);                              \
            CHECK_FAIL_AT("scene accepted: %s", JSON);                  \
        }                                                               \
        CHECK_DIAG(diags, ID);                                          \
        CHECK_STR_CONTAINS(check_find_diag(diags, ID, 0)->text, PATH);  \
        CHECK_STR_EQ(check_find_diag(diags, ID, 0)->file, "test.json"); \
    } while (0)

static int test_valid_scene(void)
{
    halo_scene *s = parse(
        "{\"halo_scene\":1, \"description\": \"a test\",\n"
        " \"stages\":[ \"silhouette\",\n"
        "   {\"boundary\":{\"k_gs\":12.5,\"live\":[\"k_gc\"],\"enabled\":true}},\n"
        "   {\"tone_shading\":{\"lights\":[[1,0,0],[0,1,0],[0,0,-1]], \"k_ty\": 0}},\n"
        "   {\"distance_blend\":{\"background\":[0.1,0.2,0.3], \"enabled\": false}},\n"
        "   {\"sketch\":{\"live\": true}}\n"
        " ],\n"
        " \"render\":{\"azimuth\":45, \"elevation\":-10, \"zoom\":2, \"step\":0.25,\n"
        "   \"background\":[0.5,0.5,0.5], \"window\":[0.1,0.9],\n"
        "   \"transfer\":[[0,0,0,0,0],[0.5,1,0.5,0.25,0.1],[1,1,1,1,1]]}}\n");
    CHECK_NO_ERRORS(diags);
    CHECK(s != NULL);
    CHECK_INT_EQ(halo_scene_describe(s).stage_count, 5);
    CHECK_STR_EQ(halo_scene_describe(s).stages[0], "silhouette");
    CHECK_STR_EQ(halo_scene_describe(s).stages[1], "boundary");
    CHECK_STR_EQ(halo_scene_describe(s).stages[2], "tone_shading");
    CHECK_STR_EQ(halo_scene_describe(s).stages[3], "distance_blend");
    CHECK_STR_EQ(halo_scene_describe(s).stages[4], "sketch");

    const halo_param_value *v = value_of(s, "boundary", "k_gs");
    CHECK(v != NULL);
    CHECK_NEAR(v->value[0], 12.5, 0);
    CHECK_INT_EQ(v->live, 0);
    v = value_of(s, "boundary", "k_gc");
    CHECK_INT_EQ(v->live, 1);
    CHECK_NEAR(v->value[0], 0.7, 0); /* the default */
    v = value_of(s, "silhouette", "k_ss");
    CHECK_NEAR(v->value[0], 50, 0); /* the default */
    v = value_of(s, "tone_shading", "lights");
    CHECK_INT_EQ(v->count, 3);
    CHECK_NEAR(v->value[0], 1, 0);
    CHECK_NEAR(v->value[4], 1, 0);
    CHECK_NEAR(v->value[8], -1, 0);
    CHECK_NEAR(value_of(s, "tone_shading", "k_ty")->value[0], 0, 0);
    v = value_of(s, "distance_blend", "background");
    CHECK_NEAR(v->value[1], 0.2, 0);
    CHECK_INT_EQ(enabled_of(s, "boundary"), 1);
    CHECK_INT_EQ(enabled_of(s, "distance_blend"), 0);
    CHECK_INT_EQ(value_of(s, "sketch", "k_le")->live, 1);
    CHECK_INT_EQ(value_of(s, "sketch", "line_color")->live, 1);

    const halo_render_settings *r = halo_scene_describe(s).render;
    CHECK_NEAR(r->azimuth, 45, 0);
    CHECK_NEAR(r->elevation, -10, 0);
    CHECK_NEAR(r->zoom, 2, 0);
    CHECK_NEAR(r->step, 0.25, 0);
    CHECK_NEAR(r->background[2], 0.5, 0);
    CHECK_NEAR(r->window[0], 0.1, 0);
    CHECK_NEAR(r->window[1], 0.9, 0);
    CHECK_INT_EQ(r->transfer_count, 3);
    CHECK_NEAR(r->transfer[1][3], 0.25, 0);
    halo_scene_destroy(s);
    return 0;
}

static int test_minimal_scenes(void)
{
    halo_scene *s = parse("{}");
    CHECK(s != NULL);
    CHECK_INT_EQ(halo_scene_describe(s).stage_count, 0);
    const halo_render_settings *r = halo_scene_describe(s).render;
    CHECK(r->zoom > 0);
    CHECK(r->transfer_count >= 1);
    halo_scene_destroy(s);
    s = parse("{\"halo_scene\": 1, \"stages\": []}");
    CHECK(s != NULL);
    CHECK_INT_EQ(halo_scene_describe(s).stage_count, 0);
    halo_scene_destroy(s);
    /* An integer-valued parameter given as 10 or 10.0 is the same. */
    s = parse("{\"stages\": [{\"boundary\": {\"k_gs\": 10.0, \"k_ge\": 3}}]}");
    CHECK(s != NULL);
    CHECK_NEAR(value_of(s, "boundary", "k_ge")->value[0], 3, 0);
    halo_scene_destroy(s);
    return 0;
}

static int test_bad_json(void)
{
    halo_scene *s = parse(
        "{\"halo_scene\": 1,\n"
        " \"stages\": [\n"
        "   \"boundary\",,\n"
        " ]}\n");
    CHECK(s == NULL);
    CHECK_DIAG(diags, HALO_MSG_SCENE_JSON);
    const halo_diagnostic *g = check_find_diag(diags, HALO_MSG_SCENE_JSON, 0);
    CHECK_INT_EQ(g->line, 3);
    CHECK(g->column > 0);
    CHECK_STR_EQ(g->file, "test.json");
    /* Not JSON at all; empty; trailing garbage; duplicate keys. */
    static const char *const bad[] = {"stages: [boundary]", "", "{} {}", "{\"stages\": [], \"stages\": []}",
                                      "{\"stages\": [\"boundary\"]"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        s = parse(bad[i]);
        if (s) {
            halo_scene_destroy(s);
            CHECK_FAIL_AT("accepted: %s", bad[i]);
        }
        CHECK_DIAG(diags, HALO_MSG_SCENE_JSON);
        CHECK(check_find_diag(diags, HALO_MSG_SCENE_JSON, 0)->line > 0);
    }
    return 0;
}

static int test_top_level(void)
{
    CHECK_REJECTED("{\"halo_scene\": 1, \"stagez\": []}", HALO_MSG_SCENE_KEY_UNKNOWN, "stagez");
    CHECK_REJECTED("{\"halo_scene\": 2}", HALO_MSG_SCENE_VERSION, "halo_scene");
    CHECK_REJECTED("[\"boundary\"]", HALO_MSG_SCENE_TYPE, "");
    CHECK_REJECTED("{\"stages\": \"boundary\"}", HALO_MSG_SCENE_TYPE, "stages");
    CHECK_REJECTED("{\"description\": 3}", HALO_MSG_SCENE_TYPE, "description");
    return 0;
}

static int test_stage_errors(void)
{
    CHECK_REJECTED("{\"stages\": [\"boundary\", \"no_such_stage\"]}", HALO_MSG_SCENE_STAGE_UNKNOWN, "stages[1]");
    CHECK_STR_CONTAINS(check_find_diag(diags, HALO_MSG_SCENE_STAGE_UNKNOWN, 0)->text, "no_such_stage");
    /* The helper library is no stage. */
    CHECK_REJECTED("{\"stages\": [\"halo_math\"]}", HALO_MSG_SCENE_STAGE_UNKNOWN, "stages[0]");
    CHECK_REJECTED("{\"stages\": [\"boundary\", {\"silhouette\": {}}, {\"boundary\": {\"k_gs\": 1}}]}",
                   HALO_MSG_SCENE_STAGE_DUPLICATE, "stages[2]");
    CHECK_REJECTED("{\"stages\": [{\"boundary\": {\"k_gz\": 1}}]}", HALO_MSG_SCENE_PARAM_UNKNOWN,
                   "stages[0].boundary.k_gz");
    CHECK_REJECTED("{\"stages\": [{\"boundary\": 3}]}", HALO_MSG_SCENE_TYPE, "stages[0].boundary");
    CHECK_REJECTED("{\"stages\": [{\"boundary\": {}, \"silhouette\": {}}]}", HALO_MSG_SCENE_TYPE, "stages[0]");
    CHECK_REJECTED("{\"stages\": [3]}", HALO_MSG_SCENE_TYPE, "stages[0]");
    CHECK_REJECTED("{\"stages\": [{\"boundary\": {\"enabled\": 1}}]}", HALO_MSG_SCENE_TYPE,
                   "stages[0].boundary.enabled");
    return 0;
}

static int test_wrong_types(void)
{
    CHECK_REJECTED("{\"stages\": [{\"boundary\": {\"k_gs\": \"ten\"}}]}", HALO_MSG_SCENE_TYPE,
                   "stages[0].boundary.k_gs");
    CHECK_REJECTED("{\"stages\": [{\"boundary\": {\"k_gs\": [10]}}]}", HALO_MSG_SCENE_TYPE, "stages[0].boundary.k_gs");
    CHECK_REJECTED("{\"stages\": [{\"boundary\": {\"k_gs\": null}}]}", HALO_MSG_SCENE_TYPE, "stages[0].boundary.k_gs");
    CHECK_REJECTED("{\"stages\": [{\"boundary\": {\"k_gs\": true}}]}", HALO_MSG_SCENE_TYPE, "stages[0].boundary.k_gs");
    CHECK_REJECTED("{\"stages\": [{\"distance_blend\": {\"background\": 0.5}}]}", HALO_MSG_SCENE_TYPE,
                   "stages[0].distance_blend.background");
    CHECK_REJECTED("{\"stages\": [{\"distance_blend\": {\"background\": [0, \"a\", 0]}}]}", HALO_MSG_SCENE_TYPE,
                   "stages[0].distance_blend.background");
    CHECK_REJECTED("{\"stages\": [{\"tone_shading\": {\"lights\": [1, 0, 0]}}]}", HALO_MSG_SCENE_TYPE,
                   "stages[0].tone_shading.lights");
    return 0;
}

static int test_range(void)
{
    CHECK_REJECTED("{\"stages\": [\"silhouette\", \"sketch\", {\"boundary\": {\"k_gs\": -1}}]}",
                   HALO_MSG_SCENE_VALUE_BELOW_MIN, "stages[2].boundary.k_gs");
    CHECK_REJECTED("{\"stages\": [{\"boundary\": {\"k_ge\": 64.5}}]}", HALO_MSG_SCENE_VALUE_ABOVE_MAX,
                   "stages[0].boundary.k_ge");
    CHECK_REJECTED("{\"stages\": [{\"distance_blend\": {\"background\": [0, 1.5, 0]}}]}",
                   HALO_MSG_SCENE_VALUE_ABOVE_MAX, "stages[0].distance_blend.background");
    CHECK_REJECTED("{\"stages\": [{\"tone_shading\": {\"lights\": [[0, 0, 1], [0, -2, 0]]}}]}",
                   HALO_MSG_SCENE_VALUE_BELOW_MIN, "stages[0].tone_shading.lights");
    /* The bounds themselves are allowed. */
    halo_scene *s = parse("{\"stages\": [{\"boundary\": {\"k_gs\": 0, \"k_ge\": 64, \"k_gc\": 1000}}]}");
    CHECK_NO_ERRORS(diags);
    CHECK(s != NULL);
    halo_scene_destroy(s);
    return 0;
}

/* JSON has no NaN or infinity; halo_scene_set takes any double. */
static int test_nonfinite(void)
{
    halo_scene *s = halo_scene_create(library);
    SETUP(s != NULL);
    const double bad[] = {NAN, INFINITY, -INFINITY};
    for (int i = 0; i < 3; i++) {
        halo_diagnostics_clear(diags);
        CHECK_INT_EQ(halo_scene_set(s, "boundary", "k_gs", &bad[i], 1, 0, diags), HALO_ERROR_INPUT);
        CHECK_DIAG(diags, HALO_MSG_SCENE_VALUE_NONFINITE);
        CHECK_STR_CONTAINS(check_find_diag(diags, HALO_MSG_SCENE_VALUE_NONFINITE, 0)->text, "k_gs");
    }
    const double color[3] = {0.5, NAN, 0.5};
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_scene_set(s, "distance_blend", "background", color, 1, 0, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_SCENE_VALUE_NONFINITE);
    /* The scene is unchanged by the rejected values. */
    CHECK_INT_EQ(halo_scene_describe(s).stage_count, 0);
    const double ok = 20;
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_scene_set(s, "boundary", "k_gs", &ok, 1, 0, diags), HALO_OK);
    CHECK_INT_EQ(halo_scene_set(s, "boundary", "k_gs", &bad[0], 1, 0, diags), HALO_ERROR_INPUT);
    CHECK_NEAR(value_of(s, "boundary", "k_gs")->value[0], 20, 0);
    halo_scene_destroy(s);
    /* Numbers JSON cannot hold as a finite double. */
    s = parse("{\"stages\": [{\"boundary\": {\"k_gs\": 1e999}}]}");
    CHECK(s == NULL);
    CHECK(halo_diagnostics_describe(diags).errors >= 1);
    s = parse("{\"stages\": [{\"boundary\": {\"k_gs\": NaN}}]}");
    CHECK(s == NULL);
    CHECK_DIAG(diags, HALO_MSG_SCENE_JSON);
    return 0;
}

static int test_counts(void)
{
    /* tone_shading.lights is vec3[4]: five lights are too many, none too few. The id
     * (SCENE_VALUE_COUNT) is checked in test_scene_counts. */
    halo_scene *rejected =
        parse("{\"stages\": [{\"tone_shading\": {\"lights\": [[1,0,0],[0,1,0],[0,0,1],[1,1,0],[0,1,1]]}}]}");
    CHECK(rejected == NULL);
    CHECK_INT_EQ(halo_diagnostics_describe(diags).errors, 1);
    CHECK_STR_CONTAINS(halo_diagnostics_get(diags, 0)->text, "stages[0].tone_shading.lights");
    rejected = parse("{\"stages\": [{\"tone_shading\": {\"lights\": []}}]}");
    CHECK(rejected == NULL);
    CHECK_STR_CONTAINS(halo_diagnostics_get(diags, 0)->text, "stages[0].tone_shading.lights");
    halo_scene *s = halo_scene_create(library);
    SETUP(s != NULL);
    double lights[15] = {0};
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_scene_set(s, "tone_shading", "lights", lights, 5, 0, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_SCENE_VALUE_COUNT);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_scene_set(s, "tone_shading", "lights", lights, 0, 0, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_SCENE_VALUE_COUNT);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_scene_set(s, "boundary", "k_gs", lights, 2, 0, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_SCENE_VALUE_COUNT);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_scene_set(s, "tone_shading", "lights", lights, 4, 0, diags), HALO_OK);
    CHECK_INT_EQ(value_of(s, "tone_shading", "lights")->count, 4);
    halo_scene_destroy(s);
    return 0;
}

static int test_render_errors(void)
{
    CHECK_REJECTED("{\"render\": {\"zoom\": 0}}", HALO_MSG_SCENE_VALUE_BELOW_MIN, "render.zoom");
    CHECK_REJECTED("{\"render\": {\"elevation\": 91}}", HALO_MSG_SCENE_VALUE_ABOVE_MAX, "render.elevation");
    CHECK_REJECTED("{\"render\": {\"azimuth\": \"north\"}}", HALO_MSG_SCENE_TYPE, "render.azimuth");
    CHECK_REJECTED("{\"render\": {\"background\": [0, 0]}}", HALO_MSG_SCENE_VALUE_COUNT, "render.background");
    CHECK_REJECTED("{\"render\": {\"background\": [0, 0, 2]}}", HALO_MSG_SCENE_VALUE_ABOVE_MAX, "render.background[2]");
    CHECK_REJECTED("{\"render\": {\"colour\": 1}}", HALO_MSG_SCENE_KEY_UNKNOWN, "render.colour");
    CHECK_REJECTED("{\"render\": 5}", HALO_MSG_SCENE_TYPE, "render");
    CHECK_REJECTED("{\"render\": {\"transfer\": []}}", HALO_MSG_SCENE_VALUE_COUNT, "render.transfer");
    CHECK_REJECTED("{\"render\": {\"transfer\": [[0,0,0,0,0], [0.5,1,1]]}}", HALO_MSG_SCENE_VALUE_COUNT,
                   "render.transfer[1]");
    CHECK_REJECTED("{\"render\": {\"transfer\": [[0,0,0,0,0], [0.5,1,1,1,1.5]]}}", HALO_MSG_SCENE_VALUE_ABOVE_MAX,
                   "render.transfer[1][4]");
    /* Window end not above its start; transfer points out of order. */
    halo_scene *s = parse("{\"render\": {\"window\": [0.5, 0.5]}}");
    CHECK(s == NULL);
    CHECK(halo_diagnostics_describe(diags).errors >= 1);
    CHECK_STR_CONTAINS(halo_diagnostics_get(diags, 0)->text, "render.window");
    s = parse("{\"render\": {\"transfer\": [[0.5,0,0,0,0], [0.25,1,1,1,1]]}}");
    CHECK(s == NULL);
    CHECK(halo_diagnostics_describe(diags).errors >= 1);
    CHECK_STR_CONTAINS(halo_diagnostics_get(diags, 0)->text, "render.transfer[1]");
    return 0;
}

static int test_live_lists(void)
{
    halo_scene *s = parse(
        "{\"stages\": [{\"silhouette\": {\"live\": [\"k_ss\", \"k_se\"]}},"
        " {\"boundary\": {\"live\": false}}, {\"sketch\": {\"live\": true, \"k_le\": 4}}]}");
    CHECK_NO_ERRORS(diags);
    CHECK(s != NULL);
    CHECK_INT_EQ(value_of(s, "silhouette", "k_sc")->live, 0);
    CHECK_INT_EQ(value_of(s, "silhouette", "k_ss")->live, 1);
    CHECK_INT_EQ(value_of(s, "silhouette", "k_se")->live, 1);
    CHECK_INT_EQ(value_of(s, "boundary", "k_gs")->live, 0);
    CHECK_INT_EQ(value_of(s, "sketch", "k_le")->live, 1);
    CHECK_NEAR(value_of(s, "sketch", "k_le")->value[0], 4, 0);
    halo_scene_destroy(s);
    CHECK_REJECTED("{\"stages\": [{\"silhouette\": {\"live\": [\"k_zz\"]}}]}", HALO_MSG_SCENE_PARAM_UNKNOWN,
                   "stages[0].silhouette.live[0]");
    CHECK_REJECTED("{\"stages\": [{\"silhouette\": {\"live\": [\"k_ss\", 3]}}]}", HALO_MSG_SCENE_PARAM_UNKNOWN,
                   "stages[0].silhouette.live[1]");
    CHECK_REJECTED("{\"stages\": [{\"silhouette\": {\"live\": \"k_ss\"}}]}", HALO_MSG_SCENE_TYPE,
                   "stages[0].silhouette.live");
    return 0;
}

/* Every error in a scene is reported, not only the first. */
static int test_all_errors_reported(void)
{
    halo_scene *s = parse(
        "{\"stages\": [\"nope\", {\"boundary\": {\"k_gs\": -1, \"k_zz\": 1}}],"
        " \"render\": {\"zoom\": 100}, \"extra\": 1}");
    CHECK(s == NULL);
    CHECK_DIAG(diags, HALO_MSG_SCENE_STAGE_UNKNOWN);
    CHECK_DIAG(diags, HALO_MSG_SCENE_VALUE_BELOW_MIN);
    CHECK_DIAG(diags, HALO_MSG_SCENE_PARAM_UNKNOWN);
    CHECK_DIAG(diags, HALO_MSG_SCENE_VALUE_ABOVE_MAX);
    CHECK_DIAG(diags, HALO_MSG_SCENE_KEY_UNKNOWN);
    CHECK_INT_EQ(halo_diagnostics_describe(diags).errors, 5);
    return 0;
}

static int test_api(void)
{
    halo_scene *s = halo_scene_create(library);
    SETUP(s != NULL);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_scene_enable(s, "no_such_stage", 1, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_SCENE_STAGE_UNKNOWN);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_scene_enable(s, "halo_math", 1, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_SCENE_STAGE_UNKNOWN);
    halo_diagnostics_clear(diags);
    double v = 1;
    CHECK_INT_EQ(halo_scene_set(s, "boundary", "k_zz", &v, 1, 0, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_SCENE_PARAM_UNKNOWN);
    halo_diagnostics_clear(diags);
    v = -3;
    CHECK_INT_EQ(halo_scene_set(s, "boundary", "k_gs", &v, 1, 0, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_SCENE_VALUE_BELOW_MIN);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_scene_enable(s, "sketch", 1, diags), HALO_OK);
    CHECK_INT_EQ(halo_scene_enable(s, "sketch", 0, diags), HALO_OK);
    CHECK_INT_EQ(halo_scene_describe(s).stage_count, 1);
    CHECK_INT_EQ(enabled_of(s, "sketch"), 0);
    v = 5;
    CHECK_INT_EQ(halo_scene_set(s, "boundary", "k_gs", &v, 1, 1, diags), HALO_OK);
    CHECK_NO_ERRORS(diags);
    CHECK_INT_EQ(enabled_of(s, "boundary"), 1);
    CHECK_INT_EQ(value_of(s, "boundary", "k_gs")->live, 1);
    halo_render_settings r = *halo_scene_describe(s).render;
    r.zoom = 3;
    halo_scene_set_render(s, &r);
    CHECK_NEAR(halo_scene_describe(s).render->zoom, 3, 0);
    halo_scene_destroy(s);
    halo_scene_destroy(NULL);
    return 0;
}

static int test_load(void)
{
    halo_diagnostics_clear(diags);
    halo_scene *s = halo_scene_load("/nonexistent/dir/scene.json", NULL, library, diags);
    CHECK(s == NULL);
    CHECK_DIAG(diags, HALO_MSG_IO_READ);
    CHECK_STR_EQ(check_find_diag(diags, HALO_MSG_IO_READ, 0)->file, "/nonexistent/dir/scene.json");
    return 0;
}

/* Each semantic error at the line and column of the value (or, for an unknown key, of
 * the key) besides its JSON path, with the line shown. */
static int test_error_places(void)
{
    CHECK(parse("{\n"
                "  \"halo_scene\": 1,\n"
                "  \"stages\": [\n"
                "    {\"boundary\": {\"k_gs\": -1, \"bogus\": 1}},\n"
                "    \"nosuch\"\n"
                "  ],\n"
                "  \"render\": {\"elevation\": 200, \"background\": [0, 2, 0], \"what\": 1}\n"
                "}\n") == NULL);
    static const struct {
        halo_message_id id;
        int line, column;
    } places[] = {
        {HALO_MSG_SCENE_VALUE_BELOW_MIN, 4, 27}, /* -1 */
        {HALO_MSG_SCENE_PARAM_UNKNOWN, 4, 31},   /* "bogus" */
        {HALO_MSG_SCENE_STAGE_UNKNOWN, 5, 5},    /* "nosuch" */
        {HALO_MSG_SCENE_VALUE_ABOVE_MAX, 7, 27}, /* 200 */
        {HALO_MSG_SCENE_KEY_UNKNOWN, 7, 57},     /* "what" */
    };
    for (size_t i = 0; i < sizeof places / sizeof places[0]; i++) {
        const halo_diagnostic *g = check_find_diag(diags, places[i].id, places[i].line);
        if (!g)
            CHECK_FAIL_AT("no %s at line %d", halo_message_name(places[i].id), places[i].line);
        CHECK_INT_EQ(g->column, places[i].column);
        CHECK(g->source_line != NULL);
    }
    /* background[1] = 2, after the elevation's error on the same line */
    int found = 0;
    for (size_t i = 0; i < halo_diagnostics_describe(diags).count; i++) {
        const halo_diagnostic *g = halo_diagnostics_get(diags, i);
        found |= g->id == HALO_MSG_SCENE_VALUE_ABOVE_MAX && g->line == 7 && g->column == 50;
    }
    CHECK(found);
    return 0;
}

int main(void)
{
    static const check_test tests[] = {CHECK_TEST(test_valid_scene),
                                       CHECK_TEST(test_error_places),
                                       CHECK_TEST(test_minimal_scenes),
                                       CHECK_TEST(test_bad_json),
                                       CHECK_TEST(test_top_level),
                                       CHECK_TEST(test_stage_errors),
                                       CHECK_TEST(test_wrong_types),
                                       CHECK_TEST(test_range),
                                       CHECK_TEST(test_nonfinite),
                                       CHECK_TEST(test_counts),
                                       CHECK_TEST(test_render_errors),
                                       CHECK_TEST(test_live_lists),
                                       CHECK_TEST(test_all_errors_reported),
                                       CHECK_TEST(test_api),
                                       CHECK_TEST(test_load)};
    return check_main_with_library(&library, &diags, tests, sizeof tests / sizeof tests[0]);
}
