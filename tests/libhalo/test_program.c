/* libhalo/program.c: a linked program's parameters (halo_program_set) and what its
 * stages are (the reflection's stages and reads_labels). No GL. */
#include "link_fixture.h"

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
    CHECK(halo_diagnostics_describe(diags).errors >= 1);
    CHECK_NEAR(halo_program_find_uniform(p, "boundary", "k_ge")->value[0], 2, 0);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_program_set(p, "boundary", "k_zz", &v, 1, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_SCENE_PARAM_UNKNOWN);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_program_set(p, "sketch", "k_le", &v, 1, diags), HALO_ERROR_INPUT);
    CHECK(halo_diagnostics_describe(diags).errors >= 1);
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
        const halo_stage_info *info = i >= 0 ? &halo_program_reflection(p).stages[(size_t)i] : NULL;
        CHECK(info != NULL);
        if (!info)
            continue;
        CHECK_STR_EQ(info->name, expect[k].name);
        CHECK_INT_EQ(info->keeps_empty, expect[k].keeps_empty);
        CHECK_INT_EQ(info->zero_generation, expect[k].zero_generation);
        CHECK(info->labels_when == NULL);
    }
    CHECK_INT_EQ(halo_program_reflection(p).reads_labels, 0);
    /* M from the stage that says which parameter is it (halo_generate: interval, default 4) */
    int generate = stage_index(p, "halo_generate");
    const halo_stage_info *gen = generate >= 0 ? &halo_program_reflection(p).stages[(size_t)generate] : NULL;
    CHECK(gen && gen->interval && !strcmp(gen->interval, "interval"));
    CHECK_INT_EQ(halo_program_reflection(p).interval, 4);
    char *json = halo_program_reflect_json(p);
    CHECK(json && strstr(json, "\"stage_info\"") && strstr(json, "\"zero_generation\": true"));
    free(json);
    halo_program_destroy(p);
    p = link_valid(
        "{\"halo_scene\": 1, \"stages\": [\"halo_seed\", {\"halo_generate\": {\"interval\": 7}}, "
        "\"halo_map\"]}");
    CHECK(p && halo_program_reflection(p).interval == 7);
    halo_program_destroy(p);
    /* the reflection follows a live parameter's new value */
    p = link_valid(
        "{\"halo_scene\": 1, \"stages\": [\"halo_seed\", {\"halo_generate\": {\"interval\": 7, \"live\": "
        "[\"interval\"]}}, \"halo_map\"]}");
    const double five = 5;
    CHECK(p && halo_program_set(p, "halo_generate", "interval", &five, 1, NULL) == HALO_OK &&
          halo_program_reflection(p).interval == 5);
    halo_program_destroy(p);
    p = link_valid("{\"halo_scene\": 1, \"stages\": [\"boundary\"]}");
    CHECK(p && halo_program_reflection(p).interval == 0);
    halo_program_destroy(p);
    /* outline_feature reads the labels only for a feature with label >= 0 */
    p = link_valid(
        "{\"halo_scene\": 1, \"stages\": [\"gradient\", {\"outline_feature\": {\"label\": [-1]}}, "
        "\"outlines\"]}");
    CHECK(p != NULL);
    if (p) {
        int at = stage_index(p, "outline_feature");
        const halo_stage_info *info = at >= 0 ? &halo_program_reflection(p).stages[at] : NULL;
        CHECK(info && info->labels_when && !strcmp(info->labels_when, "label"));
        CHECK_INT_EQ(halo_program_reflection(p).reads_labels, 0);
        halo_program_destroy(p);
    }
    p = link_valid(
        "{\"halo_scene\": 1, \"stages\": [\"gradient\", {\"outline_feature\": {\"label\": [-1, 3]}}, "
        "\"outlines\"]}");
    CHECK(p != NULL);
    if (p) {
        CHECK_INT_EQ(halo_program_reflection(p).reads_labels, 1);
        halo_program_destroy(p);
    }
    return 0;
}


int main(void)
{
    link_fixture_setup();
    RUN_TEST(test_program_set);
    RUN_TEST(test_stage_info);
    return link_fixture_finish();
}
