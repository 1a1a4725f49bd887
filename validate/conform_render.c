/* The whole-render family: the example ray caster (examples/hosts/raycast.frag) linked
 * with no stage against the unlinked one, bit for bit; and a small whole render with
 * several stages against a C emulation of the ray caster (emulate_pixel). */
#include "conform_render.h"

#include "halo.h"
#include "render_driver.h"
#include "volume.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The ray cast row's tolerance (its number and reason: conform_rows.c) covers float32
 * texel coordinates and weights. Decisions on a threshold (the 0.99 early termination,
 * the last step before the exit point) are bracketed: the emulation is also run with
 * each threshold moved by 1e-5 and the spread is allowed. */
#define RAYCAST_THRESHOLD_MOVE 1e-5

/* Renders the built-in volume with the ray caster (the render driver): linked program, or raw text. */
static float *render_raycast(conform *c, const halo_program *program, const char *raw_source, const halo_scene *scene,
                             const float *volume, int volume_size, halo_raycast_state *state_out, float *transfer_out)
{
    halo_driver r;
    if (!halo_driver_create(&r, HALO_DRIVER_RAYCAST,
                            &(halo_host_desc){.gl = c->gl,
                                              .runtime = c->runtime,
                                              .program = program,
                                              .fragment_source = program ? NULL : raw_source,
                                              .fragment_file = "raycast.frag",
                                              .width = c->size,
                                              .height = c->size},
                            c->diag)) {
        halo_driver_destroy(&r);
        return NULL;
    }
    float *image = malloc((size_t)c->size * (size_t)c->size * 4 * sizeof *image);
    const halo_render_settings *settings = halo_scene_describe(scene).render;
    const int dims[3] = {volume_size, volume_size, volume_size};
    if (!image || halo_driver_set_volume(&r, volume, dims, settings, 0, c->diag) != HALO_OK) {
        if (!image)
            HALO_REPORT_ERROR(c->diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "out of memory");
        free(image);
        halo_driver_destroy(&r);
        return NULL;
    }
    halo_driver_set_camera(&r, settings->azimuth, settings->elevation, settings->zoom);
    if (halo_driver_render(&r, image, c->diag) != HALO_OK) {
        free(image);
        image = NULL;
    }
    if (state_out) {
        /* the state points into the ray caster: keep a copy of its transfer table */
        halo_raycast_get_state(r.raycast, state_out);
        memcpy(transfer_out, state_out->transfer, HALO_RAYCAST_TRANSFER_TEXELS * 4 * sizeof *transfer_out);
        state_out->transfer = transfer_out;
    }
    halo_driver_destroy(&r);
    return image;
}

/* What both rows render: the built-in volume of side RAYCAST_VOLUME_SIZE and the row's
 * scene linked into the example ray caster. */
#define RAYCAST_VOLUME_SIZE 32
typedef struct raycast_input {
    halo_scene *scene;
    halo_program *program;
    float *volume;
} raycast_input;

/* Takes the scene over (NULL: its failure is reported already), makes the volume and
 * links the program. Returns 0 on failure; raycast_input_close either way. */
static int raycast_input_open(conform *c, halo_scene *scene, raycast_input *in)
{
    *in = (raycast_input){.scene = scene, .volume = halo_volume_create(RAYCAST_VOLUME_SIZE)};
    if (!in->volume)
        HALO_REPORT_ERROR(c->diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "out of memory");
    if (!in->scene || !in->volume)
        return 0;
    in->program = halo_link(&(halo_link_desc){.library = c->lib,
                                              .scene = scene,
                                              .host_source = c->raycast_source,
                                              .host_file = "raycast.frag",
                                              .target = c->target},
                            c->diag);
    return in->program != NULL;
}

/* Frees the input and ends the row (conform_row_end). */
static void raycast_input_close(conform *c, const conform_row *row, raycast_input *in, int printed)
{
    free(in->volume);
    conform_row_end(c, row->name, printed, in->program, in->scene);
}

