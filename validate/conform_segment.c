/* Conformance of segmented ray casting (host contract 2): raycast.frag drawn by
 * halo_gl_frame_draw in depth segments, against a double-precision emulation of the same
 * renderer: the same rays, samples and compositing as the one-draw emulation of the
 * raycast row, the samples of each segment chosen by the same plan as the runtime's
 * (conform_segment_plan_make), halo_emu_apply with the frame per sample, the fragment's outputs
 * finished once per segment, halo_emu_frame_generate between segments.
 *
 * The hosts in the styles of the wild (examples/hosts/webgl_caster.frag,
 * exit_point_caster.frag, tf2d_caster.frag, mip_iso_caster.frag) are emulated by the same
 * loop: a conform_segment_host says where each does otherwise than raycast.frag (its
 * first sample and step count, its transfer lookup, classification and lighting, its
 * inputs derived by libhalo or its own, its opacity correction and termination), and
 * the row brackets the decisions float32 may take the other way. */
#include "conform_segment.h"

#include "hosts/host_common.h"
#include "volume.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* The hosts (conform_segment.h): raycast.frag, and what the others do otherwise. */
const conform_segment_host conform_segment_raycast = {.file = "raycast.frag",
                                                      .target = HALO_TARGET_GLSL330,
                                                      .shading = CONFORM_SHADE_TRANSFER,
                                                      .threshold = 0.99,
                                                      .centred_lookup = 1,
                                                      .opacity_correction = 1};
/* ES 300 style, drawn as GLSL 330 (the context has no ES): derived inputs, a jittered first
 * sample, a counted loop, termination at 0.98, the table read at texture(tf, vec2(v, 0.5)) */
const conform_segment_host conform_segment_webgl = {.file = "webgl_caster.frag",
                                                    .target = HALO_TARGET_GLSL330,
                                                    .shading = CONFORM_SHADE_TRANSFER,
                                                    .threshold = 0.98,
                                                    .counted_steps = 1,
                                                    .derived_view = 1,
                                                    .derived_depth = 1,
                                                    .opacity_correction = 1};
/* raycast.frag's sampling and classification; its exit from the back-face texture (the
 * same ray parameter up to the rasterizer's interpolation: bracketed), derived inputs */
const conform_segment_host conform_segment_exit_points = {.file = "exit_point_caster.frag",
                                                          .target = HALO_TARGET_GLSL450,
                                                          .shading = CONFORM_SHADE_TRANSFER,
                                                          .threshold = 0.99,
                                                          .centred_lookup = 1,
                                                          .derived_view = 1,
                                                          .derived_depth = 1,
                                                          .opacity_correction = 1,
                                                          .exit_points = 1};
/* its own gradient and view, libhalo's depth; passes 0.995 to end */
const conform_segment_host conform_segment_tf2d = {.file = "tf2d_caster.frag",
                                                   .target = HALO_TARGET_GLSL330,
                                                   .shading = CONFORM_SHADE_TF2D,
                                                   .threshold = 0.995,
                                                   .strict_threshold = 1,
                                                   .derived_depth = 1,
                                                   .opacity_correction = 1};
/* its own gradient at hits, libhalo's view and depth; opacity 0 or 1, not corrected */
const conform_segment_host conform_segment_iso = {.file = "mip_iso_caster.frag",
                                                  .target = HALO_TARGET_GLSL330,
                                                  .shading = CONFORM_SHADE_ISO,
                                                  .threshold = 0.99,
                                                  .counted_steps = 1,
                                                  .derived_view = 1,
                                                  .derived_depth = 1};
const conform_segment_host conform_segment_mip = {
    .file = "mip_iso_caster.frag", .target = HALO_TARGET_GLSL330, .shading = CONFORM_SHADE_MIP, .counted_steps = 1};

/* mip_iso_caster.frag's iso_value and tf2d_caster.frag's lighting */
#define ISO_VALUE      0.5
#define TF2D_AMBIENT   0.3
#define TF2D_DIFFUSE   0.6
#define TF2D_SPECULAR  0.25
#define TF2D_SHININESS 24.0

/* One pixel's ray: origin, unit direction, the box's entry and exit, the first sample
 * (the entry, jittered in webgl_caster.frag), the host's end of the sample loop, and the
 * segment index bounds as the shader computes them (in float). */
typedef struct segment_ray {
    double origin[3], direction[3], t_enter, t_exit, t_first;
    int steps;
    float phi0, dphi;
    int ended;
} segment_ray;

/* webgl_caster.frag's pixel_hash of uvec2(gl_FragCoord.xy): integer arithmetic, exact. */
static double pixel_hash(int x, int y)
{
    uint32_t h = (uint32_t)x * 1664525u + (uint32_t)y * 22695477u + 1013904223u;
    h ^= h >> 15;
    h *= 2246822519u;
    h ^= h >> 13;
    return (double)(h >> 8) * (1.0 / 16777216.0);
}

enum { MAX_STEPS = 4096 }; /* the ray caster's loop bound */

