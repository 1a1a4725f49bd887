/* The C emulation (halo_emu_apply) against the stages' formulas, computed here
 * independently from the papers' equations as docs/ and the modules state them, and
 * hard cases that must stay finite. No GL, no glslang. */
#include "check.h"
#include "emu/stages.h"
#include "internal.h"

static halo_library *library;
static halo_diagnostics *diags;

/* Same formulas in double precision, differently ordered: allow rounding only. */
#define TOLERANCE 1e-12

static const char trivial_host[] =
    "#pragma halo declarations\n"
    "void main() { halo_sample s; halo_apply(s); halo_finish(); }\n";

static halo_program *program_of(const char *json)
{
    halo_diagnostics_clear(diags);
    halo_scene *scene = halo_scene_load("test.json", json, library, diags);
    if (!scene) {
        check_print_diags(diags);
        SETUP_FAIL("scene rejected: %s", json);
    }
    halo_program *p =
        halo_link(&(halo_link_desc){.library = library, .scene = scene, .host_source = trivial_host}, diags);
    halo_scene_destroy(scene);
    if (!p) {
        check_print_diags(diags);
        SETUP_FAIL("link failed: %s", json);
    }
    return p;
}

/* The guards of docs/modules.md, part of the formulas: pow(0, 0) = 1 and a base at or
 * below zero gives 0; clamp to [0, 1]. */
static double guarded_pow(double x, double e) { return x <= 0 ? (e == 0 ? 1 : 0) : pow(x, e); }
static double clamp01(double x) { return x < 0 ? 0 : x > 1 ? 1 : x; }
static double length3(const double v[3]) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

static halo_emu_sample sample(double value, double gx, double gy, double gz, double depth, double opacity)
{
    halo_emu_sample s = {0};
    s.position[0] = s.position[1] = s.position[2] = 0.5;
    s.value = value;
    s.gradient[0] = gx;
    s.gradient[1] = gy;
    s.gradient[2] = gz;
    s.view[2] = 1; /* towards the eye along +z */
    s.depth = depth;
    s.color[0] = 0.8;
    s.color[1] = 0.4;
    s.color[2] = 0.2;
    s.opacity = opacity;
    return s;
}

static int apply(const halo_program *p, halo_emu_sample *s)
{
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_emu_apply(p, NULL, s, diags), HALO_OK);
    CHECK_NO_ERRORS(diags);
    return 0;
}

/* The scene's emulation leaves the sample's opacity and colour exactly as they were. */
static int check_unchanged(const char *json, halo_emu_sample s)
{
    const halo_emu_sample before = s;
    halo_program *p = program_of(json);
    if (apply(p, &s))
        return 1;
    CHECK_NEAR(s.opacity, before.opacity, 0);
    for (int c = 0; c < 3; c++)
        CHECK_NEAR(s.color[c], before.color[c], 0);
    halo_program_destroy(p);
    return 0;
}

/* |n.V| with n = -g/|g|, V = s.view (a unit vector here). */
static double facing_of(const halo_emu_sample *s)
{
    double len = length3(s->gradient);
    double d = -(s->gradient[0] * s->view[0] + s->gradient[1] * s->view[1] + s->gradient[2] * s->view[2]) / len;
    return fabs(d);
}

static int test_opacity_power(void)
{
    halo_program *p = program_of("{\"stages\": [{\"opacity_power\": {\"k_os\": 2, \"k_oe\": 1.5}}]}");
    static const double values[] = {0, 0.1, 0.3, 0.49, 0.8, 1};
    for (size_t i = 0; i < sizeof values / sizeof values[0]; i++) {
        halo_emu_sample s = sample(values[i], 0.1, 0.2, 0.3, 0.5, 0.7);
        if (apply(p, &s))
            return 1;
        CHECK_NEAR(s.opacity, clamp01(guarded_pow(2 * values[i], 1.5)), TOLERANCE);
        /* The colour is left alone. */
        CHECK_NEAR(s.color[0], 0.8, 0);
    }
    halo_program_destroy(p);
    return 0;
}

