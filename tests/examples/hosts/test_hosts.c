/* The example hosts in the styles of the wild (examples/hosts/, host contract 2): a
 * WebGL2-style ES 300 caster (webgl_caster.frag), a GL 4 two-pass caster with an
 * exit-point texture (exit_point_caster.frag), a 2D transfer function caster with its
 * own Phong lighting (tf2d_caster.frag) and a MIP / isosurface host (mip_iso_caster.frag).
 *
 * For each: (a) it links and validates for its targets with an empty scene and a halo
 * scene; (b) it renders the built-in volume (OSMesa) with volumetric halos, outlines
 * (post passes) and feature halos, finite and different from the same scene without its
 * stages; (c) forced into K = 1, 4, 16 segments with a per-sample-only scene it renders
 * the same float image as in one draw (max abs <= 1e-6; jitter on for the WebGL host).
 * Also: each desktop host's unlinked text (the renderer before libhalo) renders the
 * image of the host linked with no stage; the jitter reaches the WebGL host; the
 * exit-point caster renders the example ray caster's image (same sampling, exit from the
 * texture); the MIP variant refuses any stage (HOST_COMPOSITING at its pragma's line)
 * and renders without one. HALO_HOSTS_ONLY=webgl runs one host. Exit 77 without OpenGL. */
#include "../../gl_fixture.h"
#include "halo_feature.h"
#include "hosts/raycast.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SIZE         40
#define VOLUME       32
#define FEATURE_UNIT 15

typedef struct host_case {
    const char *file;
    halo_target targets[3];
    int target_count;
    halo_target render_target; /* the target rendered on the GL 4.5 / 3.3 context */
    float jitter;
    int exit_points;
} host_case;

static const host_case hosts[] = {
    {"webgl_caster.frag",
     {HALO_TARGET_ES300, HALO_TARGET_GLSL330, HALO_TARGET_GLSL450},
     3,
     HALO_TARGET_GLSL330,
     1.0f,
     0},
    {"exit_point_caster.frag",
     {HALO_TARGET_GLSL450, HALO_TARGET_GLSL330, HALO_TARGET_ES300},
     3,
     HALO_TARGET_GLSL450,
     0.0f,
     1},
    {"tf2d_caster.frag",
     {HALO_TARGET_GLSL330, HALO_TARGET_GLSL450, HALO_TARGET_ES300},
     3,
     HALO_TARGET_GLSL330,
     0.0f,
     0},
    {"mip_iso_caster.frag",
     {HALO_TARGET_GLSL330, HALO_TARGET_GLSL450, HALO_TARGET_ES300},
     3,
     HALO_TARGET_GLSL330,
     0.0f,
     0},
};

/* A per-sample-only scene: default.json without its halo stages. */
static const char per_sample_scene[] =
    "{\"halo_scene\": 1, \"stages\": [{\"boundary\": {\"k_gc\": 0.4, \"k_gs\": 12, \"k_ge\": 1}},"
    " {\"silhouette\": {\"k_sc\": 0.5, \"k_ss\": 3, \"k_se\": 2}},"
    " {\"tone_shading\": {\"k_ty\": 0.35, \"k_tb\": 0.45, \"k_ta\": 0.6, \"k_td\": 0.5, \"lights\": [[-0.4, 0.7, 0.6]]}},"
    " {\"distance_blend\": {\"background\": [0.05, 0.08, 0.25], \"k_ds\": 0.9, \"k_de\": 1.5}}],"
    " \"render\": {\"azimuth\": 35, \"elevation\": 25, \"zoom\": 1.5, \"step\": 0.5, \"background\": [0.05, 0.08, 0.25],"
    " \"transfer\": [[0, 0, 0, 0, 0], [0.18, 0.6, 0.8, 1, 0], [0.3, 0.6, 0.8, 1, 0.06], [0.42, 1, 0.85, 0.55, 0.02],"
    " [0.5, 1, 0.85, 0.55, 0.25], [0.62, 0.9, 0.35, 0.25, 0.05], [0.75, 0.95, 0.3, 0.2, 0.7],"
    " [0.9, 1, 0.95, 0.7, 0.8], [1, 1, 1, 0.8, 0.9]]}}";

