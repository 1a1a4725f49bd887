/* Host contract 2 (docs/host-contract.md, "Segmented ray casting"): the example ray caster
 * (raycast.frag) drawn by the runtime in depth segments.
 *   1. Segments alone change nothing: a per-sample scene linked with force_segments and
 *      drawn in K = 1, 4, 16 segments gives the float image of the same host drawn once
 *      (max abs <= 1e-6), with early ray termination on most rays.
 *   2. Volumetric halos: the segmented ray caster and the slab host agree at equal M
 *      within the difference their sampling makes without halos (stated below), and the
 *      halos themselves change the image far more than that.
 *   3. The diagnostics: a scene with passes in a single-pass ray caster, force_segments
 *      without halo_segment_begin.
 *   4. Host contract 3 (one_draw): the same ray caster drawn once over the field libhalo
 *      computes before the draw agrees with the slab host at equal M as the segmented one
 *      does, emissive, occlusive, directional and with halo images at 1/2; it is drawn
 *      once, keeps early ray termination, links a single-pass host without segment calls,
 *      refuses force_segments and slab hosts, links the slice host (its slices drawn at
 *      once), and says what it needs.
 *   5. A host that leaves hostile GL state between its draws (issue 26: culling, depth and
 *      stencil tests that pass nothing, blending to zero, a one-pixel scissor and
 *      viewport, colour writes off, lines, rasterizer discard, sRGB, odd packing and
 *      bindings) gets the tidy host's floats in segments and in one draw, and libhalo
 *      gives all of that state back (before the fixes: a GL error in segments, 0.56 max
 *      abs in one draw).
 *   6. Host contract 3 across the pieces of a distributed volume: two pieces' marches, the
 *      seeds of every segment combined once a frame by the exchange, against one
 *      renderer of the whole volume (control: a piece without the other's seeds).
 *   7. Host contract 3's field kept across draws: drawn again, the frame reuses its field
 *      unless the camera, the volume or a parameter of a stage that seeds or spreads it
 *      changed, and each image is the one a new frame computes from scratch (max abs 0);
 *      a parameter of halo_map (read in the host's draw) changes the image, not the field.
 *   1 again with an orthographic camera (segments of the clip z planes).
 * The segmented ray caster against its emulation is the conformance family "segments"
 * (validate/conform_segment.c, halo-validate conform --stage segments).
 * Exit 77 without OpenGL. */
#include "../../gl_fixture.h"
#include "../../hostile.h"
#include "gl/frame.h" /* halo_gl_field_computed */
#include "hosts/raycast.h"
#include "hosts/slab.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SIZE   48
#define VOLUME 24

#define RENDER                                                                       \
    "\"render\": {\"azimuth\": 30, \"elevation\": 20, \"zoom\": 1.3, \"step\": 0.5," \
    " \"transfer\": [[0, 0, 0, 0, 0], [0.25, 0.6, 0.8, 1, 0.6], [0.5, 1, 0.85, 0.55, 1], [1, 1, 1, 0.8, 1]]}"

/* Dense enough that most rays end on the 0.99 opacity threshold. */
static const char sample_scene[] =
    "{\"halo_scene\": 1, \"stages\": [{\"boundary\": {}}, {\"silhouette\": {\"k_ss\": 4, \"k_se\": 1}},"
    " {\"tone_shading\": {}}, {\"distance_blend\": {}}], " RENDER "}";
/* halo-render's default halo (examples/scenes/default.json): emissive, dark, around the
 * tube and the blobs, seen through transparent shells. */
#define HALO_RENDER                                                                            \
    "\"render\": {\"azimuth\": 35, \"elevation\": 25, \"zoom\": 1.5, \"step\": 0.5,"           \
    " \"background\": [0.05, 0.08, 0.25],"                                                     \
    " \"transfer\": [[0, 0, 0, 0, 0], [0.18, 0.6, 0.8, 1, 0], [0.3, 0.6, 0.8, 1, 0.06],"       \
    " [0.42, 1, 0.85, 0.55, 0.02], [0.5, 1, 0.85, 0.55, 0.25], [0.62, 0.9, 0.35, 0.25, 0.05]," \
    " [0.75, 0.95, 0.3, 0.2, 0.7], [0.9, 1, 0.95, 0.7, 0.8], [1, 1, 1, 0.8, 0.9]]}"
static const char halos_scene[] =
    "{\"halo_scene\": 1, \"stages\": ["
    " {\"halo_seed\": {\"alpha\": 2, \"gradient_scale\": 6, \"value_0\": [[0.55, 0], [0.62, 1], [0.8, 1], [0.9, 0]]}},"
    " {\"halo_generate\": {\"passes\": 5, \"delta\": 0.9, \"interval\": 4}},"
    " {\"halo_map\": {\"mode\": 0, \"color_near\": [[0, 0, 0]], \"color_far\": [[0, 0, 0]], \"opacity\": 1,"
    " \"full_at\": 0.25}}], " HALO_RENDER "}";
static const char occlusive_scene[] =
    "{\"halo_scene\": 1, \"stages\": ["
    " {\"halo_seed\": {\"alpha\": 2, \"gradient_scale\": 6, \"value_0\": [[0.55, 0], [0.62, 1], [0.8, 1], [0.9, 0]]}},"
    " {\"halo_generate\": {\"passes\": 5, \"delta\": 0.9, \"interval\": 4}},"
    " {\"halo_map\": {\"mode\": 1, \"color_near\": [[0, 0, 0]], \"color_far\": [[0, 0, 0]], \"opacity\": 1,"
    " \"full_at\": 0.25}}], " HALO_RENDER "}";
/* directional: halo_seed's image-plane axes matter (derived from the camera in one draw) */
static const char directional_scene[] =
    "{\"halo_scene\": 1, \"stages\": ["
    " {\"halo_seed\": {\"alpha\": 2, \"gradient_scale\": 6, \"direction_center\": 45, \"direction_width\": 120,"
    " \"value_0\": [[0.55, 0], [0.62, 1], [0.8, 1], [0.9, 0]]}},"
    " {\"halo_generate\": {\"passes\": 5, \"delta\": 0.9, \"interval\": 4}},"
    " {\"halo_map\": {\"mode\": 0, \"color_near\": [[0, 0, 0]], \"color_far\": [[0, 0, 0]], \"opacity\": 1,"
    " \"full_at\": 0.25}}], " HALO_RENDER "}";
static const char no_halo_scene[] = "{\"halo_scene\": 1, \"stages\": [], " HALO_RENDER "}";