static int test_gradient_and_boundary(void)
{
    halo_program *p = program_of("{\"stages\": [{\"boundary\": {\"k_gc\": 0.4, \"k_gs\": 12, \"k_ge\": 1.5}}]}");
    CHECK_INT_EQ(halo_program_reflection(p).stage_count, 2); /* gradient, then boundary */
    static const double g[][3] = {{0.03, -0.04, 0.12}, {0.3, 0.4, 0}, {0.001, 0, 0}, {-1, 2, -2}};
    static const double opacities[] = {0.2, 0.05, 0.9, 0.01};
    for (size_t i = 0; i < 4; i++) {
        halo_emu_sample s = sample(0.5, g[i][0], g[i][1], g[i][2], 0.5, opacities[i]);
        if (apply(p, &s))
            return 1;
        double magnitude = length3(g[i]);
        CHECK_NEAR(s.gradient_magnitude, magnitude, TOLERANCE);
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(s.normal[c], -g[i][c] / magnitude, TOLERANCE);
        /* o_g = o_v (k_gc + k_gs |grad f|^k_ge), Ebert & Rheingans 2000, Sec. 4.1 */
        CHECK_NEAR(s.opacity, clamp01(opacities[i] * (0.4 + 12 * pow(magnitude, 1.5))), TOLERANCE);
    }
    halo_program_destroy(p);
    return 0;
}

static int test_silhouette(void)
{
    halo_program *p = program_of("{\"stages\": [{\"silhouette\": {\"k_sc\": 0.5, \"k_ss\": 3, \"k_se\": 2}}]}");
    static const double g[][3] = {{0, 0, -0.2}, {0.2, 0, -0.2}, {0.3, 0.1, 0}, {0.05, 0.05, 0.5}};
    for (size_t i = 0; i < 4; i++) {
        halo_emu_sample s = sample(0.5, g[i][0], g[i][1], g[i][2], 0.5, 0.3);
        double facing = facing_of(&s);
        if (apply(p, &s))
            return 1;
        /* o_s = o_v (k_sc + k_ss (1 - |n.V|)^k_se), Sec. 4.2 */
        CHECK_NEAR(s.opacity, clamp01(0.3 * (0.5 + 3 * pow(1 - facing, 2))), TOLERANCE);
    }
    halo_program_destroy(p);
    return 0;
}

static int test_tone_shading(void)
{
    halo_program *p = program_of(
        "{\"stages\": [{\"tone_shading\": {\"k_ty\": 0.35, \"k_tb\": 0.45, \"k_ta\": 0.6,"
        " \"k_td\": 0.5, \"lights\": [[1, 1, 0], [0, 0.5, -0.5]]}}]}");
    static const double g[][3] = {{0, 0, -0.2}, {-0.3, -0.1, 0.05}, {0.1, 0.2, 0.3}};
    static const double lights[2][3] = {{1 / 1.4142135623730951, 1 / 1.4142135623730951, 0},
                                        {0, 1 / 1.4142135623730951, -1 / 1.4142135623730951}};
    for (size_t i = 0; i < 3; i++) {
        halo_emu_sample s = sample(0.5, g[i][0], g[i][1], g[i][2], 0.5, 0.3);
        double len = length3(g[i]), n[3] = {-g[i][0] / len, -g[i][1] / len, -g[i][2] / len};
        double expected[3];
        for (int c = 0; c < 3; c++)
            expected[c] = 0.6 * s.color[c];
        for (int l = 0; l < 2; l++) {
            double n_dot_l = n[0] * lights[l][0] + n[1] * lights[l][1] + n[2] * lights[l][2];
            double toward = (1 + n_dot_l) / 2;
            double warm[3] = {0.35, 0.35, 0}, cool[3] = {0, 0, 0.45};
            /* c = k_ta c_v + sum (I_t + k_td c_v max(n.L, 0)), Sec. 5.3 */
            for (int c = 0; c < 3; c++)
                expected[c] += toward * warm[c] + (1 - toward) * cool[c] + 0.5 * s.color[c] * fmax(n_dot_l, 0);
        }
        if (apply(p, &s))
            return 1;
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(s.color[c], expected[c], TOLERANCE);
        CHECK_NEAR(s.opacity, 0.3, 0);
    }
    halo_program_destroy(p);
    return 0;
}

