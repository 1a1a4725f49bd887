/* Conformance of the slice host and the slab ray caster: the GPU render of a small
 * scene with one emissive and one occlusive halo against a double-precision emulation
 * of the same renderer (same slice planes, halo_emu_apply with the frame per fragment,
 * halo_emu_frame_generate every M slices, the same compositing). */
#include "conform_slice.h"

#include "halo.h"
#include "halo_gl_loader.h"
#include "hosts/slab.h"
#include "hosts/slice.h"
#include "volume.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- Tolerance ---------------------------------------------------------------------------
 *
 * The GPU works in float32 where the emulation works in double on the same uploaded
 * floats: texel coordinates and trilinear weights (~1e-7 relative, llvmpipe), the seed
 * |grad f|^alpha (1 - |n.V|)^beta with alpha = 32 amplifying the gradient's relative
 * error 32-fold, the image passes (the spreading's sums over 3x3 taps, 4 passes), the
 * opacity correction's pow and the front-to-back blending of ~110 slices into a
 * float32 colour buffer. The raycast row (conform_render.c) measured 1e-5 for the volume
 * part alone at 64x64; the halo images add the seed's amplification. Measured on
 * llvmpipe (LLVM 15), 32^3 volume: at 64x64 largest errors 2.4e-6 (slice, slab@M4),
 * 2.8e-6 (slab, M = 1), 3.1e-6 (plain); at 128x128 2.7e-6, 4.6e-5 (slab: 110
 * generations, each a chance for a seed near a blend or clamp decision), 3.2e-6. The
 * tolerances leave a margin of about 10 over the largest of them: 5e-4 with halos,
 * 1e-4 without (more pixels, more extremes at larger sizes): the registry's rows
 * (conform_rows.c). */

static const char slice_scene_halos[] =
    "{\"halo_scene\": 1, \"stages\": ["
    " {\"halo_seed\": {\"alpha\": [1, 2], \"beta\": 0.125, \"gradient_scale\": 4}},"
    " {\"halo_generate\": {\"passes\": 3, \"delta\": [0.8, 0.9], \"interval\": 4}},"
    " {\"halo_map\": {\"mode\": [0, 1], \"color_near\": [[1, 0.9, 0.4], [0, 0, 0]],"
    "   \"color_far\": [[1, 0.3, 0.1], [0, 0, 0]], \"opacity\": [0.8, 0.7]}}],"
    " \"render\": {\"azimuth\": 30, \"elevation\": 20, \"zoom\": 1.3, \"step\": 0.5,"
    "  \"background\": [0.05, 0.08, 0.25],"
    "  \"transfer\": [[0, 0, 0, 0, 0], [0.2, 0.6, 0.8, 1, 0], [0.3, 0.6, 0.8, 1, 0.08],"
    "                [0.5, 1, 0.85, 0.55, 0.3], [0.75, 0.95, 0.3, 0.2, 0.7], [1, 1, 1, 0.8, 0.9]]}}";

static const char slice_scene_plain[] =
    "{\"halo_scene\": 1, \"stages\": [],"
    " \"render\": {\"azimuth\": 30, \"elevation\": 20, \"zoom\": 1.3, \"step\": 0.5,"
    "  \"background\": [0.05, 0.08, 0.25],"
    "  \"transfer\": [[0, 0, 0, 0, 0], [0.2, 0.6, 0.8, 1, 0], [0.3, 0.6, 0.8, 1, 0.08],"
    "                [0.5, 1, 0.85, 0.55, 0.3], [0.75, 0.95, 0.3, 0.2, 0.7], [1, 1, 1, 0.8, 0.9]]}}";

/* Per pixel: the ray (origin, unit direction) of slice.frag / slab.frag. */
typedef struct pixel_ray {
    double origin[3], direction[3], cosine, origin_distance;
} pixel_ray;

/* The slice renderer in double: slices k = 0..count-1 outer, pixels inner, a generation
 * after every interval-th slice. The slab caster samples the same planes with the same
 * images (its seeds accumulate over a slab as the slices' do between generations), so
 * one emulation serves both. out: width*height*4, over the background. */
int halo_conform_slice_emulate(const halo_slice_state *s, const halo_program *p, int interval, double *out,
                               halo_diagnostics *diag);
/* conform_ray_init: the ray of pixel (x, y), with its cosine to and distance along the view axis. */
static void init_pixel_ray(void *context, int x, int y, void *ray)
{
    const halo_slice_state *s = context;
    pixel_ray *r = ray;
    conform_pixel_ray(s->inverse_view_projection, s->width, s->height, x, y, r->origin, r->direction);
    r->cosine = r->origin_distance = 0.0;
    for (int k = 0; k < 3; ++k) {
        r->cosine += r->direction[k] * s->view_axis[k];
        r->origin_distance += (r->origin[k] - s->eye[k]) * s->view_axis[k];
    }
}

int halo_conform_slice_emulate(const halo_slice_state *s, const halo_program *p, int interval, double *out,
                               halo_diagnostics *diag)
{
    size_t pixels = (size_t)s->width * (size_t)s->height;
    halo_emu_frame *frame = NULL;
    pixel_ray *rays = conform_host_frame_rays(p, s->width, s->height, s->screen_right, s->screen_up, sizeof *rays,
                                              init_pixel_ray, (void *)s, &frame, diag);
    if (!rays)
        return 0;
    for (size_t i = 0; i < pixels * 4; ++i)
        out[i] = 0.0;
    const double radius = 0.8660254037844386;
    double centre_distance = sqrt((s->eye[0] - 0.5) * (s->eye[0] - 0.5) + (s->eye[1] - 0.5) * (s->eye[1] - 0.5) +
                                  (s->eye[2] - 0.5) * (s->eye[2] - 0.5));
    double front_distance = centre_distance - radius;
    float *gradients = halo_volume_gradients(s->volume, s->dims);
    int ok = gradients != NULL;
    if (!ok)
        HALO_REPORT_ERROR(diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "out of memory");
    for (int k = 0; k < s->slice_count && ok; ++k) {
        double plane = s->first_distance + k * s->step_size;
        for (size_t i = 0; i < pixels && ok; ++i) {
            const pixel_ray *r = &rays[i];
            double t = (plane - r->origin_distance) / r->cosine;
            double P[3];
            int inside = 1;
            for (int c = 0; c < 3; ++c) {
                P[c] = r->origin[c] + t * r->direction[c];
                inside = inside && P[c] >= 0.0 && P[c] <= 1.0;
            }
            halo_emu_sample sample;
            memset(&sample, 0, sizeof sample);
            memcpy(sample.position, P, sizeof P);
            double color[4] = {0, 0, 0, 0};
            if (inside) {
                sample.value = halo_volume_trilinear(s->volume, s->dims, P);
                conform_transfer_lookup(s->transfer, s->transfer_texels, sample.value, color);
            }
            double distance = 0.0;
            if (inside) /* the host's precomputed voxel gradients (float), trilinear */
                halo_volume_trilinear3(gradients, s->dims, P, sample.gradient);
            for (int c = 0; c < 3; ++c) {
                sample.view[c] = s->eye[c] - P[c];
                distance += sample.view[c] * sample.view[c];
            }
            distance = sqrt(distance);
            for (int c = 0; c < 3; ++c)
                sample.view[c] /= distance;
            double depth = (distance - front_distance) / (2.0 * radius);
            sample.depth = depth < 0.0 ? 0.0 : depth > 1.0 ? 1.0 : depth;
            sample.fragcoord[0] = (double)(i % (size_t)s->width) + 0.5;
            sample.fragcoord[1] = (double)(i / (size_t)s->width) + 0.5;
            memcpy(sample.color, color, 3 * sizeof *color);
            sample.opacity = color[3];
            if (frame) {
                ok = halo_emu_apply(p, frame, &sample, diag) == HALO_OK;
                halo_emu_frame_finish(frame, &sample);
            } else {
                ok = halo_emu_apply(p, NULL, &sample, diag) == HALO_OK;
            }
            double alpha = sample.opacity < 0.0 ? 0.0 : sample.opacity > 1.0 ? 1.0 : sample.opacity;
            if (alpha > 0.0) {
                alpha = 1.0 - pow(1.0 - alpha, s->step_size / (r->cosine * s->unit_step));
                double *acc = &out[i * 4];
                for (int c = 0; c < 3; ++c)
                    acc[c] += (1.0 - acc[3]) * alpha * sample.color[c];
                acc[3] += (1.0 - acc[3]) * alpha;
            }
        }
        if (ok && frame && halo_program_reflection(p).pass_count > 0 && (k + 1) % interval == 0 &&
            k + 1 < s->slice_count)
            ok = halo_emu_frame_generate(frame, diag) == HALO_OK;
    }
    conform_over_background(out, pixels, s->background);
    halo_emu_frame_destroy(frame);
    free(rays);
    free(gradients);
    return ok;
}

/* One row: render with the slice host (slab = 0) or slab caster at interval M (0: the
 * program's), emulate, compare. */
static void run_row(conform *c, const char *row, const char *scene_text, int slab, int interval, int scale,
                    int one_draw, double tolerance, const char *tolerance_text, const char *reason, const float *volume,
                    int volume_size)
{
    halo_scene *scene = halo_scene_load("(conformance slice scene)", scene_text, c->lib, c->diag);
    halo_program *program = NULL, *interleaved = NULL;
    halo_slice *host = NULL;
    float *gpu = NULL;
    double *reference = NULL;
    size_t pixels = (size_t)c->size * (size_t)c->size;
    char *source = NULL;
    int printed = 0; /* the row printed its line; else conform_row_end prints an error row */
    if (!scene)
        goto done;
    source = halo_host_load(slab ? "slab.frag" : "slice.frag", NULL, c->diag);
    if (!source)
        goto done;
    program = halo_link(&(halo_link_desc){.library = c->lib,
                                          .scene = scene,
                                          .host_source = source,
                                          .host_file = slab ? "slab.frag" : "slice.frag",
                                          .target = c->target,
                                          .image_scale = scale,
                                          .one_draw = one_draw},
                        c->diag);
    if (!program)
        goto done;
    halo_host_desc desc = {.gl = c->gl, .runtime = c->runtime, .program = program, .width = c->size, .height = c->size};
    host = slab ? halo_slab_create(&desc, c->diag) : halo_slice_create(&desc, c->diag);
    if (!host)
        goto done;
    halo_slice_set_gradient_format(host, (halo_gradient_format)c->gradient_format);
    const halo_render_settings *settings = halo_scene_describe(scene).render;
    if (halo_slice_set_volume(host, volume, volume_size, volume_size, volume_size, c->diag) != HALO_OK ||
        halo_slice_set_render(host, settings, c->diag) != HALO_OK)
        goto done;
    halo_slice_set_camera(host, settings->azimuth, settings->elevation, settings->zoom);
    halo_slice_set_interval(host, interval);
    gpu = malloc(pixels * 4 * sizeof *gpu);
    reference = malloc(pixels * 4 * sizeof *reference);
    if (!gpu || !reference) {
        HALO_REPORT_ERROR(c->diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "out of memory");
        goto done;
    }
    if (one_draw && !halo_program_reflection(program).one_draw) {
        HALO_REPORT_ERROR(c->diag, HALO_MSG_USAGE, "", 0, 0, "%s: the program was not linked for one draw", row);
        goto done;
    }
    if (halo_slice_render(host, gpu, c->diag) != HALO_OK)
        goto done;
    halo_slice_state state;
    halo_slice_get_state(host, &state);
    if (one_draw && (halo_slice_draws(host) != state.slice_count ||
                     halo_gl_frame_describe(halo_slice_frame(host)).segment_count != 1)) {
        HALO_REPORT_ERROR(c->diag, HALO_MSG_USAGE, "", 0, 0,
                          "%s: not drawn once over the field (%ld slices drawn of %d, %d host draws)", row,
                          halo_slice_draws(host), state.slice_count,
                          halo_gl_frame_describe(halo_slice_frame(host)).segment_count);
        goto done;
    }
    /* one_draw: the program's seeding stages run in libhalo's march, not in its samples; the
     * emulation is the slice host's with the generations between its slices (the same
     * algorithm on the same planes: docs/host-contract.md, "Host contract 3") */
    if (one_draw && !(interleaved = halo_link(&(halo_link_desc){.library = c->lib,
                                                                .scene = scene,
                                                                .host_source = source,
                                                                .host_file = "slice.frag",
                                                                .target = c->target,
                                                                .image_scale = scale},
                                              c->diag)))
        goto done;
    if (!halo_conform_slice_emulate(&state, one_draw ? interleaved : program, state.interval, reference, c->diag))
        goto done;
    row_stats stats = {0};
    for (size_t i = 0; i < pixels; ++i) {
        const double g[4] = {gpu[i * 4], gpu[i * 4 + 1], gpu[i * 4 + 2], gpu[i * 4 + 3]};
        row_stats_add(&stats, i, g, &reference[i * 4], NULL, 4, tolerance, 0.0);
    }
    int pass = stats.over == 0 && stats.nonfinite == 0;
    print_row(c, row, &stats, tolerance_text, pass);
    if (c->verbose || !pass) {
        size_t w = stats.worst;
        fprintf(stderr,
                "  %s: %d slices, M = %d, %ld draws, %ld pass draws; largest error at pixel (%zu, %zu): gpu "
                "(%.9g %.9g %.9g) emulation (%.9g %.9g %.9g)\n  tolerance: %s\n",
                row, state.slice_count, state.interval, halo_slice_draws(host), halo_slice_pass_draws(host),
                w % (size_t)c->size, w / (size_t)c->size, gpu[w * 4], gpu[w * 4 + 1], gpu[w * 4 + 2], reference[w * 4],
                reference[w * 4 + 1], reference[w * 4 + 2], reason);
    }
    printed = 1;
done:
    halo_slice_destroy(host);
    halo_program_destroy(interleaved);
    free(gpu);
    free(reference);
    free(source);
    conform_row_end(c, row, printed, program, scene);
}

void conform_slice_row(conform *c, const conform_row *row)
{
    /* --stage slice or slab (or any slice@, slab@ row) selects the family */
    if (c->only && strncmp(c->only, "slice", 5) && strncmp(c->only, "slab", 4))
        return;
    if (conform_skip_on_es(c, row->name, "the slice and slab hosts are written for desktop OpenGL"))
        return;
    const conform_slice_params *params = row->params;
    const int volume_size = 32;
    float *volume = halo_volume_create(volume_size);
    if (!volume) {
        HALO_REPORT_ERROR(c->diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "out of memory");
        print_error_row(c, row->name);
        return;
    }
    char tolerance_text[32];
    conform_tolerance_text(row, tolerance_text, sizeof tolerance_text);
    run_row(c, row->name, params->halos ? slice_scene_halos : slice_scene_plain, params->slab, params->interval,
            params->scale, params->one_draw, row->tolerance_abs, tolerance_text, row->why, volume, volume_size);
    free(volume);
}