typedef struct env {
    gl_fixture g; /* the context, library, runtime, diagnostics and the built-in volume */
    char *raycast, *slab;
} env;

static int failures;
static int orthographic; /* the camera of the next renders */

#define CHECK(cond, ...)                                \
    do {                                                \
        if (!(cond)) {                                  \
            printf("FAIL %s:%d: ", __FILE__, __LINE__); \
            printf(__VA_ARGS__);                        \
            printf("\n");                               \
            failures++;                                 \
        }                                               \
    } while (0)

static int one_draw;             /* host contract 3 for the next ray caster renders */
static int untidy;               /* the next ray caster renders leave hostile GL state (hostile_state) */
static int image_scale;          /* halo_link_desc.image_scale of the next renders */
static size_t field_max_bytes;   /* halo_gl_segments_desc.field_max_bytes of the next ray caster renders */
static char field_message[1024]; /* the last render's FIELD_MEMORY diagnostic, or "" */
static long pass_draws;          /* the last ray caster render's generation pass draws */
static size_t gpu_bytes;         /* and its frame's GPU memory (halo_gl_frame_info.gpu_bytes) */
/* a piece of the volume that the next ray caster renders' march reads (test_pieces) */
typedef struct piece_setup {
    const float *data;
    int dims[3];
    float min[3], max[3];
    void (*exchange)(void *user, float *values, size_t count, halo_blend blend);
    void *user;
    size_t max_bytes; /* halo_gl_segments_desc.exchange_max_bytes */
} piece_setup;
static const piece_setup *piece;
/* the ray caster's and the slab host's difference without halos, perspective (RMSE) */
static double plain_difference;

/* ---- A host that leaves hostile GL state between its draws (issue 26) ---- */

static hostile hostile_host; /* tests/hostile.h; its functions are set in test_hostile_state */

/* The ray caster's untidy hook: after each of its draws the host leaves hostile state;
 * before each (and when halo_gl_frame_draw returns) libhalo must have given it back. */
static void hostile_state(void *user, int before_draw)
{
    (void)user;
    if (before_draw)
        hostile_check(&hostile_host, before_draw == 2, "halo_gl_frame_draw");
    else
        hostile_set(&hostile_host);
}

static halo_program *link_scene(env *e, const char *scene_text, const char *host, const char *file, int force,
                                halo_scene **scene_out)
{
    halo_scene *scene = halo_scene_load("(test scene)", scene_text, e->g.lib, e->g.diag);
    halo_program *p = scene ? halo_link(&(halo_link_desc){.library = e->g.lib,
                                                          .scene = scene,
                                                          .host_source = host,
                                                          .host_file = file,
                                                          .force_segments = force,
                                                          .one_draw = one_draw,
                                                          .image_scale = image_scale},
                                        e->g.diag)
                            : NULL;
    if (!p) {
        halo_diagnostics_print(e->g.diag, stdout);
        halo_scene_destroy(scene);
        return NULL;
    }
    *scene_out = scene;
    return p;
}

/* Renders with the ray caster (slab 0) in `segments` segments (0: as the program needs),
 * or with the slab host (slab 1), of M = interval planes. */
static float *render_host(env *e, const char *scene_text, int slab, int force, int interval, int segments, int *drawn)
{
    halo_scene *scene = NULL;
    halo_program *p =
        link_scene(e, scene_text, slab ? e->slab : e->raycast, slab ? "slab.frag" : "raycast.frag", force, &scene);
    float *rgba = malloc((size_t)SIZE * SIZE * 4 * sizeof *rgba);
    const halo_host_desc desc = {.gl = e->g.gl, .runtime = e->g.runtime, .program = p, .width = SIZE, .height = SIZE};
    halo_raycast *r = p && !slab ? halo_raycast_create(&desc, e->g.diag) : NULL;
    halo_slab *s = p && slab ? halo_slab_create(&desc, e->g.diag) : NULL;
    int ok = (r || s) && rgba;
    if (ok && r) {
        const halo_render_settings *settings = halo_scene_describe(scene).render;
        ok = halo_raycast_set_volume(r, e->g.volume, VOLUME, VOLUME, VOLUME, e->g.diag) == HALO_OK &&
             halo_raycast_set_render(r, settings, e->g.diag) == HALO_OK;
        halo_raycast_set_orthographic(r, orthographic);
        halo_raycast_set_camera(r, settings->azimuth, settings->elevation, settings->zoom);
        halo_raycast_set_segments(r, interval, segments);
        if (untidy)
            halo_raycast_set_untidy(r, hostile_state, e);
        if (piece)
            ok =
                ok && halo_raycast_set_piece(r, piece->data, piece->dims[0], piece->dims[1], piece->dims[2], piece->min,
                                             piece->max, piece->exchange, piece->user, e->g.diag) == HALO_OK;
        if (piece)
            halo_raycast_set_exchange_max_bytes(r, piece->max_bytes);
        halo_raycast_set_field_max_bytes(r, field_max_bytes);
        ok = ok && halo_raycast_render(r, rgba, e->g.diag) == HALO_OK;
        if (drawn)
            *drawn = halo_raycast_frame(r) ? halo_gl_frame_describe(halo_raycast_frame(r)).segment_count : 1;
        pass_draws = halo_raycast_frame(r) ? halo_gl_frame_describe(halo_raycast_frame(r)).pass_draws : 0;
        gpu_bytes = halo_raycast_frame(r) ? halo_gl_frame_describe(halo_raycast_frame(r)).gpu_bytes : 0;
    } else if (ok) {
        const halo_render_settings *settings = halo_scene_describe(scene).render;
        ok = halo_slice_set_volume(s, e->g.volume, VOLUME, VOLUME, VOLUME, e->g.diag) == HALO_OK &&
             halo_slice_set_render(s, settings, e->g.diag) == HALO_OK;
        halo_slice_set_camera(s, settings->azimuth, settings->elevation, settings->zoom);
        halo_slice_set_interval(s, interval);
        ok = ok && halo_slice_render(s, rgba, e->g.diag) == HALO_OK;
    }
    if (!ok) {
        halo_diagnostics_print(e->g.diag, stdout);
        free(rgba);
        rgba = NULL;
    }
    halo_raycast_destroy(r);
    halo_slice_destroy(s);
    halo_program_destroy(p);
    halo_scene_destroy(scene);
    field_message[0] = '\0';
    for (size_t i = 0; i < halo_diagnostics_describe(e->g.diag).count; ++i)
        if (halo_diagnostics_get(e->g.diag, i)->id == HALO_MSG_FIELD_MEMORY)
            snprintf(field_message, sizeof field_message, "%s", halo_diagnostics_get(e->g.diag, i)->text);
    halo_diagnostics_clear(e->g.diag);
    return rgba;
}