typedef struct context {
    halo_library *lib;
    halo_gl *runtime;
    const halo_glfuncs *gl;
    halo_diagnostics *diag;
    float *volume;
    const char *srcdir;
} context;

static char *scene_path(const context *c, const char *name)
{
    size_t n = strlen(c->srcdir) + strlen(name) + 32;
    char *path = malloc(n);
    if (path)
        snprintf(path, n, "%s/examples/scenes/%s", c->srcdir, name);
    return path;
}

static halo_scene *load_scene(const context *c, const char *name)
{
    char *path = scene_path(c, name);
    halo_scene *s = path ? halo_scene_load(path, NULL, c->lib, c->diag) : NULL;
    free(path);
    return s;
}

/* The same render settings, no stage. */
static halo_scene *empty_like(const context *c, const halo_scene *scene)
{
    halo_scene *empty = halo_scene_create(c->lib);
    if (empty && scene)
        halo_scene_set_render(empty, halo_scene_describe(scene).render);
    return empty;
}

/* mode 1: force_segments; 2: one_draw (host contract 3) */
static halo_program *link_host(const context *c, const char *file, const char *source, const halo_scene *scene,
                               halo_target target, int mode)
{
    return halo_link(&(halo_link_desc){.library = c->lib,
                                       .scene = scene,
                                       .host_source = source,
                                       .host_file = file,
                                       .target = target,
                                       .force_segments = mode == 1,
                                       .one_draw = mode == 2},
                     c->diag);
}

static int report_diagnostics(const context *c, const char *what)
{
    if (!halo_diagnostics_describe(c->diag).errors)
        return 0;
    printf("%s: ERROR\n", what);
    halo_diagnostics_print(c->diag, stdout);
    halo_diagnostics_clear(c->diag);
    return 1;
}

/* (a) links and validates for every target with an empty scene and the default (halo) scene. */
static int link_validate(const context *c, const host_case *h, const char *source)
{
    int failed = 0;
    halo_scene *halos = load_scene(c, "default.json");
    halo_scene *empty = empty_like(c, halos);
    for (int t = 0; t < h->target_count; ++t)
        for (int s = 0; s < 2; ++s) {
            halo_program *p = link_host(c, h->file, source, s ? halos : empty, h->targets[t], 0);
            int ok = p && halo_validate(&(halo_validate_desc){.program = p}, c->diag) == HALO_OK;
            char what[160];
            snprintf(what, sizeof what, "%s link+validate %s %s scene", h->file, halo_target_name(h->targets[t]),
                     s ? "halo" : "empty");
            ok = !report_diagnostics(c, what) && ok;
            printf("%-60s %s\n", what, ok ? "PASS" : "FAIL");
            failed += !ok;
            halo_program_destroy(p);
        }
    halo_scene_destroy(halos);
    halo_scene_destroy(empty);
    return failed;
}

typedef struct render_options {
    float jitter;
    int exit_points;
    int segments;           /* > 0: forced count (a program linked with force_segments) */
    int drawn;              /* out: segments the frame drew (0: no frame) */
    const char *raw_source; /* with no program: the host's unlinked text */
} render_options;

/* Renders program (a linked host) with the scene's render settings: feature halo buffer,
 * post passes (their last image replaces the host's colour). rgba: SIZE*SIZE*4. */