static int test_distance_blend(void)
{
    halo_program *p = program_of(
        "{\"stages\": [{\"distance_blend\": {\"background\": [0.1, 0.2, 0.3],"
        " \"k_ds\": 0.8, \"k_de\": 2}}]}");
    static const double depths[] = {0, 0.25, 0.5, 0.9, 1, 1.5, -0.5};
    for (size_t i = 0; i < sizeof depths / sizeof depths[0]; i++) {
        halo_emu_sample s = sample(0.5, 0.1, 0.1, 0.1, depths[i], 0.3);
        const double color[3] = {s.color[0], s.color[1], s.color[2]}, background[3] = {0.1, 0.2, 0.3};
        double d = clamp01(depths[i]), t = 0.8 * d * d;
        if (apply(p, &s))
            return 1;
        /* c_d = (1 - k_ds d^k_de) c_v + k_ds d^k_de c_b, Sec. 5.1 */
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(s.color[c], (1 - t) * color[c] + t * background[c], TOLERANCE);
    }
    halo_program_destroy(p);
    return 0;
}

static int test_distance_cue(void)
{
    halo_program *p = program_of(
        "{\"stages\": [{\"distance_cue\": {\"colors\": [[1, 0, 0], [0, 1, 0], [0, 0, 1]],"
        " \"k_cm\": 0.5}}]}");
    /* depth → the colour map's value, piecewise linear through the three colours. */
    static const double points[][4] = {{0, 1, 0, 0}, {0.25, 0.5, 0.5, 0}, {0.5, 0, 1, 0}, {0.75, 0, 0.5, 0.5},
                                       {1, 0, 0, 1}, {1.5, 0, 0, 1},      {-1, 1, 0, 0},  {0.1, 0.8, 0.2, 0}};
    for (size_t i = 0; i < sizeof points / sizeof points[0]; i++) {
        halo_emu_sample s = sample(0.5, 0.1, 0.1, 0.1, points[i][0], 0.3);
        const double color[3] = {s.color[0], s.color[1], s.color[2]};
        if (apply(p, &s))
            return 1;
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(s.color[c], color[c] * (0.5 + 0.5 * points[i][1 + c]), TOLERANCE);
    }
    halo_program_destroy(p);
    /* One colour: a constant tint; the default map: two colours. */
    p = program_of("{\"stages\": [{\"distance_cue\": {\"colors\": [[0.5, 0.25, 1]], \"k_cm\": 1}}]}");
    halo_emu_sample s = sample(0.5, 0.1, 0.1, 0.1, 0.7, 0.3);
    if (apply(p, &s))
        return 1;
    CHECK_NEAR(s.color[0], 0.8 * 0.5, TOLERANCE);
    CHECK_NEAR(s.color[1], 0.4 * 0.25, TOLERANCE);
    CHECK_NEAR(s.color[2], 0.2 * 1, TOLERANCE);
    halo_program_destroy(p);
    p = program_of("{\"stages\": [\"distance_cue\"]}");
    const halo_uniform_info *colors = halo_program_find_uniform(p, "distance_cue", "colors");
    CHECK(colors && colors->count == 2);
    s = sample(0.5, 0.1, 0.1, 0.1, 0.25, 0.3);
    if (apply(p, &s))
        return 1;
    double k_cm = halo_program_find_uniform(p, "distance_cue", "k_cm")->value[0];
    for (int c = 0; c < 3; c++) {
        double map = 0.75 * colors->value[c] + 0.25 * colors->value[3 + c];
        CHECK_NEAR(s.color[c], (c == 0 ? 0.8 : c == 1 ? 0.4 : 0.2) * ((1 - k_cm) + k_cm * map), TOLERANCE);
    }
    halo_program_destroy(p);
    return 0;
}