static float *render_ray(env *e, const char *scene_text, int force, int interval, int segments, int *drawn)
{
    return render_host(e, scene_text, 0, force, interval, segments, drawn);
}

static float *render_slab(env *e, const char *scene_text, int interval)
{
    return render_host(e, scene_text, 1, 0, interval, 0, NULL);
}

static void difference(const float *a, const float *b, double *max_abs, double *rmse)
{
    double worst = 0.0, sum = 0.0;
    size_t n = (size_t)SIZE * SIZE * 4;
    for (size_t i = 0; i < n; ++i) {
        double d = fabs((double)a[i] - (double)b[i]);
        if (!(d <= worst))
            worst = d; /* NaN wins */
        sum += d * d;
    }
    *max_abs = worst;
    *rmse = sqrt(sum / (double)n);
}

static void test_segments_change_nothing(env *e)
{
    float *once = render_ray(e, sample_scene, 0, 0, 0, NULL);
    CHECK(once, "the ray caster renders the per-sample scene in one draw");
    static const int counts[] = {1, 4, 16};
    for (size_t k = 0; once && k < sizeof counts / sizeof counts[0]; ++k) {
        int drawn = 0;
        float *segmented = render_ray(e, sample_scene, 1, 0, counts[k], &drawn);
        CHECK(segmented, "K = %d renders", counts[k]);
        if (!segmented)
            continue;
        double max_abs, rmse;
        difference(segmented, once, &max_abs, &rmse);
        printf("segments K = %2d (%2d drawn, %s): max abs %.3g against one draw\n", counts[k], drawn,
               orthographic ? "orthographic" : "perspective", max_abs);
        CHECK(drawn == counts[k], "K = %d: %d segments drawn", counts[k], drawn);
        CHECK(max_abs <= 1e-6, "K = %d: max abs %.3g > 1e-6", counts[k], max_abs);
        free(segmented);
    }
    free(once);
}

/* Tolerance of the ray caster against the slab host with halos at equal M: their samples
 * lie at other places (along each ray from its entry, against on the slice planes), so
 * without halos they already differ by d0 (RMSE); the halos may add at most as much again
 * plus 2e-3 for the seeds that fall into the neighbouring segment. */
static void test_halos_match_slab(env *e)
{
    int drawn = 0;
    float *ray = render_ray(e, halos_scene, 0, 4, 0, &drawn);
    float *slab = render_slab(e, halos_scene, 4);
    float *ray_plain = render_ray(e, no_halo_scene, 0, 0, 0, NULL);
    float *slab_plain = render_slab(e, no_halo_scene, 4);
    CHECK(ray && slab && ray_plain && slab_plain, "the four renders");
    if (ray && slab && ray_plain && slab_plain) {
        double m_halo, r_halo, m_plain, r_plain, m_effect, r_effect;
        difference(ray, slab, &m_halo, &r_halo);
        difference(ray_plain, slab_plain, &m_plain, &r_plain);
        difference(ray, ray_plain, &m_effect, &r_effect);
        double tolerance = 2.0 * r_plain + 2e-3;
        printf(
            "halos at M = 4 (%d segments): ray caster against slab host RMSE %.3g (max %.3g); without halos %.3g"
            " (max %.3g); tolerance %.3g; the halos' own effect RMSE %.3g\n",
            drawn, r_halo, m_halo, r_plain, m_plain, tolerance, r_effect);
        CHECK(r_halo <= tolerance, "ray caster against slab host: RMSE %.3g > %.3g", r_halo, tolerance);
        CHECK(r_effect > 5.0 * r_halo,
              "the halos change the image (RMSE %.3g) not far more than the hosts differ (%.3g)", r_effect, r_halo);
        CHECK(drawn > 1, "a halo scene is drawn in segments (%d)", drawn);
    }
    free(ray);
    free(slab);
    free(ray_plain);
    free(slab_plain);
}

/* The one-draw ray caster at M = 4 through a runtime of its own with the read-back policy
 * `readback` (the pass draws of its frame in *passes); NULL after a message. */
static float *render_one_draw_readback(env *e, const char *scene_text, halo_gl_readback readback, long *passes)
{
    halo_gl *runtime = e->g.runtime;
    e->g.runtime = halo_gl_create(
        &(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address, .readback = readback}, e->g.diag);
    one_draw = 1;
    float *image = e->g.runtime ? render_ray(e, scene_text, 0, 4, 0, NULL) : NULL;
    *passes = pass_draws;
    one_draw = 0;
    if (!e->g.runtime)
        halo_diagnostics_print(e->g.diag, stdout);
    halo_gl_destroy(e->g.runtime);
    e->g.runtime = runtime;
    return image;
}

/* Host contract 3: at equal M the one-draw ray caster's halos are the slab host's as the
 * segmented ray caster's are (the same tolerance), and it is drawn once. With image_scale,
 * the one draw's halo images and march at that scale against the references at full size
 * (the exact algorithm: the references' own 1/2 max-reduces their seeds, a coarser
 * approximation than the march's samples at the 1/2 pixels' centres, docs/performance.md). */
