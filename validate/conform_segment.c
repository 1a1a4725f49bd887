/* Conformance of segmented ray casting (host contract 2): raycast.frag drawn by
 * halo_gl_frame_draw in depth segments, against a double-precision emulation of the same
 * renderer: the same rays, samples and compositing as the one-draw emulation of the
 * raycast row, the samples of each segment chosen by the same plan as the runtime's
 * (halo_segment_plan_make), halo_emu_apply_frame per sample, the fragment's outputs
 * finished once per segment, halo_emu_frame_generate between segments. */
#include "conform_segment.h"

#include "internal.h"
#include "diag.h"
#include "volume.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* One pixel's ray in raycast.frag: origin, unit direction, the box's entry and exit, and
 * the segment index bounds as the shader computes them (in float). */
typedef struct segment_ray {
    double origin[3], direction[3], t_enter, t_exit;
    float phi0, dphi;
    int ended;
} segment_ray;

static void make_ray(const halo_raycast_state *s, const halo_segment_plan *plan, int x, int y, segment_ray *r)
{
    conform_pixel_ray(s->inverse_view_projection, s->width, s->height, x, y, r->origin, r->direction);
    r->t_enter = 0.0;
    r->t_exit = INFINITY;
    for (int k = 0; k < 3; ++k) {
        double inverse = 1.0 / r->direction[k];
        double a = (0.0 - r->origin[k]) * inverse, b = (1.0 - r->origin[k]) * inverse;
        r->t_enter = fmax(r->t_enter, fmin(a, b));
        r->t_exit = fmin(r->t_exit, fmax(a, b));
    }
    /* halo_segment_begin, in float as the shader */
    float phi0 = (float)plan->plane[3], dphi = 0.0f;
    for (int k = 0; k < 3; ++k) {
        phi0 += (float)plan->plane[k] * (float)(r->origin[k] + r->t_enter * r->direction[k]);
        dphi += (float)plan->plane[k] * (float)r->direction[k];
    }
    r->phi0 = phi0;
    r->dphi = dphi * (float)s->step_size;
    r->ended = 0;
}

/* The shader's halo_segment_index: the first sample at or behind the plane phi = bound. */
static int segment_index(float bound, const segment_ray *r, int end)
{
    float k = ceilf((bound - r->phi0) / r->dphi);
    return k > (float)end ? end : k > 0.0f ? (int)k : 0;
}

static int post_passes(halo_emu_frame *frame, const halo_image_info *post, size_t pixels, double *out,
                       halo_diagnostics *diag)
{
    double *host = halo_emu_frame_image(frame, "host_color");
    if (!host)
        return 0;
    memcpy(host, out, pixels * 4 * sizeof *out);
    if (halo_emu_frame_post(frame, diag) != HALO_OK)
        return 0;
    const double *image = halo_emu_frame_image(frame, post->name);
    int channels = post->channels;
    for (size_t k = 0; image && k < pixels; ++k) {
        const double *px = &image[k * (size_t)channels];
        double grey = 0.0;
        for (int c = 0; c < channels; ++c)
            grey = px[c] > grey ? px[c] : grey;
        for (int c = 0; c < 3; ++c)
            out[k * 4 + (size_t)c] = channels >= 3 ? px[c] : grey;
        out[k * 4 + 3] = 1.0;
    }
    return image != NULL;
}