static int test_orientation_fade(void)
{
    halo_program *p = program_of(
        "{\"stages\": [{\"orientation_fade\": {\"k_fo\": 0.6, \"k_fs\": 0.5, \"k_fv\": 0.3,"
        " \"k_fe\": 2}}]}");
    static const double g[][3] = {{0, 0, -0.2}, {0.2, 0, -0.2}, {0.3, 0.1, 0}, {0.05, -0.05, 0.5}};
    for (size_t i = 0; i < 4; i++) {
        /* colour (0.8, 0.4, 0.2): red is the largest, blue the smallest. In HSV, V = 0.8,
         * S = 0.75, and the hue puts green at a third of the way from blue to red. */
        halo_emu_sample s = sample(0.5, g[i][0], g[i][1], g[i][2], 0.5, 0.9);
        double facing = pow(facing_of(&s), 2);
        double saturation = 0.75 * (1 - 0.5 * facing), value = 0.8 * (1 - 0.3 * (1 - facing));
        double red = value, blue = value * (1 - saturation), green = blue + (red - blue) / 3;
        if (apply(p, &s))
            return 1;
        /* o *= 1 - k_fo facing; S *= 1 - k_fs facing; V *= 1 - k_fv (1 - facing), Sec. 4.2 */
        CHECK_NEAR(s.opacity, 0.9 * (1 - 0.6 * facing), TOLERANCE);
        CHECK_NEAR(s.color[0], red, TOLERANCE);
        CHECK_NEAR(s.color[1], green, TOLERANCE);
        CHECK_NEAR(s.color[2], blue, TOLERANCE);
    }
    halo_program_destroy(p);
    return 0;
}

static int test_sketch(void)
{
    halo_program *p =
        program_of("{\"stages\": [{\"sketch\": {\"line_color\": [1, 0.5, 0], \"k_ls\": 2, \"k_le\": 3}}]}");
    static const double g[][3] = {{0, 0, -0.2}, {0.2, 0, -0.2}, {0.3, 0.1, 0}, {0.05, -0.05, 0.5}};
    for (size_t i = 0; i < 4; i++) {
        halo_emu_sample s = sample(0.5, g[i][0], g[i][1], g[i][2], 0.5, 0.4);
        double line = pow(1 - facing_of(&s), 3);
        if (apply(p, &s))
            return 1;
        /* line = (1 - |n.V|)^k_le; c = line colour; o = clamp(o k_ls line), Sec. 4.2 */
        CHECK_NEAR(s.opacity, clamp01(0.4 * 2 * line), TOLERANCE);
        CHECK_NEAR(s.color[0], 1, 0);
        CHECK_NEAR(s.color[1], 0.5, 0);
        CHECK_NEAR(s.color[2], 0, 0);
    }
    halo_program_destroy(p);
    return 0;
}

/* Several stages: the emulation runs them in the program's order. */
static int test_chain(void)
{
    halo_program *p = program_of(
        "{\"stages\": [{\"distance_blend\": {\"background\": [0, 0, 0], \"k_ds\": 1,"
        " \"k_de\": 1}}, {\"opacity_power\": {\"k_os\": 1, \"k_oe\": 2}},"
        " {\"boundary\": {\"k_gc\": 0, \"k_gs\": 1, \"k_ge\": 1}}]}");
    halo_emu_sample s = sample(0.5, 0.3, 0.4, 0, 0.25, 0.9);
    if (apply(p, &s))
        return 1;
    /* opacity_power (0.25), then boundary (x |g| = 0.5); blend towards black by 0.25 */
    CHECK_NEAR(s.opacity, 0.25 * 0.5, TOLERANCE);
    CHECK_NEAR(s.color[0], 0.8 * 0.75, TOLERANCE);
    halo_program_destroy(p);
    return 0;
}