static void test_one_draw_matches(env *e, const char *scene_text, const char *what)
{
    int drawn = 0, segmented_drawn = 0, scale = image_scale;
    one_draw = 1;
    float *ray = render_ray(e, scene_text, 0, 4, 0, &drawn);
    long one_draw_passes = pass_draws;
    size_t one_draw_bytes = gpu_bytes;
    one_draw = 0;
    image_scale = 0;
    float *segmented = render_ray(e, scene_text, 0, 4, 0, &segmented_drawn);
    float *slab = render_slab(e, scene_text, 4);
    float *ray_plain = render_ray(e, no_halo_scene, 0, 0, 0, NULL);
    float *slab_plain = render_slab(e, no_halo_scene, 4);
    image_scale = scale;
    /* at 1/scale: the slab host's own 1/scale halos, whose error against its full size the
     * one draw's must not exceed */
    float *slab_scaled = scale > 1 ? render_slab(e, scene_text, 4) : NULL;
    CHECK(ray && segmented && slab && ray_plain && slab_plain && (scale <= 1 || slab_scaled), "%s: the renders", what);
    if (ray && segmented && slab && ray_plain && slab_plain) {
        double m_halo, r_halo, m_plain, r_plain, m_seg, r_seg, m_effect, r_effect;
        difference(ray, slab, &m_halo, &r_halo);
        difference(ray_plain, slab_plain, &m_plain, &r_plain);
        difference(ray, segmented, &m_seg, &r_seg);
        difference(ray, ray_plain, &m_effect, &r_effect);
        if (!orthographic)
            plain_difference = r_plain;
        double tolerance = 2.0 * plain_difference + 2e-3, m_scaled = 0.0, r_scaled = 0.0;
        if (slab_scaled) {
            difference(slab_scaled, slab, &m_scaled, &r_scaled);
            printf("%s: the slab host at 1/%d against itself at full size RMSE %.3g (max %.3g)\n", what, scale,
                   r_scaled, m_scaled);
            tolerance = r_scaled; /* an approximation: no worse than the slab host's own */
        }
        printf(
            "%s halos at M = 4, one draw (%d drawn, %ld generation pass draws; segmented: %d): against the slab host RMSE %.3g (max %.3g),"
            " tolerance %.3g; against the segmented ray caster RMSE %.3g (max %.3g); the halos' own effect RMSE"
            " %.3g\n",
            what, drawn, one_draw_passes, segmented_drawn, r_halo, m_halo, tolerance, r_seg, m_seg, r_effect);
        /* the slab host has no orthographic camera: there the segmented ray caster is the reference */
        CHECK(orthographic || r_halo <= tolerance, "%s: one draw against slab host: RMSE %.3g > %.3g", what, r_halo,
              tolerance);
        CHECK(r_seg <= tolerance, "%s: one draw against segments: RMSE %.3g > %.3g", what, r_seg, tolerance);
        double r_reference = orthographic ? r_seg : r_halo;
        CHECK(r_effect > (slab_scaled ? 3.0 : 5.0) * r_reference,
              "%s: the halos change the image (RMSE %.3g) not far more than the hosts"
              " differ (%.3g)",
              what, r_effect, r_reference);
        CHECK(drawn == 1, "%s: one draw of the host (%d)", what, drawn);
        /* an emissive scene's generations on the atlas (gl/field_atlas.c): each pass one draw
         * over every segment, H_0 and the five spreading passes, however many segments */
        if (scene_text == halos_scene)
            CHECK(one_draw_passes > 0 && one_draw_passes <= 6, "%s: generation pass draws of the frame %ld, not <= 6",
                  what, one_draw_passes);
        /* the memory the frame reports holds at least the field's stack (20 layers of a
         * one-channel float image, at the halo images' size) and the atlas beside it */
        size_t side = (size_t)(SIZE + (scale > 1 ? scale : 1) - 1) / (size_t)(scale > 1 ? scale : 1),
               stack = 20 * side * side * 4;
        printf("%s: the frame's GPU memory %.3g MiB, the field's stack %.3g MiB\n", what,
               (double)one_draw_bytes / 1048576.0, (double)stack / 1048576.0);
        CHECK(one_draw_bytes >= 2 * stack, "%s: the frame's GPU memory %zu bytes, under the stack and atlas's %zu",
              what, one_draw_bytes, 2 * stack);
        /* and the occlusion image's running maximum on the atlas too: where the frame reads
         * back (a software renderer: the pixels are the cost), a tile a draw, at most 20 for
         * 21 segments; without (a GPU) a prefix scan, a draw each doubling of the tiles it
         * combines, at most 5; the same floats (both forced here, whatever the renderer) */
        if (scene_text == occlusive_scene) {
            long sequence_passes = 0, scan_passes = 0;
            float *sequence = render_one_draw_readback(e, scene_text, HALO_GL_READBACK_ON, &sequence_passes);
            float *scan = render_one_draw_readback(e, scene_text, HALO_GL_READBACK_OFF, &scan_passes);
            double m_scan = 1.0, r_scan = 1.0;
            if (scan && sequence)
                difference(scan, sequence, &m_scan, &r_scan);
            printf("%s: %ld generation pass draws with read-back, %ld without; the two images max abs %.3g\n", what,
                   sequence_passes, scan_passes, m_scan);
            CHECK(scan && sequence && m_scan == 0.0, "%s: the scan against a tile a draw: max abs %.3g", what, m_scan);
            CHECK(sequence_passes > 0 && sequence_passes <= 6 + 20,
                  "%s, read-back on: generation pass draws of the frame %ld, not <= 6 + 20", what, sequence_passes);
            CHECK(scan_passes > 0 && scan_passes <= 6 + 5,
                  "%s, read-back off: generation pass draws of the frame %ld, not <= 6 + 5", what, scan_passes);
            free(sequence);
            free(scan);
        }
    }
    free(ray);
    free(segmented);
    free(slab);
    free(ray_plain);
    free(slab_plain);
    free(slab_scaled);
}

/* Host contract 3's memory cap: a field over field_max_bytes is refused (FIELD_MEMORY, the
 * image scale that fits named), drawing nothing; at that scale the same cap holds it. */
static void test_field_memory(env *e)
{
    one_draw = 1;
    float *full = render_ray(e, halos_scene, 0, 4, 0, NULL);
    /* the layers (the segments but the last): from the refusal at a cap of one byte */
    char text[1024] = "";
    int layers = 0;
    for (int round = 0; round < 2; ++round) {
        /* a layer at full size: SIZE^2 texels of the field (one channel, 4 bytes) */
        field_max_bytes = round == 0 ? 1 : (size_t)layers * SIZE * SIZE * 4 / 2;
        float *refused = render_ray(e, halos_scene, 0, 4, 0, NULL);
        snprintf(text, sizeof text, "%s", field_message);
        if (round == 0 && sscanf(text, "halo_gl_frame_draw: the halo field of %d layers", &layers) != 1)
            layers = 0;
        printf("field over its cap (%zu bytes): %s\n", field_max_bytes, text[0] ? text : "(no message)");
        CHECK(full && !refused && text[0], "field over a cap of %zu bytes: refused with FIELD_MEMORY (%s)",
              field_max_bytes, refused ? "drawn" : "not drawn");
        free(refused);
        if (!layers)
            break;
    }
    CHECK(layers > 1 && strstr(text, "image_scale 2 fits"), "field over its cap: the message names image_scale 2 (%s)",
          text);
    image_scale = 2; /* a quarter of the bytes: under the same cap */
    float *half = render_ray(e, halos_scene, 0, 4, 0, NULL);
    CHECK(half != NULL, "field at 1/2 under the same cap: drawn");
    image_scale = 0;
    field_max_bytes = 0;
    one_draw = 0;
    free(full);
    free(half);
}