void conform_empty_row(conform *c, const conform_row *row)
{
    if (!row_selected(c, row->name, NULL))
        return;
    if (conform_skip_on_es(c, row->name, "it compares with the unlinked host, which is GLSL 330"))
        return;
    raycast_input in;
    float *raw = NULL, *linked = NULL;
    int printed = 0;
    if (raycast_input_open(c, halo_scene_create(c->lib), &in)) {
        raw = render_raycast(c, NULL, c->raycast_source, in.scene, in.volume, RAYCAST_VOLUME_SIZE, NULL, NULL);
        linked = raw ? render_raycast(c, in.program, NULL, in.scene, in.volume, RAYCAST_VOLUME_SIZE, NULL, NULL) : NULL;
    }
    if (raw && linked) {
        size_t pixels = (size_t)c->size * (size_t)c->size;
        row_stats stats = {0};
        for (size_t i = 0; i < pixels; ++i) {
            int differs = memcmp(&raw[i * 4], &linked[i * 4], 4 * sizeof(float)) != 0, nonfinite = 0;
            for (int k = 0; k < 4; ++k) {
                double a = raw[i * 4 + (size_t)k], b = linked[i * 4 + (size_t)k];
                if (!isfinite(a) || !isfinite(b)) {
                    nonfinite = 1;
                    continue;
                }
                row_stats_note(&stats, i, fabs(a - b));
            }
            stats.over += (size_t)differs;
            stats.nonfinite += (size_t)nonfinite;
        }
        char tolerance_text[32];
        conform_tolerance_text(row, tolerance_text, sizeof tolerance_text);
        print_row(c, row->name, &stats, tolerance_text, stats.over == 0 && stats.nonfinite == 0);
        printed = 1;
    }
    raycast_input_close(c, row, &in, printed);
    free(raw);
    free(linked);
}

/* One pixel of raycast.frag, in double, with halo_emu_apply per sample. The two
 * thresholds are parameters so that the decisions on them can be bracketed. */
static int emulate_pixel(const halo_raycast_state *s, const halo_program *p, int x, int y, double threshold,
                         double exit_move, double out[4])
{
    double ndc[2] = {(x + 0.5) / s->width * 2.0 - 1.0, (y + 0.5) / s->height * 2.0 - 1.0};
    double near_point[4], far_point[4];
    conform_transform(s->inverse_view_projection, (const double[]){ndc[0], ndc[1], -1.0, 1.0}, near_point);
    conform_transform(s->inverse_view_projection, (const double[]){ndc[0], ndc[1], 1.0, 1.0}, far_point);
    double origin[3], direction[3];
    for (int k = 0; k < 3; ++k) {
        origin[k] = near_point[k] / near_point[3];
        direction[k] = far_point[k] / far_point[3] - origin[k];
    }
    conform_normalize3(direction);
    double t_enter = 0.0, t_exit = INFINITY;
    for (int k = 0; k < 3; ++k) {
        double inverse = 1.0 / direction[k];
        double a = (0.0 - origin[k]) * inverse, b = (1.0 - origin[k]) * inverse;
        t_enter = fmax(t_enter, fmin(a, b));
        t_exit = fmin(t_exit, fmax(a, b));
    }
    t_exit += exit_move;
    const double radius = 0.8660254037844386;
    double centre_distance = sqrt((s->eye[0] - 0.5) * (s->eye[0] - 0.5) + (s->eye[1] - 0.5) * (s->eye[1] - 0.5) +
                                  (s->eye[2] - 0.5) * (s->eye[2] - 0.5));
    double front_distance = centre_distance - radius;
    double exponent = s->step_size / s->unit_step;
    double voxel[3] = {1.0 / s->dims[0], 1.0 / s->dims[1], 1.0 / s->dims[2]};
    double accumulated[4] = {0, 0, 0, 0};
    for (int i = 0; i < 4096; ++i) {
        double t = t_enter + i * s->step_size;
        if (t > t_exit)
            break;
        double P[3] = {origin[0] + t * direction[0], origin[1] + t * direction[1], origin[2] + t * direction[2]};
        double value = halo_volume_trilinear(s->volume, s->dims, P);
        double color[4];
        conform_transfer_lookup(s->transfer, s->transfer_texels, value, color);
        halo_emu_sample sample = {0};
        memcpy(sample.position, P, sizeof P);
        sample.value = value;
        for (int k = 0; k < 3; ++k) {
            double plus[3] = {P[0], P[1], P[2]}, minus[3] = {P[0], P[1], P[2]};
            plus[k] += voxel[k];
            minus[k] -= voxel[k];
            sample.gradient[k] =
                (halo_volume_trilinear(s->volume, s->dims, plus) - halo_volume_trilinear(s->volume, s->dims, minus)) *
                0.5;
            sample.view[k] = s->eye[k] - P[k];
        }
        double distance =
            sqrt(sample.view[0] * sample.view[0] + sample.view[1] * sample.view[1] + sample.view[2] * sample.view[2]);
        conform_normalize3(sample.view);
        double depth = (distance - front_distance) / (2.0 * radius);
        sample.depth = depth < 0.0 ? 0.0 : depth > 1.0 ? 1.0 : depth;
        sample.fragcoord[0] = x + 0.5;
        sample.fragcoord[1] = y + 0.5;
        memcpy(sample.color, color, 3 * sizeof *color);
        sample.opacity = color[3];
        if (halo_emu_apply(p, NULL, &sample, NULL) != HALO_OK)
            return 0;
        double alpha = sample.opacity < 0.0 ? 0.0 : sample.opacity > 1.0 ? 1.0 : sample.opacity;
        if (alpha > 0.0) {
            alpha = 1.0 - pow(1.0 - alpha, exponent);
            for (int k = 0; k < 3; ++k)
                accumulated[k] += (1.0 - accumulated[3]) * alpha * sample.color[k];
            accumulated[3] += (1.0 - accumulated[3]) * alpha;
            if (accumulated[3] >= threshold)
                break;
        }
    }
    memcpy(out, accumulated, sizeof accumulated);
    conform_over_background(out, 1, s->background);
    return 1;
}