/* Edge inputs stay finite, with the values the guards define. */
static int test_hard_cases(void)
{
    /* Zero gradient: no normal, no orientation. */
    halo_program *p = program_of("{\"stages\": [{\"silhouette\": {\"k_sc\": 0.5, \"k_ss\": 3, \"k_se\": 0}}]}");
    halo_emu_sample s = sample(0.5, 0, 0, 0, 0.5, 0.4);
    if (apply(p, &s))
        return 1;
    CHECK_NEAR(s.gradient_magnitude, 0, 0);
    CHECK(s.normal[0] == 0 && s.normal[1] == 0 && s.normal[2] == 0);
    CHECK_NEAR(s.opacity, 0.4 * 0.5, TOLERANCE);
    halo_program_destroy(p);

    /* Opacities the guards define: one scene, one sample each. */
    static const struct {
        const char *scene;
        double value, gradient, opacity; /* the sample: gradient (g, g, g), depth 0.5 */
        double expected, tolerance;
    } guarded[] = {
        /* zero gradient: no line */
        {"{\"stages\": [\"sketch\"]}", 0.5, 0, 0.4, 0, 0},
        /* zero gradient under boundary: 0^k_ge is 0, and 1 when k_ge = 0 */
        {"{\"stages\": [{\"boundary\": {\"k_gc\": 0.5, \"k_gs\": 0.25, \"k_ge\": 2}}]}", 0.5, 0, 0.4, 0.4 * 0.5,
         TOLERANCE},
        {"{\"stages\": [{\"boundary\": {\"k_gc\": 0.5, \"k_gs\": 0.25, \"k_ge\": 0}}]}", 0.5, 0, 0.4, 0.4 * 0.75,
         TOLERANCE},
        /* opacity_power at value 0: 0^0 = 1 */
        {"{\"stages\": [{\"opacity_power\": {\"k_oe\": 0}}]}", 0, 0.1, 0.5, 1, 0},
    };
    for (size_t i = 0; i < sizeof guarded / sizeof guarded[0]; i++) {
        p = program_of(guarded[i].scene);
        double g = guarded[i].gradient;
        s = sample(guarded[i].value, g, g, g, 0.5, guarded[i].opacity);
        if (apply(p, &s))
            return 1;
        CHECK_NEAR(s.opacity, guarded[i].expected, guarded[i].tolerance);
        halo_program_destroy(p);
    }

    /* zero gradient: no orientation to fade by */
    if (check_unchanged("{\"stages\": [\"orientation_fade\"]}", sample(0.5, 0, 0, 0, 0.5, 0.4)))
        return 1;

    p = program_of(
        "{\"stages\": [{\"tone_shading\": {\"k_ta\": 1, \"k_td\": 1, \"k_ty\": 0.2, \"k_tb\": 0.4,"
        " \"lights\": [[0, 0, 0], [0, 1, 0]]}}]}");
    s = sample(0.5, 0, 0, 0, 0.5, 0.4);
    if (apply(p, &s))
        return 1;
    /* n.L = 0 for both lights (no normal; a zero light has no direction): half warm, half cool */
    CHECK_NEAR(s.color[0], 0.8 + 2 * 0.5 * 0.2, TOLERANCE);
    CHECK_NEAR(s.color[2], 0.2 + 2 * 0.5 * 0.4, TOLERANCE);
    halo_program_destroy(p);

    /* n.V rounding past +-1: the normal along a view vector a hair longer than 1. */
    static const char *const orientation_scenes[] = {
        "{\"stages\": [{\"silhouette\": {\"k_sc\": 0.5, \"k_ss\": 3, \"k_se\": 0.25}}]}",
        "{\"stages\": [{\"silhouette\": {\"k_sc\": 0.5, \"k_ss\": 3, \"k_se\": 0}}]}",
        "{\"stages\": [{\"sketch\": {\"k_le\": 0.5}}]}",
        "{\"stages\": [{\"sketch\": {\"k_le\": 0}}]}",
        "{\"stages\": [{\"orientation_fade\": {\"k_fe\": 0.5}}]}",
        "{\"stages\": [\"tone_shading\"]}",
    };
    for (size_t i = 0; i < sizeof orientation_scenes / sizeof orientation_scenes[0]; i++) {
        p = program_of(orientation_scenes[i]);
        for (int sign = -1; sign <= 1; sign += 2) {
            s = sample(0.5, 0, 0, -0.3 * sign, 0.5, 0.4);
            s.view[2] = sign * (1 + 1e-7);
            if (apply(p, &s))
                return 1;
            CHECK_FINITE(s.opacity);
            CHECK(s.opacity >= 0 && s.opacity <= 1);
            for (int c = 0; c < 3; c++)
                CHECK_FINITE(s.color[c]);
            /* Facing the viewer squarely: no silhouette, no line. */
            if (i == 0)
                CHECK_NEAR(s.opacity, 0.4 * 0.5, TOLERANCE);
            if (i == 1)
                CHECK_NEAR(s.opacity, clamp01(0.4 * 3.5), TOLERANCE); /* (1 - 1)^0 = 1 */
            if (i == 2)
                CHECK_NEAR(s.opacity, 0, 0);
        }
        halo_program_destroy(p);
    }

    /* Exponents 0 and 64, depth 0 and 1, opacity 0 and 1, gradient 0 to large. */
    static const char *const stage_forms[] = {
        "{\"opacity_power\": {\"k_os\": 1000, \"k_oe\": %s}}",
        "{\"boundary\": {\"k_gs\": 1000, \"k_gc\": 1000, \"k_ge\": %s}}",
        "{\"silhouette\": {\"k_ss\": 1000, \"k_se\": %s}}",
        "{\"orientation_fade\": {\"k_fe\": %s}}",
        "{\"sketch\": {\"k_ls\": 100, \"k_le\": %s}}",
        "{\"distance_blend\": {\"k_de\": %s}}",
        "\"distance_cue\"",
        "{\"tone_shading\": {\"k_ta\": 10, \"k_td\": 10, \"lights\": [[1, 1, 1], [0, 0, 0], [-1, 0, 0], [0, 0, 1]]}}",
    };
    static const char *const exponents[] = {"0", "64"};
    static const double gradients[][3] = {{0, 0, 0}, {1e-12, 0, 0}, {0, 0, -1}, {3, -4, 12}, {1e-5, 1e-5, 1e-5}};
    static const double edges[] = {0, 1};
    for (size_t f = 0; f < sizeof stage_forms / sizeof stage_forms[0]; f++)
        for (int e = 0; e < 2; e++) {
            char stage[256], json[512];
            snprintf(stage, sizeof stage, stage_forms[f], exponents[e]);
            snprintf(json, sizeof json, "{\"stages\": [%s]}", stage);
            p = program_of(json);
            for (size_t g = 0; g < sizeof gradients / sizeof gradients[0]; g++)
                for (int d = 0; d < 2; d++)
                    for (int o = 0; o < 2; o++)
                        for (int v = 0; v < 2; v++) {
                            s = sample(edges[v], gradients[g][0], gradients[g][1], gradients[g][2], edges[d], edges[o]);
                            if (apply(p, &s))
                                return 1;
                            if (!isfinite(s.opacity) || !isfinite(s.color[0]) || !isfinite(s.color[1]) ||
                                !isfinite(s.color[2]) || s.opacity < 0 || s.opacity > 1)
                                CHECK_FAIL_AT(
                                    "%s: value %g, gradient (%g, %g, %g), depth %g, opacity %g gave colour "
                                    "(%g, %g, %g) opacity %g",
                                    json, edges[v], gradients[g][0], gradients[g][1], gradients[g][2], edges[d],
                                    edges[o], s.color[0], s.color[1], s.color[2], s.opacity);
                        }
            halo_program_destroy(p);
        }
    /* distance_blend at the edges: d^0 = 1 even at d = 0; 0^64 = 0. */
    p = program_of("{\"stages\": [{\"distance_blend\": {\"background\": [0, 0, 0], \"k_ds\": 1, \"k_de\": 0}}]}");
    s = sample(0.5, 0.1, 0.1, 0.1, 0, 0.5);
    if (apply(p, &s))
        return 1;
    CHECK_NEAR(s.color[0], 0, TOLERANCE);
    halo_program_destroy(p);
    p = program_of("{\"stages\": [{\"distance_blend\": {\"background\": [0, 0, 0], \"k_ds\": 1, \"k_de\": 64}}]}");
    s = sample(0.5, 0.1, 0.1, 0.1, 0, 0.5);
    if (apply(p, &s))
        return 1;
    CHECK_NEAR(s.color[0], 0.8, TOLERANCE);
    s = sample(0.5, 0.1, 0.1, 0.1, 1, 0.5);
    if (apply(p, &s))
        return 1;
    CHECK_NEAR(s.color[0], 0, TOLERANCE);
    halo_program_destroy(p);
    return 0;
}