static int render(const context *c, const halo_program *program, const halo_scene *scene, render_options *o,
                  float *rgba)
{
    int ok = 0;
    halo_feature_buffer *buffer = NULL;
    halo_raycast *r = halo_raycast_create(&(halo_host_desc){.gl = c->gl,
                                                            .runtime = c->runtime,
                                                            .program = program,
                                                            .fragment_source = o->raw_source,
                                                            .width = SIZE,
                                                            .height = SIZE},
                                          c->diag);
    if (!r)
        goto done;
    const halo_render_settings *settings = halo_scene_describe(scene).render;
    if (halo_raycast_set_volume(r, c->volume, VOLUME, VOLUME, VOLUME, c->diag) != HALO_OK ||
        halo_raycast_set_render(r, settings, c->diag) != HALO_OK)
        goto done;
    halo_raycast_set_camera(r, settings->azimuth, settings->elevation, settings->zoom);
    halo_raycast_set_jitter(r, o->jitter);
    if (o->segments)
        halo_raycast_set_segments(r, 0, o->segments);
    if (o->exit_points && halo_raycast_set_exit_points(r, c->diag) != HALO_OK)
        goto done;
    halo_feature_desc fd;
    if (program && halo_feature_desc_from_program(program, &fd) == HALO_OK) {
        const int dims[3] = {VOLUME, VOLUME, VOLUME};
        halo_raycast_state state;
        halo_raycast_get_state(r, &state);
        double view[3] = {state.eye[0] - 0.5, state.eye[1] - 0.5, state.eye[2] - 0.5};
        double length = sqrt(view[0] * view[0] + view[1] * view[1] + view[2] * view[2]);
        for (int k = 0; k < 3; ++k)
            view[k] /= length;
        buffer = halo_feature_buffer_create(c->runtime, c->volume, dims, &fd, c->diag);
        if (!buffer || halo_feature_buffer_build(buffer, view) != HALO_OK)
            goto done;
        unsigned gl_program = halo_raycast_gl_program(r);
        c->gl->UseProgram(gl_program);
        c->gl->Uniform1i(c->gl->GetUniformLocation(gl_program, "halo_host_feature_buffer"), FEATURE_UNIT);
        c->gl->UseProgram(0);
        c->gl->ActiveTexture(GL_TEXTURE0 + FEATURE_UNIT);
        c->gl->BindTexture(GL_TEXTURE_3D, halo_feature_buffer_describe(buffer).texture);
        c->gl->ActiveTexture(GL_TEXTURE0);
    }
    if (halo_raycast_render(r, rgba, c->diag) != HALO_OK)
        goto done;
    o->drawn = halo_raycast_frame(r) ? halo_gl_frame_describe(halo_raycast_frame(r)).segment_count : 0;
    /* the post passes (outlines) on the host's image */
    const char *post = NULL;
    for (size_t i = 0; program && i < halo_program_reflection(program).pass_count; ++i)
        if (halo_program_reflection(program).passes[i].at)
            post = halo_program_reflection(program).passes[i].output;
    if (post) {
        const halo_image_info *info = NULL;
        for (size_t i = 0; i < halo_program_reflection(program).image_count; ++i)
            if (!strcmp(halo_program_reflection(program).images[i].name, post))
                info = &halo_program_reflection(program).images[i];
        float *out =
            info ? malloc((size_t)SIZE * SIZE * (size_t)(info->channels > 4 ? info->channels : 4) * sizeof *out) : NULL;
        if (!out || info->channels < 3) {
            free(out);
            printf("post image %s: not a colour image\n", post);
            goto done;
        }
        unsigned texture = 0;
        c->gl->GenTextures(1, &texture);
        c->gl->BindTexture(GL_TEXTURE_2D, texture);
        c->gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        c->gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        c->gl->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, SIZE, SIZE, 0, GL_RGBA, GL_FLOAT, rgba);
        c->gl->BindTexture(GL_TEXTURE_2D, 0);
        halo_gl_frame_post(halo_raycast_frame(r), texture);
        int read = halo_gl_frame_read(halo_raycast_frame(r), info->name, out) == HALO_OK;
        c->gl->DeleteTextures(1, &texture);
        for (size_t p = 0; read && p < (size_t)SIZE * SIZE; ++p)
            for (int k = 0; k < 3; ++k)
                rgba[p * 4 + (size_t)k] = out[p * (size_t)info->channels + (size_t)k];
        free(out);
        if (!read)
            goto done;
    }
    ok = c->gl->GetError() == GL_NO_ERROR;