/* ---- Host contract 3 across the pieces of a distributed volume ---- */

/* The seeds a piece's exchange sees: kept (capture: every call's values one after the
 * other), or combined with those kept (max), call after call from the start. */
typedef struct seed_exchange {
    int combine, calls;
    float *kept;
    size_t count, at;
} seed_exchange;

static void exchange_seeds(void *user, float *values, size_t count, halo_blend blend)
{
    seed_exchange *x = user;
    x->calls++;
    if (!x->combine) {
        float *grown = realloc(x->kept, (x->count + count) * sizeof *values);
        if (!grown)
            return;
        x->kept = grown;
        memcpy(x->kept + x->count, values, count * sizeof *values);
        x->count += count;
        return;
    }
    for (size_t i = 0; i < count && x->at + i < x->count && blend == HALO_BLEND_MAX; ++i)
        values[i] = values[i] > x->kept[x->at + i] ? values[i] : x->kept[x->at + i];
    x->at += count;
}

/* The x points [first, first + n) of the built-in volume, and their texels' box. */
static float *volume_piece(const env *e, int first, int n, piece_setup *ps)
{
    float *data = malloc((size_t)n * VOLUME * VOLUME * sizeof *data);
    if (!data)
        return NULL;
    for (int z = 0; z < VOLUME; ++z)
        for (int y = 0; y < VOLUME; ++y)
            for (int x = 0; x < n; ++x)
                data[((size_t)z * VOLUME + (size_t)y) * (size_t)n + (size_t)x] =
                    e->g.volume[((size_t)z * VOLUME + (size_t)y) * VOLUME + (size_t)(first + x)];
    *ps = (piece_setup){data,
                        {n, VOLUME, VOLUME},
                        {(float)first / VOLUME, 0, 0},
                        {(float)(first + n) / VOLUME, 1, 1},
                        exchange_seeds,
                        NULL,
                        0};
    return data;
}

/* Two pieces sharing the volume's middle x point, each with its own march, the seeds of
 * every segment combined once a frame (halo_gl_segments_desc.exchange): piece A's render,
 * with B's seeds combined in, against one renderer of the whole volume; the whole volume
 * given as one piece with an exchange that changes nothing, against no exchange at all;
 * and the control, piece A without B's seeds, which must be far off. */
static void test_pieces(env *e)
{
    one_draw = 1;
    float *whole = render_ray(e, halos_scene, 0, 4, 0, NULL);
    piece_setup all, a, b;
    seed_exchange same = {.combine = 1}, capture = {0}, combine = {.combine = 1}, alone = {.combine = 1};
    float *all_data = volume_piece(e, 0, VOLUME, &all);
    all.user = &same;
    piece = &all;
    float *as_piece = render_ray(e, halos_scene, 0, 4, 0, NULL);
    int half = VOLUME / 2;
    float *b_data = volume_piece(e, half, VOLUME - half, &b), *a_data = volume_piece(e, 0, half + 1, &a);
    b.user = &capture;
    piece = &b;
    float *b_image = render_ray(e, halos_scene, 0, 4, 0, NULL);
    combine.kept = capture.kept;
    combine.count = capture.count;
    a.user = &combine;
    piece = &a;
    float *a_image = render_ray(e, halos_scene, 0, 4, 0, NULL);
    a.user = &alone;
    float *a_alone = render_ray(e, halos_scene, 0, 4, 0, NULL);
    /* the same two pieces with the exchange split into calls of one layer each
     * (exchange_max_bytes 1: at least one layer a call) */
    seed_exchange capture1 = {0}, combine1 = {.combine = 1};
    b.user = &capture1;
    b.max_bytes = 1;
    piece = &b;
    float *b_split = render_ray(e, halos_scene, 0, 4, 0, NULL);
    combine1.kept = capture1.kept;
    combine1.count = capture1.count;
    a.user = &combine1;
    a.max_bytes = 1;
    piece = &a;
    float *a_split = render_ray(e, halos_scene, 0, 4, 0, NULL);
    piece = NULL;
    one_draw = 0;
    CHECK(whole && as_piece && b_image && a_image && a_alone, "pieces: the five renders");
    if (whole && as_piece && b_image && a_image && a_alone) {
        double m_same, r_same, m_pieces, r_pieces, m_alone, r_alone;
        difference(as_piece, whole, &m_same, &r_same);
        difference(a_image, whole, &m_pieces, &r_pieces);
        difference(a_alone, whole, &m_alone, &r_alone);
        printf(
            "pieces: the whole volume as one piece with an exchange against none, max abs %.3g; two pieces, the "
            "seeds combined once a frame (%d and %d calls, %zu floats each), against the whole volume: RMSE %.3g "
            "(max %.3g); piece A without B's seeds: RMSE %.3g (max %.3g)\n",
            m_same, capture.calls, combine.calls, capture.count, r_pieces, m_pieces, r_alone, m_alone);
        CHECK(m_same <= 1e-6, "pieces: an exchange that changes nothing changes the image by %.3g", m_same);
        CHECK(capture.calls == 1 && combine.calls == 1, "pieces: one exchange a frame (%d, %d)", capture.calls,
              combine.calls);
        double m_split = 1.0, r_split;
        if (a_split && b_split)
            difference(a_split, a_image, &m_split, &r_split);
        printf(
            "pieces: the exchange in calls of one layer (%d and %d calls, %zu floats in all): max abs %.3g against "
            "one call\n",
            capture1.calls, combine1.calls, capture1.count, m_split);
        CHECK(capture1.calls > 1 && capture1.calls == combine1.calls && capture1.count == capture.count,
              "pieces: the split exchange: %d and %d calls, %zu floats (one call: %zu)", capture1.calls, combine1.calls,
              capture1.count, capture.count);
        CHECK(m_split == 0.0, "pieces: the split exchange changes the image by %.3g", m_split);
        /* the pieces' gradients at the shared points are one-sided (no ghost points) */
        CHECK(r_pieces <= 2e-3, "pieces: two pieces against the whole volume: RMSE %.3g > 2e-3", r_pieces);
        CHECK(r_alone > 5.0 * r_pieces, "pieces: the other piece's seeds change little (RMSE %.3g against %.3g)",
              r_alone, r_pieces);
    }
    free(capture.kept);
    free(capture1.kept);
    free(a_split);
    free(b_split);
    free(all_data);
    free(a_data);
    free(b_data);
    free(whole);
    free(as_piece);
    free(b_image);
    free(a_image);
    free(a_alone);
}