int halo_conform_segment_emulate(const halo_raycast_state *s, const halo_program *p, const halo_segment_plan *plan,
                                 double threshold, double exit_move, double *out, halo_diagnostics *diag)
{
    enum { MAX_STEPS = 4096 };
    const double radius = 0.8660254037844386;
    size_t pixels = (size_t)s->width * (size_t)s->height;
    segment_ray *rays = malloc(pixels * sizeof *rays);
    halo_emu_frame *frame = NULL;
    if (!rays) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return 0;
    }
    int framed = 1;
    frame = conform_host_frame(p, s->width, s->height, s->screen_right, s->screen_up, &framed, diag);
    if (!framed) {
        free(rays);
        return 0;
    }
    for (int y = 0; y < s->height; ++y)
        for (int x = 0; x < s->width; ++x)
            make_ray(s, plan, x, y, &rays[(size_t)y * (size_t)s->width + (size_t)x]);
    for (size_t i = 0; i < pixels * 4; ++i)
        out[i] = 0.0;
    double centre_distance = sqrt((s->eye[0] - 0.5) * (s->eye[0] - 0.5) + (s->eye[1] - 0.5) * (s->eye[1] - 0.5) +
                                  (s->eye[2] - 0.5) * (s->eye[2] - 0.5));
    double front_distance = centre_distance - radius;
    double exponent = s->step_size / s->unit_step;
    double voxel[3] = {1.0 / s->dims[0], 1.0 / s->dims[1], 1.0 / s->dims[2]};
    if (halo_program_output_count(p) > 0) /* HALO_RAY_MAY_END 0: the ray goes on to its end */
        threshold = INFINITY;
    int ok = 1, generation = 0;
    for (size_t i = 0; i < halo_program_pass_count(p); ++i)
        generation |= halo_program_pass(p, i)->post == 0;
    for (int j = 0; j < plan->segments && ok; ++j) {
        int head = j == 0, tail = j == plan->segments - 1;
        float low_bound = (float)(plan->start + j * plan->length), high_bound =
                                                                       (float)(plan->start + (j + 1) * plan->length);
        for (size_t i = 0; i < pixels && ok; ++i) {
            segment_ray *r = &rays[i];
            int first = 0, end = MAX_STEPS;
            if (r->dphi > 0.0f) {
                if (!head)
                    first = segment_index(low_bound, r, MAX_STEPS);
                if (!tail)
                    end = segment_index(high_bound, r, MAX_STEPS);
            } else if (!head) {
                first = MAX_STEPS;
            }
            if (r->ended)
                first = MAX_STEPS;
            if (end < first)
                end = first;
            double *acc = &out[i * 4];
            halo_emu_sample fragment; /* the outputs' accumulators of this fragment */
            memset(&fragment, 0, sizeof fragment);
            fragment.fragcoord[0] = (double)(i % (size_t)s->width) + 0.5;
            fragment.fragcoord[1] = (double)(i / (size_t)s->width) + 0.5;
            int k = first;
            for (; k < end && ok; ++k) {
                double t = r->t_enter + k * s->step_size;
                if (t > r->t_exit + exit_move)
                    break;
                halo_emu_sample sample;
                memset(&sample, 0, sizeof sample);
                double *P = sample.position;
                for (int c = 0; c < 3; ++c)
                    P[c] = r->origin[c] + t * r->direction[c];
                sample.value = halo_volume_trilinear(s->volume, s->dims, P);
                double color[4];
                conform_transfer_lookup(s->transfer, s->transfer_texels, sample.value, color);
                double distance = 0.0;
                for (int c = 0; c < 3; ++c) {
                    double plus[3] = {P[0], P[1], P[2]}, minus[3] = {P[0], P[1], P[2]};
                    plus[c] += voxel[c];
                    minus[c] -= voxel[c];
                    sample.gradient[c] = (halo_volume_trilinear(s->volume, s->dims, plus) -
                                          halo_volume_trilinear(s->volume, s->dims, minus)) * 0.5;
                    sample.view[c] = s->eye[c] - P[c];
                    distance += sample.view[c] * sample.view[c];
                }
                distance = sqrt(distance);
                for (int c = 0; c < 3; ++c)
                    sample.view[c] /= distance;
                double depth = (distance - front_distance) / (2.0 * radius);
                sample.depth = depth < 0.0 ? 0.0 : depth > 1.0 ? 1.0 : depth;
                memcpy(sample.fragcoord, fragment.fragcoord, sizeof sample.fragcoord);
                memcpy(sample.color, color, 3 * sizeof *color);
                sample.opacity = color[3];
                memcpy(sample.output_accum, fragment.output_accum, sizeof sample.output_accum);
                memcpy(sample.output_accum_next, fragment.output_accum_next, sizeof sample.output_accum_next);
                ok = (frame ? halo_emu_apply_frame(p, frame, &sample, diag) : halo_emu_apply(p, &sample, diag)) ==
                     HALO_OK;
                memcpy(fragment.output_accum, sample.output_accum, sizeof sample.output_accum);
                memcpy(fragment.output_accum_next, sample.output_accum_next, sizeof sample.output_accum_next);
                double alpha = sample.opacity < 0.0 ? 0.0 : sample.opacity > 1.0 ? 1.0 : sample.opacity;
                if (alpha > 0.0) {
                    alpha = 1.0 - pow(1.0 - alpha, exponent);
                    for (int c = 0; c < 3; ++c)
                        acc[c] += (1.0 - acc[3]) * alpha * sample.color[c];
                    acc[3] += (1.0 - acc[3]) * alpha;
                    if (acc[3] >= threshold)
                        break;
                }
            }
            if (k < end)
                r->ended = 1;
            if (frame)
                halo_emu_frame_finish(frame, &fragment);
        }
        if (ok && frame && !tail && generation)
            ok = halo_emu_frame_generate(frame, diag) == HALO_OK;
    }
    for (size_t i = 0; i < pixels; ++i) {
        double *px = &out[i * 4];
        for (int c = 0; c < 3; ++c)
            px[c] += (1.0 - px[3]) * s->background[c];
        px[3] = 1.0;
    }
    const halo_image_info *post = halo_host_post_image(p);
    if (ok && frame && post) /* the host's colour through the at=post passes, as halo_host_post_passes */
        ok = post_passes(frame, post, pixels, out, diag);
    halo_emu_frame_destroy(frame);
    free(rays);
    return ok;
}