done:
    c->gl->ActiveTexture(GL_TEXTURE0 + FEATURE_UNIT);
    c->gl->BindTexture(GL_TEXTURE_3D, 0);
    c->gl->ActiveTexture(GL_TEXTURE0);
    halo_feature_buffer_destroy(buffer);
    halo_raycast_destroy(r);
    return ok;
}

/* Two renders compared: a with program p (or o_a->raw_source) and scene_a, b likewise.
 * 1 when both rendered (diagnostics reported under what); *max gets the largest
 * difference, *differing how many values differ by more than above, *bad the non-finite
 * values of both. */
typedef struct comparison {
    double max, rmse;
    long differing, bad;
} comparison;

static int compare(const context *c, const char *what, const halo_program *p, const halo_scene *scene_a,
                   render_options *o_a, const halo_program *q, const halo_scene *scene_b, render_options *o_b,
                   double above, comparison *out)
{
    size_t n = (size_t)SIZE * SIZE * 4;
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    int ok = a && b && (p || o_a->raw_source) && (q || o_b->raw_source) && render(c, p, scene_a, o_a, a) &&
             render(c, q, scene_b, o_b, b);
    ok = !report_diagnostics(c, what) && ok;
    *out = (comparison){.max = ok ? 0.0 : INFINITY, .bad = ok ? 0 : -1};
    for (size_t i = 0; ok && i < n; ++i) {
        double e = fabs((double)a[i] - (double)b[i]);
        out->max = e > out->max || e != e ? e : out->max;
        out->differing += e > above;
        out->bad += !isfinite(a[i]) + !isfinite(b[i]);
        out->rmse += e * e;
    }
    out->rmse = ok ? sqrt(out->rmse / (double)n) : INFINITY;
    free(a);
    free(b);
    return ok;
}

/* (b) volumetric halos, outlines and feature halos change the image, which stays finite:
 * each scene against itself with those stages switched off. */
static int stage_renders(const context *c, const host_case *h, const char *source)
{
    static const char *const scenes[][2] = {{"halo-emissive.json", "halo_seed halo_generate halo_map"},
                                            {"default.json", "halo_seed halo_generate halo_map"},
                                            {"outline-depth.json", "outline_feature outlines"},
                                            {"outline-mask.json", "outline_feature outlines"},
                                            {"feature-halos.json", "feature_halo"}};
    int failed = 0;
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; ++i) {
        halo_scene *scene = load_scene(c, scenes[i][0]), *reduced = load_scene(c, scenes[i][0]);
        char names[128];
        snprintf(names, sizeof names, "%s", scenes[i][1]);
        for (char *name = strtok(names, " "); reduced && name; name = strtok(NULL, " "))
            if (halo_scene_enable(reduced, name, 0, c->diag) != HALO_OK) {
                halo_scene_destroy(reduced);
                reduced = NULL;
            }
        halo_program *p = scene ? link_host(c, h->file, source, scene, h->render_target, 0) : NULL;
        halo_program *q = reduced ? link_host(c, h->file, source, reduced, h->render_target, 0) : NULL;
        render_options o_p = {.jitter = h->jitter, .exit_points = h->exit_points}, o_q = o_p;
        char what[160];
        snprintf(what, sizeof what, "%s render %s", h->file, scenes[i][0]);
        comparison d;
        int ok = p && q && compare(c, what, p, scene, &o_p, q, reduced, &o_q, 1e-3, &d);
        /* the stages must show: a clear change on at least 1% of the values; volumetric
         * halos need segments */
        int halos = strstr(scenes[i][1], "halo_generate") != NULL;
        ok = ok && d.bad == 0 && d.max > 0.02 && d.differing >= SIZE * SIZE * 4 / 100 && (!halos || o_p.drawn > 1);
        printf("%-48s %2d segments, nonfinite %ld, vs without (%s): max abs %.4f, %ld values differ > 1e-3: %s\n", what,
               o_p.drawn, ok ? d.bad : -1, scenes[i][1], ok ? d.max : 0.0, ok ? d.differing : 0, ok ? "PASS" : "FAIL");
        failed += !ok;
        halo_program_destroy(p);
        halo_program_destroy(q);
        halo_scene_destroy(scene);
        halo_scene_destroy(reduced);
    }
    return failed;
}