/* Live parameters changed with halo_program_set are what the emulation uses. */
static int test_program_set(void)
{
    halo_program *p = program_of("{\"stages\": [{\"opacity_power\": {\"live\": true}}]}");
    const double k_oe = 2;
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_program_set(p, "opacity_power", "k_oe", &k_oe, 1, diags), HALO_OK);
    halo_emu_sample s = sample(0.5, 0.1, 0.1, 0.1, 0.5, 0.5);
    if (apply(p, &s))
        return 1;
    CHECK_NEAR(s.opacity, 0.25, TOLERANCE);
    halo_program_destroy(p);
    return 0;
}

static int test_no_emulation(void)
{
    halo_diagnostics_clear(diags);
    SETUP(halo_library_add(library, "user/plain.glsl",
                           "#pragma halo module plain\n#pragma halo hook sample\n"
                           "void apply(inout halo_sample s) {}\n",
                           HALO_ADD_NEW, diags) == HALO_OK);
    CHECK(!halo_module_describe(halo_library_find(library, "plain")).has_emulation);
    CHECK(halo_module_describe(halo_library_find(library, "boundary")).has_emulation);
    halo_program *p = program_of("{\"stages\": [\"plain\"]}");
    halo_emu_sample s = sample(0.5, 0.1, 0.1, 0.1, 0.5, 0.5);
    CHECK_INT_EQ(halo_emu_apply(p, NULL, &s, diags), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_EMU_MISSING);
    halo_program_destroy(p);
    /* No stage: the sample is unchanged. */
    return check_unchanged("{}", sample(0.5, 0.1, 0.1, 0.1, 0.5, 0.5));
}