/* The scene of the ray cast row: several stages with well-conditioned parameters. */
static const char raycast_scene[] =
    "{\"halo_scene\": 1, \"stages\": ["
    "{\"boundary\": {}}, {\"silhouette\": {\"k_ss\": 4, \"k_se\": 1}}, {\"tone_shading\": {}},"
    " {\"distance_blend\": {}}],"
    " \"render\": {\"azimuth\": 30, \"elevation\": 20, \"zoom\": 1.3, \"step\": 0.5}}";

void conform_raycast_row(conform *c, const conform_row *row)
{
    if (!row_selected(c, row->name, NULL))
        return;
    raycast_input in;
    float *gpu = NULL;
    double *reference = NULL, *allowed = NULL;
    int printed = 0;
    if (!raycast_input_open(c, halo_scene_load("(conformance ray cast scene)", raycast_scene, c->lib, c->diag), &in))
        goto done;
    const halo_program *program = in.program;
    halo_raycast_state state;
    float transfer[HALO_RAYCAST_TRANSFER_TEXELS * 4];
    gpu = render_raycast(c, program, NULL, in.scene, in.volume, RAYCAST_VOLUME_SIZE, &state, transfer);
    if (!gpu)
        goto done;
    state.volume = in.volume;
    size_t pixels = (size_t)c->size * (size_t)c->size;
    reference = malloc(pixels * 4 * sizeof *reference);
    allowed = malloc(pixels * 4 * sizeof *allowed);
    if (!reference || !allowed) {
        HALO_REPORT_ERROR(c->diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "out of memory");
        goto done;
    }
    static const double moves[][2] = {{-RAYCAST_THRESHOLD_MOVE, 0.0},
                                      {RAYCAST_THRESHOLD_MOVE, 0.0},
                                      {0.0, -RAYCAST_THRESHOLD_MOVE},
                                      {0.0, RAYCAST_THRESHOLD_MOVE}};
    for (int y = 0; y < c->size; ++y)
        for (int x = 0; x < c->size; ++x) {
            size_t i = (size_t)y * (size_t)c->size + (size_t)x;
            double *r = &reference[i * 4];
            if (!emulate_pixel(&state, program, x, y, 0.99, 0.0, r)) {
                HALO_REPORT_ERROR(c->diag, HALO_MSG_EMU_MISSING, "", 0, 0,
                                  "the ray cast scene has a stage without emulation");
                goto done;
            }
            double spread[4] = {0, 0, 0, 0};
            for (size_t m = 0; m < sizeof moves / sizeof moves[0]; ++m) {
                double moved[4];
                if (emulate_pixel(&state, program, x, y, 0.99 + moves[m][0], moves[m][1], moved))
                    for (int k = 0; k < 4; ++k)
                        spread[k] = fmax(spread[k], fabs(moved[k] - r[k]));
            }
            for (int k = 0; k < 4; ++k)
                allowed[i * 4 + (size_t)k] = row->tolerance_abs + spread[k];
        }
    row_stats stats;
    memset(&stats, 0, sizeof stats);
    for (size_t i = 0; i < pixels; ++i) {
        const double g[4] = {gpu[i * 4], gpu[i * 4 + 1], gpu[i * 4 + 2], gpu[i * 4 + 3]};
        row_stats_add(&stats, i, g, &reference[i * 4], &allowed[i * 4], 4, 0.0, 0.0);
    }
    char tolerance_text[32];
    conform_tolerance_text(row, tolerance_text, sizeof tolerance_text);
    int pass = stats.over == 0 && stats.nonfinite == 0;
    print_row(c, row->name, &stats, tolerance_text, pass);
    if (c->verbose || !pass) {
        size_t w = stats.worst;
        fprintf(stderr,
                "  largest error at pixel (%zu, %zu): gpu (%.9g %.9g %.9g %.9g) emulation (%.9g %.9g %.9g %.9g)\n",
                w % (size_t)c->size, w / (size_t)c->size, gpu[w * 4], gpu[w * 4 + 1], gpu[w * 4 + 2], gpu[w * 4 + 3],
                reference[w * 4], reference[w * 4 + 1], reference[w * 4 + 2], reference[w * 4 + 3]);
    }
    printed = 1;
done:
    raycast_input_close(c, row, &in, printed);
    free(gpu);
    free(reference);
    free(allowed);
}