/* (c) K forced segments against one draw, per-sample-only scene. */
static int segment_renders(const context *c, const host_case *h, const char *source)
{
    int failed = 0;
    halo_scene *scene = halo_scene_load("per-sample.json", per_sample_scene, c->lib, c->diag);
    halo_program *once = scene ? link_host(c, h->file, source, scene, h->render_target, 0) : NULL;
    halo_program *forced = scene ? link_host(c, h->file, source, scene, h->render_target, 1) : NULL;
    if (report_diagnostics(c, h->file) || !once || !forced || halo_program_reflection(once).segment_location != 0 ||
        halo_program_reflection(forced).segment_location <= 0) {
        printf("%-60s FAIL\n", "segments: link");
        failed = 1;
    }
    render_options one = {.jitter = h->jitter, .exit_points = h->exit_points};
    comparison d;
    if (!failed && h->jitter > 0) {
        /* the jitter reaches the shader: without it the image differs */
        render_options plain = {.exit_points = h->exit_points};
        int ok = compare(c, h->file, once, scene, &one, once, scene, &plain, 0.0, &d) && d.max > 1e-3;
        printf("%-60s max abs %.3g (> 1e-3): %s\n", "jitter 1 vs jitter 0, one draw", d.max, ok ? "PASS" : "FAIL");
        failed += !ok;
    }
    static const int counts[] = {1, 4, 16};
    for (int k = 0; !failed && k < 3; ++k) {
        render_options split = {.jitter = h->jitter, .exit_points = h->exit_points, .segments = counts[k]};
        int pass = compare(c, h->file, forced, scene, &split, once, scene, &one, 0.0, &d) && d.bad == 0 &&
                   d.max <= 1e-6 && split.drawn == counts[k];
        char what[160];
        snprintf(what, sizeof what, "%s K=%d segments%s", h->file, counts[k], h->jitter > 0 ? " (jitter 1)" : "");
        printf("%-60s drew %d, max abs vs one draw %.3g (<= 1e-6): %s\n", what, split.drawn, d.max,
               pass ? "PASS" : "FAIL");
        failed += !pass;
    }
    halo_program_destroy(once);
    halo_program_destroy(forced);
    halo_scene_destroy(scene);
    return failed;
}

/* (d) host contract 3: the host drawn once over the field of every segment renders the
 * volumetric halos of the same host drawn in segments, at equal M. What differs is where
 * the seeds are sampled: libhalo's march on the segment planes (as the slice host), the
 * segmented host along its own rays (jittered in webgl_caster), and with alpha = 32 the
 * seeds are steep in the gradient; at this size (40^2, 32^3) the two differ by up to a
 * third of the halos' own effect (RMSE of the segmented host with against without
 * halos), at 128^2 by 1.4 % of it (halo-emissive.json, raycast.frag, where one draw is
 * nearer the slab host than segments are: mean abs 0.0029 against 0.0037). Tolerance:
 * 0.4 of the effect; drawn once. */