static void make_ray(const halo_raycast_state *s, const conform_segment_plan *plan, const conform_segment_model *m,
                     int max_steps, int x, int y, segment_ray *r)
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
    r->t_first = r->t_enter;
    if (m->jitter != 0.0)
        r->t_first += m->jitter * pixel_hash(x, y) * s->step_size;
    r->steps = max_steps;
    if (m->host->counted_steps) {
        double exit = r->t_exit + m->exit_move;
        double steps = exit > r->t_first ? ceil((exit - r->t_first) / s->step_size) : 0.0;
        r->steps = steps < max_steps ? (int)steps : max_steps;
    }
    /* halo_segment_begin, in float as the shader */
    float phi0 = (float)plan->plane[3], dphi = 0.0f;
    for (int k = 0; k < 3; ++k) {
        phi0 += (float)plan->plane[k] * (float)(r->origin[k] + r->t_first * r->direction[k]);
        dphi += (float)plan->plane[k] * (float)r->direction[k];
    }
    r->phi0 = phi0;
    r->dphi = dphi * (float)s->step_size;
    r->ended = 0;
}

/* What make_ray needs besides the pixel, for conform_host_frame_rays. */
typedef struct ray_context {
    const halo_raycast_state *s;
    const conform_segment_plan *plan;
    const conform_segment_model *m;
} ray_context;