/* ---- The rows (conform_rows.c) ------------------------------------------------------------ */

/* Renders the ray caster as the program needs (segments 0) or in exactly `segments`; fills
 * state (its transfer table copied into transfer: the host is gone on return) and plan.
 * NULL with diagnostics on failure. */
static float *render(conform *c, const halo_program *p, const halo_render_settings *settings, const float *volume,
                     int volume_size, int orthographic, int segments, halo_raycast_state *state,
                     float transfer[HALO_RAYCAST_TRANSFER_TEXELS * 4], halo_segment_plan *plan)
{
    size_t values = (size_t)c->size * (size_t)c->size * 4;
    float *gpu = malloc(values * sizeof *gpu);
    halo_raycast *r = halo_raycast_create(&(halo_host_desc){.gl = c->gl, .runtime = c->runtime, .program = p,
                                                            .width = c->size, .height = c->size},
                                          c->diag);
    int ok = gpu && r && halo_raycast_set_volume(r, volume, volume_size, volume_size, volume_size, c->diag) == HALO_OK &&
             halo_raycast_set_render(r, settings, c->diag) == HALO_OK;
    if (ok) {
        halo_raycast_set_orthographic(r, orthographic);
        halo_raycast_set_camera(r, settings->azimuth, settings->elevation, settings->zoom);
        halo_raycast_set_segments(r, 0, segments > 0 ? segments : 0);
        ok = halo_raycast_render(r, gpu, c->diag) == HALO_OK;
        halo_raycast_get_state(r, state);
        memcpy(transfer, state->transfer, sizeof(float) * HALO_RAYCAST_TRANSFER_TEXELS * 4);
        state->transfer = transfer;
        float inverse[16];
        for (int i = 0; i < 16; ++i)
            inverse[i] = (float)state->inverse_view_projection[i];
        halo_gl_segments_desc desc = {.inverse_view_projection = inverse, .step = (float)state->step_size,
                                      .segments = segments > 0 ? segments : 0};
        ok = ok && halo_segment_plan_make(&desc, p, plan, c->diag);
    }
    halo_raycast_destroy(r);
    if (!ok) {
        free(gpu);
        return NULL;
    }
    return gpu;
}

static halo_program *link_host(conform *c, const halo_scene *scene, int force)
{
    return halo_link(&(halo_link_desc){.library = c->lib, .scene = scene, .host_source = c->raycast_source,
                                       .host_file = "raycast.frag", .target = HALO_TARGET_GLSL330,
                                       .force_segments = force},
                     c->diag);
}