/* A line program's stages run through halo_emu_apply on the sample's line_vertex or
 * line_fragment (docs/lines.md), line_strip's depth range from the frame's host uniform:
 * the formulas of glsl/lines/strip.glsl and halo.glsl worked by hand at the defaults
 * (strip_width 0.03, depth_attenuation 0.5, taper 0.1; core 0.4, d_max 0.05, linear). */
static halo_program *line_program(const char *stage, halo_shader_kind kind, const char *host)
{
    char json[96];
    snprintf(json, sizeof json, "{\"stages\": [\"%s\"]}", stage);
    halo_diagnostics_clear(diags);
    halo_scene *scene = halo_scene_load("lines.json", json, library, diags);
    halo_program *p =
        scene
            ? halo_link(&(halo_link_desc){.library = library, .scene = scene, .host_source = host, .kind = kind}, diags)
            : NULL;
    halo_scene_destroy(scene);
    if (!p)
        check_print_diags(diags);
    return p;
}

static int test_line_stages(void)
{
    CHECK(halo_module_describe(halo_library_find(library, "line_strip")).has_emulation);
    CHECK(halo_module_describe(halo_library_find(library, "line_halo")).has_emulation);
    halo_program *strip = line_program("line_strip", HALO_SHADER_VERTEX,
                                       "#pragma halo declarations\n"
                                       "void main() { halo_line_vertex v; halo_apply(v); gl_Position = "
                                       "vec4(v.position, 1.0); }\n");
    CHECK(strip != NULL);
    /* a vertex at the origin on a line along x, seen from (0, 0, 2), on the strip's v = 1
     * side, mid-line (no taper): S = V x D = (0, 1, 0), the vertex moves by strip / 2 */
    const halo_emu_line_vertex vertex = {.direction = {1, 0, 0}, .uv = {0.5, 1}, .eye = {0, 0, 2}, .width = 1};
    halo_emu_sample s = {.line_vertex = vertex};
    CHECK_INT_EQ(halo_emu_apply(strip, NULL, &s, diags), HALO_OK); /* no frame: range (0, 0), unset */
    CHECK_NEAR(s.line_vertex.width, 0.03, TOLERANCE);
    CHECK_NEAR(s.line_vertex.position[1], 0.015, TOLERANCE);
    CHECK_NEAR(s.line_vertex.position[0], 0, TOLERANCE);
    halo_emu_frame *frame = halo_emu_frame_create(strip, 1, 1, diags);
    CHECK(frame != NULL);
    const double range[2] = {1, 3}; /* the vertex 2 from the eye: depth 0.5, width x 0.75 */
    CHECK_INT_EQ(halo_emu_frame_set_host_uniform(frame, "depth_range", range, 2), HALO_OK);
    s = (halo_emu_sample){.line_vertex = vertex};
    CHECK_INT_EQ(halo_emu_apply(strip, frame, &s, diags), HALO_OK);
    CHECK_NEAR(s.line_vertex.width, 0.0225, TOLERANCE);
    CHECK_NEAR(s.line_vertex.position[1], 0.01125, TOLERANCE);
    halo_emu_frame_destroy(frame);
    halo_program_destroy(strip);

    halo_program *halo = line_program("line_halo", HALO_SHADER_FRAGMENT,
                                      "#pragma halo declarations\n"
                                      "out vec4 color;\n"
                                      "void main() { halo_line_fragment f; halo_apply(f); color = f.color; }\n");
    CHECK(halo != NULL);
    /* v = 0.9: x = 0.8, past the core: the background, opaque, depth + 0.05 x 0.8 */
    const halo_emu_line_fragment fragment = {
        .uv = {0.5, 0.9}, .depth = 0.3, .color = {1, 0, 0}, .opacity = 0.5, .background = {0, 0, 1}};
    s = (halo_emu_sample){.line_fragment = fragment};
    CHECK_INT_EQ(halo_emu_apply(halo, NULL, &s, diags), HALO_OK);
    CHECK_NEAR(s.line_fragment.color[2], 1, 0);
    CHECK_NEAR(s.line_fragment.opacity, 1, 0);
    CHECK_NEAR(s.line_fragment.depth, 0.34, TOLERANCE);
    /* the line's centre: unchanged */
    s = (halo_emu_sample){.line_fragment = fragment};
    s.line_fragment.uv[1] = 0.5;
    CHECK_INT_EQ(halo_emu_apply(halo, NULL, &s, diags), HALO_OK);
    CHECK_NEAR(s.line_fragment.color[0], 1, 0);
    CHECK_NEAR(s.line_fragment.opacity, 0.5, 0);
    CHECK_NEAR(s.line_fragment.depth, 0.3, 0);
    halo_program_destroy(halo);
    return 0;
}