/* A host that leaves hostile state between its draws (culling, depth and stencil tests
 * that pass nothing, blending to zero, a one-pixel scissor and viewport, colour writes off,
 * lines, rasterizer discard, sRGB, odd packing and bindings: hostile_set) gets the same
 * floats as a tidy one, in segments (contract 2: libhalo's generation passes between its
 * draws) and in one draw (contract 3: libhalo's march and passes before it), with
 * emissive and occlusive halos; and libhalo gives every piece of that state back. */
static void test_hostile_state(env *e)
{
    const char *scenes[2] = {halos_scene, occlusive_scene};
    for (int s = 0; s < 2; ++s)
        for (int draw_once = 0; draw_once < 2; ++draw_once) {
            one_draw = draw_once;
            float *tidy = render_ray(e, scenes[s], 0, 4, 0, NULL);
            hostile_host = (hostile){.f = e->g.gl, .vertex_array = hostile_host.vertex_array};
            untidy = 1;
            float *untidy_image = render_ray(e, scenes[s], 0, 4, 0, NULL);
            untidy = 0;
            hostile_unset(&hostile_host); /* the later tests' hosts upload with the default packing */
            one_draw = 0;
            const char *what = draw_once ? "one draw" : "segments";
            CHECK(tidy && untidy_image, "%s, %s: both renders", s ? "occlusive halos" : "emissive halos", what);
            if (tidy && untidy_image) {
                double max_abs, rmse;
                difference(tidy, untidy_image, &max_abs, &rmse);
                printf(
                    "hostile host state, %s, %s: against a tidy host max abs %.3g; %d checks of the state libhalo "
                    "gives back, %d changes\n",
                    s ? "occlusive halos" : "emissive halos", what, max_abs, hostile_host.checks,
                    hostile_host.mismatches);
                CHECK(max_abs == 0.0, "%s, %s: a host's hostile state changes the image by %.3g",
                      s ? "occlusive halos" : "emissive halos", what, max_abs);
                CHECK(hostile_host.checks > 0 && hostile_host.mismatches == 0,
                      "%s, %s: libhalo changed %d pieces of the host's "
                      "state",
                      s ? "occlusive halos" : "emissive halos", what, hostile_host.mismatches);
            }
            free(tidy);
            free(untidy_image);
        }
}

static void draw_nothing(void *user) { (void)user; }
static halo_gl_frame *destroying_frame;
static int destroy_calls;
static void draw_destroying(void *user)
{
    (void)user;
    destroy_calls++;
    halo_gl_frame_destroy(destroying_frame);
}