static void init_segment_ray(void *context, int x, int y, void *ray)
{
    const ray_context *c = context;
    make_ray(c->s, c->plan, c->m, MAX_STEPS, x, y, ray);
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

static double smoothstep(double edge0, double edge1, double x)
{
    double t = (x - edge0) / (edge1 - edge0);
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    return t * t * (3.0 - 2.0 * t);
}

/* tf2d_caster.frag's transfer_2d and Phong headlight: color holds the 1D table's entry
 * by value; gradient is the contract's (halved), the host's magnitude is of twice it. */
static void shade_tf2d(const double gradient[3], const double view[3], double color[4])
{
    double g[3] = {2.0 * gradient[0], 2.0 * gradient[1], 2.0 * gradient[2]};
    double magnitude = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    static const double edge_white[3] = {1.0, 0.97, 0.9};
    double whiten = 0.4 * smoothstep(0.12, 0.4, magnitude);
    for (int c = 0; c < 3; ++c)
        color[c] += (edge_white[c] - color[c]) * whiten;
    color[3] *= 0.15 + 0.85 * smoothstep(0.01, 0.12, magnitude);
    if (!(color[3] > 0.0))
        return;
    double normal[3], facing = 0.0;
    for (int c = 0; c < 3; ++c) { /* the normal points to lower values, turned to the eye */
        normal[c] = magnitude > 1e-6 ? -g[c] / magnitude : view[c];
        facing += normal[c] * view[c];
    }
    double sign = facing < 0.0 ? -1.0 : 1.0, reflected = 0.0;
    facing *= sign;
    for (int c = 0; c < 3; ++c) /* reflect(-V, N) . V */
        reflected += (-view[c] + 2.0 * facing * sign * normal[c]) * view[c];
    double specular = TF2D_SPECULAR * pow(fmax(reflected, 0.0), TF2D_SHININESS);
    for (int c = 0; c < 3; ++c)
        color[c] = color[c] * (TF2D_AMBIENT + TF2D_DIFFUSE * fmax(facing, 0.0)) + specular;
}

/* mip_iso_caster.frag's isosurface: opaque and lit by |N.V| at a hit, else empty with a
 * zero gradient; color holds the colour map's entry by value. */
static void shade_iso(int hit, double gradient[3], const double view[3], double color[4])
{
    if (!hit) {
        for (int c = 0; c < 4; ++c)
            color[c] = 0.0;
        gradient[0] = gradient[1] = gradient[2] = 0.0;
        return;
    }
    double g2 = 4.0 * (gradient[0] * gradient[0] + gradient[1] * gradient[1] + gradient[2] * gradient[2]);
    double scale = 1.0 / sqrt(fmax(g2, 1e-20)), diffuse = 0.0;
    for (int c = 0; c < 3; ++c)
        diffuse += -2.0 * gradient[c] * scale * view[c];
    for (int c = 0; c < 3; ++c)
        color[c] *= 0.25 + 0.75 * fabs(diffuse);
    color[3] = 1.0;
}

/* A sample of the model's host: position P at ray parameter t; fills the halo_sample
 * fields the host passes (value, gradient, view, depth, colour, opacity). raycast.frag's
 * arithmetic comes first and stays as it was; the others change what they do otherwise. */
static void host_sample(const halo_raycast_state *s, const conform_segment_plan *plan, const conform_segment_model *m,
                        const double P[3], halo_emu_sample *sample)
{
    const conform_segment_host *host = m->host;
    const double radius = 0.8660254037844386;
    double centre_distance = sqrt((s->eye[0] - 0.5) * (s->eye[0] - 0.5) + (s->eye[1] - 0.5) * (s->eye[1] - 0.5) +
                                  (s->eye[2] - 0.5) * (s->eye[2] - 0.5));
    double front_distance = centre_distance - radius;
    double voxel[3] = {1.0 / s->dims[0], 1.0 / s->dims[1], 1.0 / s->dims[2]};
    memcpy(sample->position, P, sizeof sample->position);
    sample->value = halo_volume_trilinear(s->volume, s->dims, P);
    double color[4];
    if (host->centred_lookup)
        conform_transfer_lookup(s->transfer, s->transfer_texels, sample->value, color);
    else
        conform_transfer_texture(s->transfer, s->transfer_texels, sample->value, color);
    double distance = 0.0;
    for (int c = 0; c < 3; ++c) {
        double plus[3] = {P[0], P[1], P[2]}, minus[3] = {P[0], P[1], P[2]};
        plus[c] += voxel[c];
        minus[c] -= voxel[c];
        sample->gradient[c] =
            (halo_volume_trilinear(s->volume, s->dims, plus) - halo_volume_trilinear(s->volume, s->dims, minus)) * 0.5;
        sample->view[c] = s->eye[c] - P[c];
        distance += sample->view[c] * sample->view[c];
    }
    distance = sqrt(distance);
    for (int c = 0; c < 3; ++c)
        sample->view[c] /= distance;
    double depth = (distance - front_distance) / (2.0 * radius);
    sample->depth = depth < 0.0 ? 0.0 : depth > 1.0 ? 1.0 : depth;
    if (host->shading == CONFORM_SHADE_TF2D)
        shade_tf2d(sample->gradient, sample->view, color);
    else if (host->shading == CONFORM_SHADE_ISO)
        shade_iso(sample->value >= ISO_VALUE + m->iso_move, sample->gradient, sample->view, color);
    if (host->derived_view) { /* halo_view_at */
        double v[3], length2 = 0.0;
        for (int c = 0; c < 3; ++c) {
            v[c] = plan->eye[c] - P[c] * plan->eye[3];
            length2 += v[c] * v[c];
        }
        for (int c = 0; c < 3; ++c)
            sample->view[c] = length2 > 1e-30 ? v[c] / sqrt(length2) : 0.0;
    }
    if (host->derived_depth) { /* halo_depth_at */
        double span = fmax(plan->back - plan->front, 1e-30);
        double phi = plan->plane[0] * P[0] + plan->plane[1] * P[1] + plan->plane[2] * P[2] + plan->plane[3];
        depth = (phi - plan->front) / span;
        sample->depth = depth < 0.0 ? 0.0 : depth > 1.0 ? 1.0 : depth;
    }
    memcpy(sample->color, color, 3 * sizeof *color);
    sample->opacity = color[3];
}

/* The MIP variant of mip_iso_caster.frag (no stage): the largest value along the ray,
 * classified, over the background. */
static void emulate_mip(const halo_raycast_state *s, const segment_ray *rays, double *out)
{
    for (size_t i = 0; i < (size_t)s->width * (size_t)s->height; ++i) {
        const segment_ray *r = &rays[i];
        double largest = 0.0, P[3], mip[4];
        for (int k = 0; k < r->steps; ++k) {
            for (int c = 0; c < 3; ++c)
                P[c] = r->origin[c] + (r->t_first + k * s->step_size) * r->direction[c];
            largest = fmax(largest, halo_volume_trilinear(s->volume, s->dims, P));
        }
        conform_transfer_texture(s->transfer, s->transfer_texels, largest, mip);
        for (int c = 0; c < 3; ++c)
            out[i * 4 + (size_t)c] = mip[c] * mip[3] + (1.0 - mip[3]) * s->background[c];
        out[i * 4 + 3] = 1.0;
    }
}

/* ---- Host contract 3: the halo field computed before the one host draw ---------------------- */

/* The images the one-draw host's samples read (its samplers), one stack layer per depth
 * segment but the last: what the samples of segment j + 1 read (gl/field.c). */
typedef struct field_stacks {
    int count, layers, width, height; /* width, height: the images' (1/scale of the frame) */
    int scale, frame_width;
    const char *images[HALO_MAX_OUTPUT_LOCATION + 1];
    int channels[HALO_MAX_OUTPUT_LOCATION + 1];
    double *layer_data[HALO_MAX_OUTPUT_LOCATION + 1]; /* layers * width * height * channels */
} field_stacks;

static void field_stacks_free(field_stacks *st)
{
    for (int i = 0; i < st->count; ++i)
        free(st->layer_data[i]);
}

/* Is image one of the march's seeds (an output of the march the host program does not
 * write itself)? The march program holds the scene's other stages too (outline features:
 * the host's samples write those). */
static int feeds_generation(const halo_program *p, const char *image)
{
    for (size_t o = 0; o < halo_program_reflection(p).output_count; ++o)
        if (!strcmp(halo_program_reflection(p).outputs[o].image, image))
            return 0;
    return 1;
}

/* The seed images (the march's outputs that feed generation) from one frame to the other. */
static void copy_seeds(const halo_program *p, halo_emu_frame *from_frame, halo_emu_frame *to_frame, size_t pixels)
{
    const halo_program *march = halo_program_reflection(p).march;
    for (size_t o = 0; o < halo_program_reflection(march).output_count; ++o) {
        const halo_output_info *out = &halo_program_reflection(march).outputs[o];
        if (!feeds_generation(p, out->image))
            continue;
        double *from = halo_emu_frame_image(from_frame, out->image), *to = halo_emu_frame_image(to_frame, out->image);
        for (size_t k = 0; from && to && k < halo_program_reflection(march).image_count; ++k)
            if (!strcmp(halo_program_reflection(march).images[k].name, out->image))
                memcpy(to, from, pixels * (size_t)halo_program_reflection(march).images[k].channels * sizeof *to);
    }
}

/* The march of gl/field.c and prepass.c in double: for segment j, front to back, each
 * pixel's ray meets the segment's planes (phi = front + k step, k in the segment's range,
 * ray parameter in [0, 1] between the near and far planes, inside the unit box); there a
 * sample of the march program (value and the contract's gradient from the volume, view
 * and depth derived, colour and opacity 0) seeds the march frame's outputs; they go into
 * the host frame's images of the same names, which generate; the images the host reads
 * are kept as layer j. */
static int field_emulate(const halo_raycast_state *s, const halo_program *p, const conform_segment_plan *plan,
                         halo_emu_frame *host, field_stacks *st, halo_diagnostics *diag)
{
    const halo_program *march = halo_program_reflection(p).march;
    memset(st, 0, sizeof *st);
    /* the march and the field at the halo images' scale (halo_link_desc.image_scale): a ray
     * through the centre of each 1/scale pixel, as gl/field.c's */
    int scale = halo_program_reflection(p).image_scale > 1 ? halo_program_reflection(p).image_scale : 1;
    st->scale = scale;
    st->frame_width = s->width;
    st->width = (s->width + scale - 1) / scale;
    st->height = (s->height + scale - 1) / scale;
    st->layers = plan->segments > 1 ? plan->segments - 1 : 1;
    size_t pixels = (size_t)st->width * (size_t)st->height;
    for (size_t i = 0; i < halo_program_reflection(p).sampler_count && st->count <= HALO_MAX_OUTPUT_LOCATION; ++i) {
        const char *name = halo_program_reflection(p).samplers[i].image;
        for (size_t k = 0; k < halo_program_reflection(p).image_count; ++k)
            if (!strcmp(halo_program_reflection(p).images[k].name, name)) {
                if (halo_program_reflection(p).images[k].scale != scale) {
                    HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0,
                                      "the one-draw emulation takes images at the program's image_scale only");
                    return 0;
                }
                st->images[st->count] = name;
                st->channels[st->count] = halo_program_reflection(p).images[k].channels;
                st->layer_data[st->count] =
                    calloc((size_t)st->layers * pixels * (size_t)st->channels[st->count], sizeof(double));
                if (!st->layer_data[st->count++]) {
                    HALO_REPORT_ERROR(diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "out of memory");
                    return 0;
                }
            }
    }
    int framed = 1;
    halo_emu_frame *seeds =
        march ? conform_host_frame(march, st->width, st->height, s->screen_right, s->screen_up, &framed, diag) : NULL;
    if (!seeds) {
        if (framed)
            HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0, "the one-draw program has no march to emulate");
        return 0;
    }
    double step = s->step_size, voxel[3] = {1.0 / s->dims[0], 1.0 / s->dims[1], 1.0 / s->dims[2]};
    int planes = (int)(floor((plan->back - plan->front) / step) + 1.0);
    int ok = 1;
    for (int j = 0; j + 1 < plan->segments && ok; ++j) {
        /* the segment's planes, as gl/field.c's segment_planes */
        double a = ceil(j * plan->length / step - 0.5 - 1e-9), b = ceil((j + 1) * plan->length / step - 0.5 - 1e-9);
        int first = a < 0.0 ? 0 : a > planes ? planes : (int)a, end = b < 0.0 ? 0 : b > planes ? planes : (int)b;
        /* the march frame's seeds start as the host frame's images (cleared by the last generation) */
        copy_seeds(p, host, seeds, pixels);
        for (int y = 0; y < st->height && ok; ++y)
            for (int x = 0; x < st->width && ok; ++x) {
                /* the pixel's centre in the frame's pixels */
                double pixel[2] = {(x + 0.5) * scale, (y + 0.5) * scale};
                double ndc[2] = {pixel[0] / s->width * 2.0 - 1.0, pixel[1] / s->height * 2.0 - 1.0};
                double near_point[4], far_point[4], origin[3], direction[3];
                conform_transform(s->inverse_view_projection, (const double[]){ndc[0], ndc[1], -1.0, 1.0}, near_point);
                conform_transform(s->inverse_view_projection, (const double[]){ndc[0], ndc[1], 1.0, 1.0}, far_point);
                double phi_origin = plan->plane[3], phi_rate = 0.0;
                for (int c = 0; c < 3; ++c) {
                    origin[c] = near_point[c] / near_point[3];
                    direction[c] = far_point[c] / far_point[3] - origin[c];
                    phi_origin += plan->plane[c] * origin[c];
                    phi_rate += plan->plane[c] * direction[c];
                }
                halo_emu_sample fragment;
                memset(&fragment, 0, sizeof fragment);
                /* the march's output pixel (its frame is the seed image's size); its samples
                 * see the frame's pixel coordinates (prepass.c) */
                fragment.fragcoord[0] = x + 0.5;
                fragment.fragcoord[1] = y + 0.5;
                for (int k = first; k < end && fabs(phi_rate) > 1e-30 && ok; ++k) {
                    double t = (plan->front + k * step - phi_origin) / phi_rate, P[3];
                    if (t < 0.0 || t > 1.0)
                        continue;
                    int inside = 1;
                    for (int c = 0; c < 3; ++c) {
                        P[c] = origin[c] + t * direction[c];
                        inside &= P[c] >= 0.0 && P[c] <= 1.0;
                    }
                    if (!inside)
                        continue;
                    halo_emu_sample sample;
                    memset(&sample, 0, sizeof sample);
                    memcpy(sample.position, P, sizeof P);
                    memcpy(sample.fragcoord, pixel, sizeof sample.fragcoord);
                    sample.value = halo_volume_trilinear(s->volume, s->dims, P);
                    double v[3], length2 = 0.0;
                    for (int c = 0; c < 3; ++c) {
                        double plus[3] = {P[0], P[1], P[2]}, minus[3] = {P[0], P[1], P[2]};
                        plus[c] += voxel[c];
                        minus[c] -= voxel[c];
                        sample.gradient[c] = (halo_volume_trilinear(s->volume, s->dims, plus) -
                                              halo_volume_trilinear(s->volume, s->dims, minus)) *
                                             0.5;
                        v[c] = plan->eye[c] - P[c] * plan->eye[3]; /* halo_view_at */
                        length2 += v[c] * v[c];
                    }
                    for (int c = 0; c < 3; ++c)
                        sample.view[c] = length2 > 1e-30 ? v[c] / sqrt(length2) : 0.0;
                    double span = fmax(plan->back - plan->front, 1e-30), phi = phi_origin + t * phi_rate;
                    double depth = (phi - plan->front) / span; /* halo_depth_at */
                    sample.depth = depth < 0.0 ? 0.0 : depth > 1.0 ? 1.0 : depth;
                    memcpy(sample.output_accum, fragment.output_accum, sizeof sample.output_accum);
                    memcpy(sample.output_accum_next, fragment.output_accum_next, sizeof sample.output_accum_next);
                    ok = halo_emu_apply(march, seeds, &sample, diag) == HALO_OK;
                    memcpy(fragment.output_accum, sample.output_accum, sizeof sample.output_accum);
                    memcpy(fragment.output_accum_next, sample.output_accum_next, sizeof sample.output_accum_next);
                }
                halo_emu_frame_finish(seeds, &fragment);
            }
        copy_seeds(p, seeds, host, pixels);
        ok = ok && halo_emu_frame_generate(host, diag) == HALO_OK;
        for (int i = 0; ok && i < st->count; ++i) {
            const double *image = halo_emu_frame_image(host, st->images[i]);
            size_t n = pixels * (size_t)st->channels[i];
            if (image)
                memcpy(st->layer_data[i] + (size_t)j * n, image, n * sizeof *image);
        }
    }
    halo_emu_frame_destroy(seeds);
    return ok;
}