/* The outlines' kernel sizes follow Svakhine et al. 2009 ("the size of the filtering
 * kernel sigma"): sigma, in percent of the image diagonal, is the full width of the
 * Gaussian truncated at 3 standard deviations, so its standard deviation is sigma / 6.
 * Measured on the blur of an impulse: sigma 6 % of a 200 x 200 diagonal (283 px) is a
 * standard deviation of 2.83 px (the truncated Gaussian's is 0.987 of that), not 17 px. */
static int test_outline_kernel_size(void)
{
    halo_program *p = program_of(
        "{\"halo_scene\": 1, \"stages\": [\"outline_feature\", "
        "{\"outlines\": {\"sigma\": 6, \"normal_sigma\": 6}}]}");
    const halo_linked_stage *stage = NULL;
    for (size_t i = 0; i < p->stage_count; i++)
        if (!strcmp(halo_module_describe(p->stages[i].module).name, "outlines"))
            stage = &p->stages[i];
    CHECK(stage != NULL);
    enum { side = 200 };
    static double impulse[side * side];
    impulse[(side / 2) * side + side / 2] = 1.0;
    halo_emu_params params = {.program = p, .stage = stage};
    halo_emu_pass_context c = {.params = &params,
                               .width = side,
                               .height = side,
                               .channels = 1,
                               .input_count = 1,
                               .inputs = {impulse},
                               .input_components = {1}};
    const halo_emu_pass_fn blurs[] = {halo_emu_lookup_pass("outlines", "blur_x_pass"),
                                      halo_emu_lookup_pass("outlines", "normal_blur_x_pass")};
    CHECK(blurs[0] && blurs[1]);
    for (int b = 0; b < 2; b++) {
        double sum = 0, moment = 0;
        for (int x = 0; x < side; x++) {
            double out[4] = {0};
            blurs[b](&c, x, side / 2, out);
            sum += out[0];
            moment += out[0] * (x - side / 2) * (x - side / 2);
        }
        double deviation = sqrt(moment / sum), expected = 0.06 * sqrt(2.0) * side / 6.0;
        CHECK_NEAR(deviation / expected, 0.987, 0.01);
        CHECK_NEAR(sum, 1.0, 1e-12);
    }
    halo_program_destroy(p);
    return 0;
}

int main(void)
{
    static const check_test tests[] = {CHECK_TEST(test_opacity_power),
                                       CHECK_TEST(test_gradient_and_boundary),
                                       CHECK_TEST(test_silhouette),
                                       CHECK_TEST(test_tone_shading),
                                       CHECK_TEST(test_distance_blend),
                                       CHECK_TEST(test_distance_cue),
                                       CHECK_TEST(test_orientation_fade),
                                       CHECK_TEST(test_sketch),
                                       CHECK_TEST(test_chain),
                                       CHECK_TEST(test_hard_cases),
                                       CHECK_TEST(test_program_set),
                                       CHECK_TEST(test_no_emulation),
                                       CHECK_TEST(test_line_stages),
                                       CHECK_TEST(test_outline_kernel_size)};
    return check_main_with_library(&library, &diags, tests, sizeof tests / sizeof tests[0]);
}