static void test_diagnostics(env *e)
{
    static const char single_pass[] =
        "#version 330 core\n"
        "#pragma halo declarations\n"
        "uniform sampler3D volume;\n"
        "layout(location = 0) out vec4 color;\n"
        "void main() {\n"
        "    vec4 sum = vec4(0.0);\n"
        "    for (int i = 0; i < 64; ++i) {\n"
        "        vec3 P = vec3(0.5, 0.5, float(i) / 64.0);\n"
        "        float v = texture(volume, P).r;\n"
        "#ifdef HALO_LINKED\n"
        "        halo_sample s = halo_make_sample(P, v, vec3(0.0), vec3(0.0, 0.0, 1.0), P.z, gl_FragCoord.xy,\n"
        "                                         vec3(v), v);\n"
        "        halo_apply(s);\n"
        "        sum += vec4(s.color, 1.0) * s.opacity * (1.0 - sum.a);\n"
        "#endif\n"
        "    }\n"
        "#ifdef HALO_LINKED\n"
        "    halo_finish();\n"
        "#endif\n"
        "    color = sum;\n"
        "}\n";
    halo_scene *scene = halo_scene_load("(test scene)", halos_scene, e->g.lib, e->g.diag);
    halo_program *p = halo_link(
        &(halo_link_desc){.library = e->g.lib, .scene = scene, .host_source = single_pass, .host_file = "single.frag"},
        e->g.diag);
    const halo_diagnostic *d = halo_diagnostics_describe(e->g.diag).count ? halo_diagnostics_get(e->g.diag, 0) : NULL;
    CHECK(!p && halo_diagnostics_has(e->g.diag, HALO_MSG_HOST_SINGLE_PASS),
          "a halo scene in a single-pass ray caster is refused with HOST_SINGLE_PASS");
    CHECK(d && !strcmp(d->file, "single.frag") && d->line == 2, "at the host's marker (single.frag:2): %s:%d",
          d ? d->file : "-", d ? d->line : 0);
    CHECK(d && strstr(d->text, "halo_generate"), "the message names the stage with passes");
    halo_program_destroy(p);
    halo_diagnostics_clear(e->g.diag);
    p = halo_link(&(halo_link_desc){.library = e->g.lib,
                                    .scene = NULL,
                                    .host_source = single_pass,
                                    .host_file = "single.frag",
                                    .force_segments = 1},
                  e->g.diag);
    CHECK(!p && halo_diagnostics_has(e->g.diag, HALO_MSG_HOST_SINGLE_PASS),
          "force_segments without halo_segment_begin is refused");
    /* issue 26: segments = 1e8 ran for minutes; past HALO_SEGMENTS_MAX it is refused at once */
    float *many = render_ray(e, sample_scene, 1, 0, 100000000, NULL);
    CHECK(many == NULL, "segments = 1e8 is refused (USAGE), not drawn");
    free(many);
    float *most = render_ray(e, sample_scene, 1, 0, 3, NULL);
    CHECK(most != NULL, "segments = 3 draws");
    free(most);
    halo_program_destroy(p);
    halo_diagnostics_clear(e->g.diag);
    /* the same host, declared a slice host that runs the passes itself, links */
    char *slices = malloc(sizeof single_pass + 32);
    if (slices) {
        snprintf(slices, sizeof single_pass + 32, "#pragma halo slices\n%s", single_pass);
        p = halo_link(
            &(halo_link_desc){.library = e->g.lib, .scene = scene, .host_source = slices, .host_file = "slices.frag"},
            e->g.diag);
        CHECK(p != NULL, "with '#pragma halo slices' the host links");
        halo_program_destroy(p);
        halo_diagnostics_clear(e->g.diag);
        free(slices);
    }
    /* host contract 3 refuses what it cannot draw once */
    p = halo_link(&(halo_link_desc){.library = e->g.lib,
                                    .scene = scene,
                                    .host_source = e->raycast,
                                    .host_file = "raycast.frag",
                                    .one_draw = 1,
                                    .force_segments = 1},
                  e->g.diag);
    CHECK(!p && halo_diagnostics_has(e->g.diag, HALO_MSG_USAGE), "one_draw with force_segments is refused");
    halo_program_destroy(p);
    halo_diagnostics_clear(e->g.diag);
    p = halo_link(
        &(halo_link_desc){
            .library = e->g.lib, .scene = scene, .host_source = e->slab, .host_file = "slab.frag", .one_draw = 1},
        e->g.diag);
    CHECK(!p && halo_diagnostics_has(e->g.diag, HALO_MSG_USAGE), "one_draw with a slab host is refused");
    halo_program_destroy(p);
    halo_diagnostics_clear(e->g.diag);
    /* a slice host (one sample a fragment) draws its slices at once over the field */
    char *slice = halo_host_load("slice.frag", NULL, e->g.diag);
    p = slice ? halo_link(&(halo_link_desc){.library = e->g.lib,
                                            .scene = scene,
                                            .host_source = slice,
                                            .host_file = "slice.frag",
                                            .one_draw = 1},
                          e->g.diag)
              : NULL;
    CHECK(p && halo_program_reflection(p).one_draw && halo_program_reflection(p).output_count == 0,
          "one_draw with the slice host links: drawn once over the field, no seed output");
    halo_program_destroy(p);
    free(slice);
    halo_diagnostics_clear(e->g.diag);
    /* host contract 3: the single-pass host links, rays may end, no seed output is left */
    p = halo_link(
        &(halo_link_desc){
            .library = e->g.lib, .scene = scene, .host_source = single_pass, .host_file = "single.frag", .one_draw = 1},
        e->g.diag);
    CHECK(p != NULL && halo_program_reflection(p).one_draw, "with one_draw the single-pass host links");
    CHECK(p && strstr(halo_program_source(p, HALO_PIECE_WHOLE), "#define HALO_RAY_MAY_END 1"),
          "one_draw: early ray termination kept");
    CHECK(p && halo_program_reflection(p).output_count == 0,
          "one_draw: the seeds are libhalo's march's, not the host's outputs");
    /* ... and a frame drawn without the volume the march needs is refused */
    halo_gl_frame *frame = p ? halo_gl_frame_create(e->g.runtime, p, SIZE, SIZE, e->g.diag) : NULL;
    CHECK(frame != NULL, "one_draw: a frame");
    static const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    CHECK(frame &&
              halo_gl_frame_draw(
                  frame, 0, &(halo_gl_segments_desc){.inverse_view_projection = identity, .step = 0.01f, .draw = NULL},
                  e->g.diag) == HALO_ERROR_INPUT,
          "halo_gl_frame_draw refuses a desc without draw");
    halo_diagnostics_clear(e->g.diag);
    CHECK(frame &&
              halo_gl_frame_draw(
                  frame, 0,
                  &(halo_gl_segments_desc){.inverse_view_projection = identity, .step = 0.01f, .draw = draw_nothing},
                  e->g.diag) == HALO_ERROR_INPUT &&
              halo_diagnostics_describe(e->g.diag).count == 1 &&
              strstr(halo_diagnostics_get(e->g.diag, 0)->text, "volume_texture"),
          "one_draw: halo_gl_frame_draw without desc.volume_texture says so");
    halo_gl_frame_destroy(frame);
    halo_program_destroy(p);
    halo_diagnostics_clear(e->g.diag);
    /* issue 26: a draw callback that destroys the frame (a use after free before): the frame
     * goes when the draw returns, with USAGE */
    p = halo_link(
        &(halo_link_desc){.library = e->g.lib, .scene = scene, .host_source = e->raycast, .host_file = "raycast.frag"},
        e->g.diag);
    frame = p ? halo_gl_frame_create(e->g.runtime, p, SIZE, SIZE, e->g.diag) : NULL;
    destroying_frame = frame;
    destroy_calls = 0;
    CHECK(frame &&
              halo_gl_frame_draw(
                  frame, 0,
                  &(halo_gl_segments_desc){.inverse_view_projection = identity, .step = 0.05f, .draw = draw_destroying},
                  e->g.diag) == HALO_ERROR_INPUT &&
              halo_diagnostics_has(e->g.diag, HALO_MSG_USAGE) && destroy_calls > 0,
          "a draw callback that destroys the frame: HALO_ERROR_INPUT with USAGE after %d calls", destroy_calls);
    halo_program_destroy(p);
    halo_diagnostics_clear(e->g.diag);
    halo_scene_destroy(scene);
}

/* 7: a one-draw frame drawn again reuses its field while what the field depends on is the
 * same (gl/field.c: field_key), and every image equals a new frame's: the outlines' too,
 * whose images (the host's outputs, the passes after its draw) start from their clear
 * values in every frame. */
static const char live_scene[] =
    "{\"halo_scene\": 1, \"stages\": ["
    " {\"halo_seed\": {\"alpha\": 2, \"gradient_scale\": 6, \"value_0\": [[0.55, 0], [0.62, 1], [0.8, 1], [0.9, 0]],"
    " \"live\": [\"gradient_scale\"]}},"
    " {\"halo_generate\": {\"passes\": 5, \"delta\": 0.9, \"interval\": 4, \"live\": [\"delta\"]}},"
    " {\"halo_map\": {\"mode\": 0, \"color_near\": [[0, 0, 0]], \"color_far\": [[0, 0, 0]], \"opacity\": 1,"
    " \"full_at\": 0.25, \"live\": [\"opacity\"]}},"
    " {\"outline_feature\": {\"value_min\": 0.3, \"value_max\": 1}},"
    " {\"outlines\": {\"sigma\": 6, \"lambda\": 4, \"live\": [\"lambda\"]}}], " HALO_RENDER "}";

typedef struct reuse_step {
    const char *what;
    const char *stage, *param; /* a parameter set to value before the draw, or NULL */
    double value;
    double azimuth; /* the camera's azimuth (the scene's elevation and zoom) */
    int upload;     /* the volume uploaded again (a new volume_version) */
    int computes;   /* 1: this draw must compute the field; 0: reuse it */
} reuse_step;