void conform_segment_row(conform *c, const conform_row *row)
{
    if (!row_selected(c, row->name, "segments"))
        return;
    const conform_segment_params *params = row->params;
    const int volume_size = 32;
    size_t values = (size_t)c->size * (size_t)c->size * 4;
    float *volume = halo_volume_create(volume_size), *gpu = NULL, *single = NULL;
    double *reference = NULL, *allowed = NULL, *moved = NULL;
    halo_program *program = NULL, *plain = NULL;
    halo_scene *scene = volume ? halo_scene_parse(params->scene, "(conformance segment scene)", c->lib, c->diag) : NULL;
    halo_raycast_state state;
    halo_segment_plan plan;
    float transfer[HALO_RAYCAST_TRANSFER_TEXELS * 4];
    int ok = scene && (program = link_host(c, scene, params->segments > 0)) != NULL;
    const halo_render_settings *settings = ok ? halo_scene_render(scene) : NULL;
    ok = ok && (gpu = render(c, program, settings, volume, volume_size, params->orthographic, params->segments,
                             &state, transfer, &plan)) != NULL;
    row_stats stats = {0};
    if (ok && params->segments > 0) {
        /* the same host in one draw: the segments alone must change nothing */
        halo_segment_plan once;
        ok = (plain = link_host(c, scene, 0)) != NULL &&
             (single = render(c, plain, settings, volume, volume_size, params->orthographic, 0, &state, transfer,
                              &once)) != NULL;
        for (size_t i = 0; ok && i < values / 4; ++i) {
            const double g[4] = {gpu[i * 4], gpu[i * 4 + 1], gpu[i * 4 + 2], gpu[i * 4 + 3]};
            const double s[4] = {single[i * 4], single[i * 4 + 1], single[i * 4 + 2], single[i * 4 + 3]};
            row_stats_add(&stats, i, g, s, NULL, 4, row->tolerance_abs, 0.0);
        }
    } else if (ok) {
        /* against the emulation; the decisions on the opacity threshold and the ray's exit bracketed */
        static const double moves[][2] = {{-1e-5, 0.0}, {1e-5, 0.0}, {0.0, -1e-5}, {0.0, 1e-5}};
        reference = malloc(values * sizeof *reference);
        moved = malloc(values * sizeof *moved);
        allowed = calloc(values, sizeof *allowed);
        state.volume = volume;
        ok = reference && moved && allowed &&
             halo_conform_segment_emulate(&state, program, &plan, 0.99, 0.0, reference, c->diag);
        for (size_t m = 0; ok && m < sizeof moves / sizeof moves[0]; ++m) {
            ok = halo_conform_segment_emulate(&state, program, &plan, 0.99 + moves[m][0], moves[m][1], moved, c->diag);
            for (size_t i = 0; ok && i < values; ++i)
                allowed[i] = fmax(allowed[i], fabs(moved[i] - reference[i]));
        }
        for (size_t i = 0; ok && i < values / 4; ++i) {
            const double g[4] = {gpu[i * 4], gpu[i * 4 + 1], gpu[i * 4 + 2], gpu[i * 4 + 3]};
            row_stats_add(&stats, i, g, &reference[i * 4], &allowed[i * 4], 4, row->tolerance_abs, 0.0);
        }
    }
    if (ok) {
        char tolerance_text[32];
        conform_tolerance_text(row, tolerance_text, sizeof tolerance_text);
        int pass = stats.over == 0 && stats.nonfinite == 0;
        print_row(c, row->name, &stats, tolerance_text, pass);
        if (c->verbose || !pass)
            fprintf(stderr, "  %s: %d segments; largest error at pixel (%zu, %zu); tolerance: %s\n", row->name,
                    plan.segments, stats.worst % (size_t)c->size, stats.worst / (size_t)c->size, row->why);
    } else {
        print_error_row(c, row->name);
    }
    halo_diagnostics_clear(c->diag);
    halo_program_destroy(program);
    halo_program_destroy(plain);
    halo_scene_destroy(scene);
    free(volume);
    free(gpu);
    free(single);
    free(reference);
    free(allowed);
    free(moved);
}