/* Before a host sample at P of pixel i: the frame's images at the pixel hold the layer
 * of P's segment (halo_stack_layer_at: the segment k of phi(P), moved by m->layer_move,
 * reads layer k - 1; the first segment reads zero). */
/* The move of plane b (the bound between segments b - 1 and b) under model m. */
static double plane_move(const conform_segment_model *m, long b)
{
    if (m->layer_pattern <= 0)
        return m->layer_move;
    return ((unsigned long)b >> (m->layer_pattern - 1)) & 1u ? m->layer_move : -m->layer_move;
}

static void field_at_sample(const field_stacks *st, const conform_segment_plan *plan, const conform_segment_model *m,
                            halo_emu_frame *host, const double P[3], size_t i)
{
    double phi = plan->plane[0] * P[0] + plan->plane[1] * P[1] + plan->plane[2] * P[2] + plan->plane[3];
    long nearest = lround((phi - plan->start) / plan->length);
    double k = floor((phi + plane_move(m, nearest) - plan->start) / plan->length);
    int layer = k >= 1.0 ? (int)fmin(k, plan->segments - 1.0) - 1 : -1;
    if (layer >= st->layers)
        layer = st->layers - 1;
    size_t pixels = (size_t)st->width * (size_t)st->height;
    /* the texels the sample's read takes: the pixel's own, or at 1/scale the four around it
     * that the bilinear read blends (halo_emu_read_image; the GPU's halo_read_NAME) */
    size_t texels[4] = {i, i, i, i};
    if (st->scale > 1) {
        double fx = (double)(i % (size_t)st->frame_width) + 0.5, fy = (double)(i / (size_t)st->frame_width) + 0.5;
        int x0 = (int)floor(fx / st->scale - 0.5), y0 = (int)floor(fy / st->scale - 0.5);
        for (int t = 0; t < 4; ++t) {
            int x = x0 + (t & 1), y = y0 + (t >> 1);
            x = x < 0 ? 0 : x > st->width - 1 ? st->width - 1 : x;
            y = y < 0 ? 0 : y > st->height - 1 ? st->height - 1 : y;
            texels[t] = (size_t)y * (size_t)st->width + (size_t)x;
        }
    }
    for (int s = 0; s < st->count; ++s) {
        double *image = halo_emu_frame_image(host, st->images[s]);
        int n = st->channels[s];
        for (int t = 0; image && t < (st->scale > 1 ? 4 : 1); ++t)
            for (int c = 0; c < n; ++c) {
                size_t at = texels[t] * (size_t)n + (size_t)c;
                image[at] = layer < 0 ? 0.0 : st->layer_data[s][(size_t)layer * pixels * (size_t)n + at];
            }
    }
}