static int one_draw_renders(const context *c, const host_case *h, const char *source)
{
    static const char *const scenes[] = {"halo-emissive.json", "default.json", "halo-occlusive.json"};
    int failed = 0;
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; ++i) {
        halo_scene *scene = load_scene(c, scenes[i]), *plain = load_scene(c, scenes[i]);
        if (plain && (halo_scene_enable(plain, "halo_map", 0, c->diag) != HALO_OK ||
                      halo_scene_enable(plain, "halo_generate", 0, c->diag) != HALO_OK ||
                      halo_scene_enable(plain, "halo_seed", 0, c->diag) != HALO_OK)) {
            halo_scene_destroy(plain);
            plain = NULL;
        }
        halo_program *one = scene ? link_host(c, h->file, source, scene, h->render_target, 2) : NULL;
        halo_program *segmented = scene ? link_host(c, h->file, source, scene, h->render_target, 0) : NULL;
        halo_program *without = plain ? link_host(c, h->file, source, plain, h->render_target, 0) : NULL;
        render_options o_one = {.jitter = h->jitter, .exit_points = h->exit_points}, o_seg = o_one, o_plain = o_one;
        char what[160];
        snprintf(what, sizeof what, "%s one draw %s", h->file, scenes[i]);
        comparison d, e;
        int ok = one && segmented && without &&
                 compare(c, what, one, scene, &o_one, segmented, scene, &o_seg, 0.02, &d) &&
                 compare(c, what, segmented, scene, &o_seg, without, plain, &o_plain, 0.02, &e);
        double share = ok ? (double)d.differing / (SIZE * SIZE * 4) : 1.0;
        ok = ok && d.bad == 0 && o_one.drawn == 1 && d.rmse <= 0.4 * e.rmse;
        printf(
            "%-48s drew %d (segmented %d): vs segments RMSE %.4f (<= %.4f: 0.4 of the halos' own),"
            " max abs %.3f, %.2f %% of values differ > 0.02: %s\n",
            what, o_one.drawn, o_seg.drawn, d.rmse, 0.4 * e.rmse, d.max, 100.0 * share, ok ? "PASS" : "FAIL");
        failed += !ok;
        halo_program_destroy(one);
        halo_program_destroy(segmented);
        halo_program_destroy(without);
        halo_scene_destroy(scene);
        halo_scene_destroy(plain);
    }
    return failed;
}

/* The host as it was before libhalo (its text compiled unlinked: the pragmas ignored,
 * HALO_LINKED undefined) renders the image of the host linked with no stage. */
static int unlinked_matches(const context *c, const host_case *h, const char *source)
{
    halo_scene *scene = load_scene(c, "default.json");
    halo_scene *empty = empty_like(c, scene);
    halo_program *p = empty ? link_host(c, h->file, source, empty, h->render_target, 0) : NULL;
    render_options linked = {.jitter = h->jitter, .exit_points = h->exit_points}, raw = linked;
    raw.raw_source = source;
    comparison d;
    int ok = p && compare(c, h->file, p, empty, &linked, NULL, empty, &raw, 0.0, &d) && d.bad == 0 && d.max <= 1e-6;
    char what[160];
    snprintf(what, sizeof what, "%s unlinked vs linked with no stage", h->file);
    printf("%-60s max abs %.3g (<= 1e-6): %s\n", what, d.max, ok ? "PASS" : "FAIL");
    halo_program_destroy(p);
    halo_scene_destroy(scene);
    halo_scene_destroy(empty);
    return !ok;
}

/* The exit-point caster samples as the example ray caster does; only its exit comes from
 * the first pass's texture. Their images agree up to the last sample before the exit. */
static int exit_points_match(const context *c, const char *exit_source)
{
    char *raycast = halo_host_load("raycast.frag", NULL, c->diag);
    halo_scene *scene = load_scene(c, "default.json");
    halo_scene *empty = empty_like(c, scene);
    halo_program *p = raycast ? link_host(c, "raycast.frag", raycast, empty, HALO_TARGET_GLSL450, 0) : NULL;
    halo_program *q = link_host(c, "exit_point_caster.frag", exit_source, empty, HALO_TARGET_GLSL450, 0);
    render_options plain = {0}, two_pass = {.exit_points = 1};
    comparison d;
    int ok = compare(c, "exit points", p, empty, &plain, q, empty, &two_pass, 1e-4, &d) && d.bad == 0 &&
             d.max <= 2e-2 && d.differing <= SIZE * SIZE * 4 / 50;
    printf("%-60s max abs %.3g, %ld values differ > 1e-4 (<= 2e-2, <= 2%%): %s\n",
           "exit_point_caster.frag vs raycast.frag, no stage", d.max, d.differing, ok ? "PASS" : "FAIL");
    halo_program_destroy(p);
    halo_program_destroy(q);
    halo_scene_destroy(scene);
    halo_scene_destroy(empty);
    free(raycast);
    return !ok;
}