/* One raycaster over program p with the settings; the steps' parameters set so far. */
static halo_raycast *reuse_host(env *e, halo_program *p, const halo_render_settings *settings)
{
    const halo_host_desc desc = {.gl = e->g.gl, .runtime = e->g.runtime, .program = p, .width = SIZE, .height = SIZE};
    halo_raycast *r = halo_raycast_create(&desc, e->g.diag);
    if (r && (halo_raycast_set_volume(r, e->g.volume, VOLUME, VOLUME, VOLUME, e->g.diag) != HALO_OK ||
              halo_raycast_set_render(r, settings, e->g.diag) != HALO_OK)) {
        halo_raycast_destroy(r);
        r = NULL;
    }
    return r;
}

static void test_field_reuse(env *e)
{
    static const reuse_step steps[] = {
        {"the first draw", NULL, NULL, 0, 35, 0, 1},
        {"drawn again", NULL, NULL, 0, 35, 0, 0},
        {"halo_map.opacity 0.4 (the host's draw reads it)", "halo_map", "opacity", 0.4, 35, 0, 0},
        {"outlines.lambda 1 (the passes after the host's draw read it)", "outlines", "lambda", 1, 35, 0, 0},
        {"halo_seed.gradient_scale 3 (the march)", "halo_seed", "gradient_scale", 3, 35, 0, 1},
        {"halo_generate.delta 0.8 (the passes)", "halo_generate", "delta", 0.8, 35, 0, 1},
        {"drawn again", NULL, NULL, 0, 35, 0, 0},
        {"another camera", NULL, NULL, 0, 50, 0, 1},
        {"the volume uploaded again", NULL, NULL, 0, 50, 1, 1},
    };
    one_draw = 1;
    halo_scene *scene = NULL, *fresh_scene = NULL;
    halo_program *p = link_scene(e, live_scene, e->raycast, "raycast.frag", 0, &scene);
    halo_program *q = link_scene(e, live_scene, e->raycast, "raycast.frag", 0, &fresh_scene);
    one_draw = 0;
    const halo_render_settings *settings = p ? halo_scene_describe(scene).render : NULL;
    halo_raycast *r = settings && q ? reuse_host(e, p, settings) : NULL;
    float *kept = malloc((size_t)SIZE * SIZE * 4 * sizeof *kept),
          *fresh = malloc((size_t)SIZE * SIZE * 4 * sizeof *fresh);
    CHECK(r && kept && fresh, "field reuse: the renderer");
    int expected = 0;
    float *previous = NULL;
    for (size_t k = 0; r && kept && fresh && k < sizeof steps / sizeof *steps; ++k) {
        const reuse_step *st = &steps[k];
        if (st->stage) {
            CHECK(halo_program_set(p, st->stage, st->param, &st->value, 1, e->g.diag) == HALO_OK &&
                      halo_program_set(q, st->stage, st->param, &st->value, 1, e->g.diag) == HALO_OK,
                  "field reuse: set %s.%s", st->stage, st->param);
        }
        if (st->upload)
            halo_raycast_set_volume(r, e->g.volume, VOLUME, VOLUME, VOLUME, e->g.diag);
        halo_raycast_set_camera(r, st->azimuth, settings->elevation, settings->zoom);
        int ok = halo_raycast_render(r, kept, e->g.diag) == HALO_OK;
        expected += st->computes;
        int computed = halo_gl_field_computed(halo_raycast_frame(r));
        /* the same image from a new frame, which computes its field */
        halo_raycast *other = reuse_host(e, q, settings);
        if (other)
            halo_raycast_set_camera(other, st->azimuth, settings->elevation, settings->zoom);
        ok = ok && other && halo_raycast_render(other, fresh, e->g.diag) == HALO_OK;
        halo_raycast_destroy(other);
        if (!ok) {
            halo_diagnostics_print(e->g.diag, stdout);
            CHECK(0, "field reuse, %s: the renders", st->what);
            break;
        }
        double max_abs, rmse, changed = 1.0;
        difference(kept, fresh, &max_abs, &rmse);
        if (previous)
            difference(kept, previous, &changed, &rmse);
        printf(
            "field reuse, %s: fields computed %d (expected %d); against a new frame max abs %.3g; against the "
            "previous image max abs %.3g\n",
            st->what, computed, expected, max_abs, changed);
        CHECK(computed == expected, "field reuse, %s: %d fields computed, not %d", st->what, computed, expected);
        CHECK(max_abs == 0.0, "field reuse, %s: %.3g from a new frame's image", st->what, max_abs);
        CHECK(!st->stage || changed > 1e-3, "field reuse, %s: the image did not change (%.3g)", st->what, changed);
        if (!previous)
            previous = malloc((size_t)SIZE * SIZE * 4 * sizeof *previous);
        if (previous)
            memcpy(previous, kept, (size_t)SIZE * SIZE * 4 * sizeof *previous);
    }
    halo_diagnostics_clear(e->g.diag);
    free(previous);
    free(kept);
    free(fresh);
    halo_raycast_destroy(r);
    halo_program_destroy(p);
    halo_program_destroy(q);
    halo_scene_destroy(scene);
    halo_scene_destroy(fresh_scene);
}

int main(void)
{
    env e = {0};
    int status = gl_fixture_open(&e.g, SIZE, VOLUME);
    if (status)
        return status;
    e.raycast = halo_host_load("raycast.frag", NULL, e.g.diag);
    e.slab = halo_host_load("slab.frag", NULL, e.g.diag);
    if (!e.raycast || !e.slab) {
        halo_diagnostics_print(e.g.diag, stderr);
        return 99;
    }
    test_segments_change_nothing(&e);
    test_halos_match_slab(&e);
    test_diagnostics(&e);
    test_hostile_state(&e);
    test_one_draw_matches(&e, halos_scene, "emissive");
    test_one_draw_matches(&e, occlusive_scene, "occlusive");
    test_one_draw_matches(&e, directional_scene, "directional");
    test_pieces(&e);
    image_scale = 2;
    test_one_draw_matches(&e, halos_scene, "1/2 scale");
    image_scale = 0;
    test_field_memory(&e);
    test_field_reuse(&e);
    orthographic = 1;
    test_segments_change_nothing(&e);
    test_one_draw_matches(&e, halos_scene, "orthographic");
    printf("%d failed\n", failures);
    free(e.raycast);
    free(e.slab);
    gl_fixture_close(&e.g);
    return failures ? 1 : 0;
}