int halo_conform_segment_emulate(const halo_raycast_state *s, const halo_program *p, const conform_segment_plan *plan,
                                 const conform_segment_model *model, double *out, halo_diagnostics *diag)
{
    conform_segment_model m = *model;
    if (!m.host)
        m.host = &conform_segment_raycast;
    size_t pixels = (size_t)s->width * (size_t)s->height;
    halo_emu_frame *frame = NULL;
    ray_context context = {s, plan, &m};
    segment_ray *rays = conform_host_frame_rays(p, s->width, s->height, s->screen_right, s->screen_up, sizeof *rays,
                                                init_segment_ray, &context, &frame, diag);
    if (!rays)
        return 0;
    if (m.host->shading == CONFORM_SHADE_MIP) {
        emulate_mip(s, rays, out);
        halo_emu_frame_destroy(frame);
        free(rays);
        return 1;
    }
    for (size_t i = 0; i < pixels * 4; ++i)
        out[i] = 0.0;
    double exponent = s->step_size / s->unit_step;
    double threshold = m.host->threshold + m.threshold_move;
    if (halo_program_reflection(p).output_count > 0) /* HALO_RAY_MAY_END 0: the ray goes on to its end */
        threshold = INFINITY;
    int ok = 1, generation = 0;
    for (size_t i = 0; i < halo_program_reflection(p).pass_count; ++i)
        generation |= halo_program_reflection(p).passes[i].at == HALO_PASS_AT_GENERATE;
    /* host contract 3: the field of every segment first, then the host in one draw */
    field_stacks stacks = {0};
    int one_draw = halo_program_reflection(p).one_draw;
    if (one_draw)
        ok = frame && field_emulate(s, p, plan, frame, &stacks, diag);
    int segments = one_draw ? 1 : plan->segments;
    for (int j = 0; j < segments && ok; ++j) {
        int head = j == 0, tail = j == segments - 1;
        /* (moved by layer_move: which segment a sample near a plane falls in is a float decision) */
        float low_bound = (float)(plan->start + j * plan->length + plane_move(&m, j)),
              high_bound = (float)(plan->start + (j + 1) * plan->length + plane_move(&m, j + 1));
        for (size_t i = 0; i < pixels && ok; ++i) {
            segment_ray *r = &rays[i];
            int first = 0, end = r->steps;
            if (r->dphi > 0.0f) {
                if (!head)
                    first = segment_index(low_bound, r, r->steps);
                if (!tail)
                    end = segment_index(high_bound, r, r->steps);
            } else if (!head) {
                first = r->steps;
            }
            if (r->ended)
                first = r->steps;
            if (end < first)
                end = first;
            double *acc = &out[i * 4];
            halo_emu_sample fragment; /* the outputs' accumulators of this fragment */
            memset(&fragment, 0, sizeof fragment);
            fragment.fragcoord[0] = (double)(i % (size_t)s->width) + 0.5;
            fragment.fragcoord[1] = (double)(i / (size_t)s->width) + 0.5;
            int k = first;
            for (; k < end && ok; ++k) {
                double t = r->t_first + k * s->step_size;
                if (!m.host->counted_steps && t > r->t_exit + m.exit_move)
                    break;
                halo_emu_sample sample;
                memset(&sample, 0, sizeof sample);
                double P[3];
                for (int c = 0; c < 3; ++c)
                    P[c] = r->origin[c] + t * r->direction[c];
                host_sample(s, plan, &m, P, &sample);
                memcpy(sample.fragcoord, fragment.fragcoord, sizeof sample.fragcoord);
                if (one_draw)
                    field_at_sample(&stacks, plan, &m, frame, P, i);
                memcpy(sample.output_accum, fragment.output_accum, sizeof sample.output_accum);
                memcpy(sample.output_accum_next, fragment.output_accum_next, sizeof sample.output_accum_next);
                ok = (frame ? halo_emu_apply(p, frame, &sample, diag) : halo_emu_apply(p, NULL, &sample, diag)) ==
                     HALO_OK;
                memcpy(fragment.output_accum, sample.output_accum, sizeof sample.output_accum);
                memcpy(fragment.output_accum_next, sample.output_accum_next, sizeof sample.output_accum_next);
                double alpha = sample.opacity < 0.0 ? 0.0 : sample.opacity > 1.0 ? 1.0 : sample.opacity;
                if (alpha > 0.0) { /* raycast.frag's skip; the others add nothing for alpha 0 either */
                    if (m.host->opacity_correction)
                        alpha = 1.0 - pow(1.0 - alpha, exponent);
                    for (int c = 0; c < 3; ++c)
                        acc[c] += (1.0 - acc[3]) * alpha * sample.color[c];
                    acc[3] += (1.0 - acc[3]) * alpha;
                    if (m.host->strict_threshold ? acc[3] > threshold : acc[3] >= threshold)
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
    field_stacks_free(&stacks);
    conform_over_background(out, pixels, s->background);
    const halo_image_info *post = halo_host_post_image(p);
    if (ok && frame && post) /* the host's colour through the at=post passes, as halo_host_post_passes */
        ok = post_passes(frame, post, pixels, out, diag);
    halo_emu_frame_destroy(frame);
    free(rays);
    return ok;
}

/* ---- The depth segments (docs/host-contract.md, "Host contract 2") ------------------------ */

int conform_segment_plan_make(const float inverse_view_projection[16], float step, int segments, const halo_program *p,
                              conform_segment_plan *plan)
{
    double inverse[16], m[16];
    for (int i = 0; i < 16; ++i)
        inverse[i] = inverse_view_projection[i];
    if (!halo_host_matrix_invert(inverse, m) || !(step > 0.0f))
        return 0;
    /* phi: clip w (perspective, the distance along the view axis) or, where w is
     * constant (orthographic), clip z; each row of the view-projection, made unit */
    const double w[4] = {m[3], m[7], m[11], m[15]}, z[4] = {m[2], m[6], m[10], m[14]};
    double w_length = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    double z_length = sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
    int perspective = w_length > 1e-9 * z_length;
    double length = perspective ? w_length : z_length;
    if (!(length > 0.0) || !isfinite(length))
        return 0;
    for (int k = 0; k < 4; ++k)
        plan->plane[k] = (perspective ? w : z)[k] / length;
    /* the eye: where clip x, y and w are 0, inverse * (0, 0, 1, 0); orthographic: -plane */
    plan->eye[3] = perspective ? 1.0 : 0.0;
    for (int k = 0; k < 3; ++k)
        plan->eye[k] = perspective ? inverse[8 + k] / inverse[11] : -plan->plane[k];
    /* the unit box's bounding sphere: centre (0.5, 0.5, 0.5), radius sqrt(3) / 2 */
    double centre = plan->plane[3], radius = 0.0;
    for (int k = 0; k < 3; ++k) {
        centre += plan->plane[k] * 0.5;
        radius += 0.25;
    }
    radius = sqrt(radius);
    plan->front = centre - radius;
    plan->back = centre + radius;
    /* the planes front + k step, k < floor((back - front) / step) + 1; a sample belongs
     * to the segment of its nearest plane, so the segments start half a step before */
    double depth = plan->back - plan->front, planes = floor(depth / step) + 1.0;
    plan->start = plan->front - 0.5 * step;
    plan->length = depth + step;
    plan->segments = 1;
    halo_reflection r = halo_program_reflection(p);
    if (r.segment_location > 0 || r.one_draw) {
        int interval = r.interval > 0 ? r.interval : 4; /* M: the program's, or the paper's 4 */
        double wanted = segments > 0 ? segments : ceil(planes / interval);
        double count = fmin(fmax(wanted, 1.0), HALO_SEGMENTS_MAX);
        plan->segments = (int)count;
        plan->length = segments > 0 || wanted > HALO_SEGMENTS_MAX ? planes * step / count : interval * (double)step;
    }
    for (int k = 0; k < 4; ++k)
        if (!isfinite(plan->eye[k]) || !isfinite(plan->plane[k]))
            return 0;
    return isfinite(plan->front) && isfinite(plan->back);
}

/* ---- The rows (conform_rows.c) ------------------------------------------------------------ */

/* Renders the row's host as the program needs (segments 0) or in exactly `segments`; fills
 * state (its transfer table copied into transfer: the host is gone on return) and plan.
 * NULL with diagnostics on failure. */
static float *render(conform *c, const halo_program *p, const halo_render_settings *settings, const float *volume,
                     int volume_size, const conform_segment_params *params, int segments, halo_raycast_state *state,
                     float transfer[HALO_RAYCAST_TRANSFER_TEXELS * 4], conform_segment_plan *plan)
{
    const conform_segment_host *host = params->host ? params->host : &conform_segment_raycast;
    size_t values = (size_t)c->size * (size_t)c->size * 4;
    float *gpu = malloc(values * sizeof *gpu);
    halo_raycast *r = halo_raycast_create(
        &(halo_host_desc){.gl = c->gl, .runtime = c->runtime, .program = p, .width = c->size, .height = c->size},
        c->diag);
    int ok = gpu && r &&
             halo_raycast_set_volume(r, volume, volume_size, volume_size, volume_size, c->diag) == HALO_OK &&
             halo_raycast_set_render(r, settings, c->diag) == HALO_OK;
    if (ok && host->exit_points)
        ok = halo_raycast_set_exit_points(r, c->diag) == HALO_OK;
    if (ok) {
        halo_raycast_set_jitter(r, params->jitter);
        halo_raycast_set_orthographic(r, params->orthographic);
        halo_raycast_set_camera(r, settings->azimuth, settings->elevation, settings->zoom);
        halo_raycast_set_segments(r, 0, segments > 0 ? segments : 0);
        halo_raycast_set_gradient_precision(r, params->one_draw);
        ok = halo_raycast_render(r, gpu, c->diag) == HALO_OK;
        halo_raycast_get_state(r, state);
        memcpy(transfer, state->transfer, sizeof(float) * HALO_RAYCAST_TRANSFER_TEXELS * 4);
        state->transfer = transfer;
        float inverse[16];
        for (int i = 0; i < 16; ++i)
            inverse[i] = (float)state->inverse_view_projection[i];
        halo_gl_segments_desc desc = {.inverse_view_projection = inverse,
                                      .step = (float)state->step_size,
                                      .segments = segments > 0 ? segments : 0};
        if (ok && !conform_segment_plan_make(inverse, desc.step, desc.segments, p, plan)) {
            HALO_REPORT_ERROR(c->diag, HALO_MSG_USAGE, "", 0, 0, "the host's camera cannot be inverted");
            ok = 0;
        }
    }
    halo_raycast_destroy(r);
    if (!ok) {
        free(gpu);
        return NULL;
    }
    return gpu;
}

static halo_program *link_host(conform *c, const halo_scene *scene, const conform_segment_host *host,
                               const char *source, int force, int one_draw, int image_scale)
{
    return halo_link(&(halo_link_desc){.library = c->lib,
                                       .scene = scene,
                                       .host_source = source,
                                       .host_file = host->file,
                                       .target = c->target == HALO_TARGET_ES300 ? c->target : host->target,
                                       .force_segments = force,
                                       .one_draw = one_draw,
                                       .image_scale = image_scale},
                     c->diag);
}

/* The host's text: raycast.frag's (loaded once by the harness), an embedded host's, or the
 * MIP variant of mip_iso_caster.frag; *owned is the copy to free. */
static const char *host_source(conform *c, const conform_segment_host *host, char **owned)
{
    *owned = NULL;
    if (host == &conform_segment_raycast)
        return c->raycast_source;
    char *text = halo_host_load(host->file, NULL, c->diag);
    if (text && host->shading == CONFORM_SHADE_MIP) {
        char *variant = halo_host_mip_variant(text);
        free(text);
        text = variant;
        if (!text)
            HALO_REPORT_ERROR(c->diag, HALO_MSG_USAGE, host->file, 0, 0, "no MIP mode lines to switch on");
    }
    return *owned = text;
}

void conform_segment_row(conform *c, const conform_row *row)
{
    if (!row_selected(c, row->name, "segments"))
        return;
    const conform_segment_params *params = row->params;
    if (params->host && params->host->target == HALO_TARGET_GLSL450 &&
        conform_skip_on_es(c, row->name, "the host is GLSL 450 (desktop OpenGL)"))
        return;
    const int volume_size = 32;
    size_t values = (size_t)c->size * (size_t)c->size * 4;
    float *volume = halo_volume_create(volume_size), *gpu = NULL, *single = NULL;
    double *reference = NULL, *allowed = NULL, *moved = NULL;
    halo_program *program = NULL, *plain = NULL;
    const conform_segment_host *host = params->host ? params->host : &conform_segment_raycast;
    char *owned_source = NULL;
    const char *source = host_source(c, host, &owned_source);
    halo_scene *scene = volume ? halo_scene_load("(conformance segment scene)", params->scene, c->lib, c->diag) : NULL;
    halo_raycast_state state;
    conform_segment_plan plan;
    float transfer[HALO_RAYCAST_TRANSFER_TEXELS * 4];
    int ok = source && scene &&
             (program = link_host(c, scene, host, source, params->segments > 0, params->one_draw,
                                  params->image_scale)) != NULL;
    const halo_render_settings *settings = ok ? halo_scene_describe(scene).render : NULL;
    ok = ok && (gpu = render(c, program, settings, volume, volume_size, params, params->segments, &state, transfer,
                             &plan)) != NULL;
    row_stats stats = {0};
    if (ok && params->segments > 0) {
        /* the same host in one draw: the segments alone must change nothing */
        conform_segment_plan once;
        ok = (plain = link_host(c, scene, host, source, 0, 0, params->image_scale)) != NULL &&
             (single = render(c, plain, settings, volume, volume_size, params, 0, &state, transfer, &once)) != NULL;
        for (size_t i = 0; ok && i < values / 4; ++i) {
            const double g[4] = {gpu[i * 4], gpu[i * 4 + 1], gpu[i * 4 + 2], gpu[i * 4 + 3]};
            const double s[4] = {single[i * 4], single[i * 4 + 1], single[i * 4 + 2], single[i * 4 + 3]};
            row_stats_add(&stats, i, g, s, NULL, 4, row->tolerance_abs, 0.0);
        }
    } else if (ok) {
        /* against the emulation; the decisions on the opacity threshold, the ray's exit and
         * the isosurface's value bracketed */
        /* threshold, exit, iso, plane, the planes' pattern */
        static const double moves[][5] = {
            {-1e-5, 0.0, 0.0, 0.0, 0}, {1e-5, 0.0, 0.0, 0.0, 0}, {0.0, -1e-5, 0.0, 0.0, 0}, {0.0, 1e-5, 0.0, 0.0, 0},
            {0.0, 0.0, 0.0, -1e-5, 0}, {0.0, 0.0, 0.0, 1e-5, 0}, {0.0, 0.0, 0.0, -1e-5, 1}, {0.0, 0.0, 0.0, 1e-5, 1},
            {0.0, 0.0, 0.0, -1e-5, 2}, {0.0, 0.0, 0.0, 1e-5, 2}, {0.0, 0.0, -1e-5, 0.0, 0}, {0.0, 0.0, 1e-5, 0.0, 0}};
        /* the segment a sample falls in (segments), the stack layer it reads (one_draw):
         * decisions on phi, bracketed as the exits; each plane's rounding is its own, so
         * besides every plane one way, the planes alternately (pattern 1) and in pairs
         * (pattern 2) each way: with all one way, a pixel at 256 x 256 of the orthographic
         * row (every ray meets the planes at the same depths) was 3.3e-3 off, bracketed
         * only to 3.1e-5; alternately, up to 5.4e-3 */
        size_t move_count = host->shading == CONFORM_SHADE_ISO ? 12 : 10;
        reference = malloc(values * sizeof *reference);
        moved = malloc(values * sizeof *moved);
        allowed = calloc(values, sizeof *allowed);
        state.volume = volume;
        conform_segment_model model = {.host = host, .jitter = params->jitter};
        ok = reference && moved && allowed &&
             halo_conform_segment_emulate(&state, program, &plan, &model, reference, c->diag);
        for (size_t m = 0; ok && m < move_count; ++m) {
            conform_segment_model bracket = {.host = host,
                                             .jitter = params->jitter,
                                             .threshold_move = moves[m][0],
                                             .exit_move = moves[m][1],
                                             .iso_move = moves[m][2],
                                             .layer_move = moves[m][3],
                                             .layer_pattern = (int)moves[m][4]};
            ok = halo_conform_segment_emulate(&state, program, &plan, &bracket, moved, c->diag);
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
    free(owned_source);
    free(volume);
    free(gpu);
    free(single);
    free(reference);
    free(allowed);
    free(moved);
}