/* The MIP variant: every scene stage refused at the pragma's line; renders without them. */
static int mip_variant_checks(const context *c, const char *iso_source)
{
    int failed = 0;
    char *mip = halo_host_mip_variant(iso_source);
    if (!mip) {
        printf("%-60s FAIL\n", "mip_iso_caster.frag: no MIP mode lines");
        return 1;
    }
    int pragma_line = 1;
    for (const char *s = mip; s < strstr(mip, "#pragma halo compositing mip"); ++s)
        pragma_line += *s == '\n';
    static const char *const scenes[] = {"default.json", "halo-emissive.json", "outline-depth.json", NULL};
    static const char *const named[] = {"halo_map", "halo_seed", "outlines", "boundary"};
    for (int i = 0; i < 4; ++i) {
        halo_scene *scene = scenes[i] ? load_scene(c, scenes[i])
                                      : halo_scene_load("per-sample.json", per_sample_scene, c->lib, c->diag);
        halo_program *p = scene ? link_host(c, "mip_iso_caster.frag", mip, scene, HALO_TARGET_GLSL330, 0) : NULL;
        const halo_diagnostic *d = halo_diagnostics_describe(c->diag).count ? halo_diagnostics_get(c->diag, 0) : NULL;
        int ok = !p && d && d->id == HALO_MSG_HOST_COMPOSITING && d->line == pragma_line &&
                 strstr(d->text, named[i]) != NULL;
        printf("%-60s %s:%d %s: %s\n", "mip variant refuses", scenes[i] ? scenes[i] : "per-sample scene",
               d ? d->line : 0, d ? halo_message_name(d->id) : "no diagnostic", ok ? "PASS" : "FAIL");
        if (!ok && d)
            halo_diagnostics_print(c->diag, stdout);
        halo_diagnostics_clear(c->diag);
        failed += !ok;
        halo_program_destroy(p);
        halo_scene_destroy(scene);
    }
    /* no stage: links, validates for every target, renders (unlike the isosurface) */
    halo_scene *scene = load_scene(c, "default.json");
    halo_scene *empty = empty_like(c, scene);
    int ok = 1;
    static const halo_target targets[] = {HALO_TARGET_GLSL330, HALO_TARGET_GLSL450, HALO_TARGET_ES300};
    for (int t = 0; t < 3; ++t) {
        halo_program *p = link_host(c, "mip_iso_caster.frag", mip, empty, targets[t], 0);
        ok = ok && p && halo_validate(&(halo_validate_desc){.program = p}, c->diag) == HALO_OK;
        halo_program_destroy(p);
    }
    halo_program *p = link_host(c, "mip_iso_caster.frag", mip, empty, HALO_TARGET_GLSL330, 0);
    halo_program *q = link_host(c, "mip_iso_caster.frag", iso_source, empty, HALO_TARGET_GLSL330, 0);
    render_options o_p = {0}, o_q = {0};
    comparison d;
    ok = compare(c, "mip variant", p, empty, &o_p, q, empty, &o_q, 0.0, &d) && ok && d.bad == 0 && d.max > 0.02;
    printf("%-60s validates; finite, vs isosurface max abs %.3f: %s\n", "mip variant, no stage", d.max,
           ok ? "PASS" : "FAIL");
    failed += !ok;
    halo_program_destroy(p);
    halo_program_destroy(q);
    halo_scene_destroy(scene);
    halo_scene_destroy(empty);
    free(mip);
    return failed;
}

/* halo_gl_program_build with defines: a host's own compile-time variant. The host gets a
 * block that only compiles wrong under TEST_VARIANT_BROKEN, before its main: built with
 * that define the driver's error is at the block's line of the host file (the inserted
 * lines and #line keep the numbering); without it, or with another define, it builds. */
static int build_defines_checks(const context *c, const char *file, const char *source)
{
    static const char block[] = "#ifdef TEST_VARIANT_BROKEN\nfloat test_variant_broken = ;\n#endif\n";
    const char *at = strstr(source, "void main()");
    if (!at)
        return 1;
    size_t head = (size_t)(at - source);
    char *text = malloc(strlen(source) + sizeof block);
    if (!text)
        return 1;
    memcpy(text, source, head);
    memcpy(text + head, block, sizeof block - 1);
    strcpy(text + head + sizeof block - 1, at);
    int line = 2; /* the broken line: one after the #ifdef */
    for (const char *p = text; p < text + head; ++p)
        line += *p == '\n';
    int failed = 0;
    halo_scene *scene = halo_scene_load("(per-sample scene)", per_sample_scene, c->lib, c->diag);
    halo_program *p = scene ? link_host(c, file, text, scene, HALO_TARGET_GLSL330, 0) : NULL;
    const char *vertex = halo_host_embedded("raycast.vert");
    for (int k = 0; k < 3 && p && vertex; ++k) {
        static const char *const defines[3] = {NULL, "#define SOMETHING_ELSE 1\n", "#define TEST_VARIANT_BROKEN 1"};
        halo_diagnostics_clear(c->diag);
        unsigned program = halo_gl_program_build(c->runtime, p, vertex, "raycast.vert", defines[k], c->diag);
        int ok;
        if (k < 2) {
            ok = program != 0 && halo_diagnostics_describe(c->diag).errors == 0;
        } else {
            const halo_diagnostic *d =
                halo_diagnostics_describe(c->diag).count ? halo_diagnostics_get(c->diag, 0) : NULL;
            ok = program == 0 && d && d->file && strstr(d->file, file) && d->line == line;
            if (!ok && d)
                printf("  got %s:%d, expected %s:%d\n", d->file ? d->file : "?", d->line, file, line);
        }
        if (program)
            c->gl->DeleteProgram(program);
        printf("%-60s %s\n",
               k == 0   ? "build_defines: none builds"
               : k == 1 ? "build_defines: another builds"
                        : "build_defines: error at the host's line",
               ok ? "PASS" : "FAIL");
        if (!ok)
            halo_diagnostics_print(c->diag, stdout);
        failed += !ok;
    }
    halo_diagnostics_clear(c->diag);
    failed += !p || !vertex;
    halo_program_destroy(p);
    halo_scene_destroy(scene);
    free(text);
    return failed;
}

int main(void)
{
    gl_fixture g;
    int status = gl_fixture_open(&g, SIZE, VOLUME);
    if (status)
        return status;
    context c = {.lib = g.lib, .runtime = g.runtime, .gl = g.gl, .diag = g.diag, .volume = g.volume};
    c.srcdir = getenv("top_srcdir") ? getenv("top_srcdir") : getenv("srcdir") ? getenv("srcdir") : ".";
    int failed = 0;
    const char *only = getenv("HALO_HOSTS_ONLY");
    for (size_t i = 0; i < sizeof hosts / sizeof hosts[0]; ++i) {
        const host_case *h = &hosts[i];
        if (only && !strstr(h->file, only))
            continue;
        char *source = halo_host_load(h->file, NULL, c.diag);
        if (!source) {
            report_diagnostics(&c, h->file);
            failed++;
            continue;
        }
        failed += link_validate(&c, h, source);
        failed += stage_renders(&c, h, source);
        failed += segment_renders(&c, h, source);
        failed += one_draw_renders(&c, h, source);
        if (h->render_target != HALO_TARGET_ES300 && strstr(source, "#version 300 es") == NULL)
            failed += unlinked_matches(&c, h, source);
        if (h->exit_points)
            failed += exit_points_match(&c, source);
        if (!strcmp(h->file, "mip_iso_caster.frag"))
            failed += mip_variant_checks(&c, source);
        if (i == 0)
            failed += build_defines_checks(&c, h->file, source);
        free(source);
    }
    printf("%d failed\n", failed);
    gl_fixture_close(&g);
    return failed ? 1 : 0;
}
