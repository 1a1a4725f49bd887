/* Conformance rows of the outline passes (Svakhine, Ebert & Andrews 2009;
 * glsl/outline/outlines.glsl, docs/outlines.md, docs/accuracy.md "Outline rows").
 *
 * Each row draws synthetic feature samples (one fragment per pixel, a second draw for
 * occluders) through outline_feature and the GL frame, runs the at=post passes on the
 * GPU with a synthetic host colour, and does the same in the emulation from the same
 * samples (feature buffers included). Every image a post pass writes is compared, and
 * each hard case also checks what it is about (flat depth gives no outline, ...). */
#include "conform_outline.h"

#include "hosts/raycast.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A case: the registry's row (conform_rows.c) seen by the code below. */
typedef struct outline_case {
    const char *name;
    enum conform_outline_shape shape;
    int occluder_band;    /* second draw: an opaque band (rows size/3 .. size/2) at depth 0.1 */
    const char *outlines; /* the outlines stage's parameters (JSON object members) */
    double tol_abs, tol_rel;
    const char *reason; /* of the tolerance */
} outline_case;

#define ONE_FEATURE "\"value_min\": 0.5, \"value_max\": 1, \"occluder_opacity\": 0.5"
#define FOUR_FEATURES \
    "\"value_min\": [0, 0.2, 0.5, 0.8], \"value_max\": [0.199, 0.399, 0.7, 1], \"occluder_opacity\": 0.5"

/* Six features: two feature groups (features 0-3, then 4-5), one volume pass each. */
#define SIX_FEATURES                                                                                 \
    "\"value_min\": [0, 0.15, 0.3, 0.5, 0.65, 0.85], \"value_max\": [0.1, 0.25, 0.4, 0.6, 0.75, 1]," \
    " \"occluder_opacity\": 0.5"
static const double six_centres[6][2] = {{0.2, 0.3}, {0.5, 0.3}, {0.8, 0.3}, {0.2, 0.7}, {0.5, 0.7}, {0.8, 0.7}};
static const double six_values[6] = {0.05, 0.2, 0.35, 0.55, 0.7, 0.9};


/* Depth and sphere normal of a disc at (cx, cy), radius r, front depth d0: 1 outside. */
static int disc(double x, double y, double cx, double cy, double r, double d0, double *depth, double n[3])
{
    double dx = (x - cx) / r, dy = (y - cy) / r, q = dx * dx + dy * dy;
    if (q >= 1.0)
        return 0;
    double dz = sqrt(1.0 - q);
    *depth = d0 + 0.25 * (1.0 - dz);
    n[0] = dx, n[1] = dy, n[2] = dz;
    return 1;
}

/* The feature sample of pixel (x, y): value selects the feature (0.75: feature 0 of
 * ONE_FEATURE; 0.1/0.3/0.6/0.9: features 0-3 of FOUR_FEATURES); outside every feature
 * an empty sample (opacity 0: no depth, no normal, no occluder). Feature samples are
 * translucent (opacity 0.25 < occluder_opacity): only the band occludes. */
static void feature_sample(enum conform_outline_shape shape, int size, int x, int y, halo_emu_sample *s)
{
    memset(s, 0, sizeof *s);
    double px = x + 0.5, py = y + 0.5, depth = 1.0, n[3] = {0, 0, 1}, value = 0.75;
    int hit = 0;
    switch (shape) {
    case OUTLINE_FLAT:
        hit = 1, depth = 0.5;
        break;
    case OUTLINE_DEPTH_ONE:
        hit = disc(px, py, size * 0.5, size * 0.5, size * 0.3, 0.0, &depth, n), depth = 1.0;
        break;
    case OUTLINE_PIXEL:
        hit = x == size / 2 && y == size / 2, depth = 0.4;
        break;
    case OUTLINE_BORDER:
        hit = disc(px, py, 0.0, size * 0.5, size * 0.3, 0.3, &depth, n);
        if (!hit && y >= size - 3)
            hit = 1, depth = 0.45, n[0] = 0, n[1] = 0.6, n[2] = 0.8;
        break;
    case OUTLINE_FOUR: {
        static const double centres[4][2] = {{0.3, 0.3}, {0.7, 0.3}, {0.3, 0.7}, {0.62, 0.62}};
        static const double values[4] = {0.1, 0.3, 0.6, 0.9};
        for (int k = 0; k < 4 && !hit; ++k)
            if (disc(px, py, centres[k][0] * size, centres[k][1] * size, size * (0.18 + 0.03 * k), 0.2 + 0.15 * k,
                     &depth, n))
                hit = 1, value = values[k];
        break;
    }
    case OUTLINE_SIX:
        for (int k = 0; k < 6 && !hit; ++k)
            if (disc(px, py, six_centres[k][0] * size, six_centres[k][1] * size, size * 0.12, 0.2 + 0.1 * k, &depth, n))
                hit = 1, value = six_values[k];
        break;
    default: /* two discs, the smaller in front and overlapping */
        hit = disc(px, py, size * 0.38, size * 0.5, size * 0.3, 0.4, &depth, n);
        double d2, n2[3];
        if (disc(px, py, size * 0.62, size * 0.58, size * 0.18, 0.2, &d2, n2) && (!hit || d2 < depth)) {
            hit = 1, depth = d2;
            memcpy(n, n2, sizeof n);
        }
        break;
    }
    s->position[0] = s->position[1] = s->position[2] = 0.5;
    s->view[2] = 1.0;
    s->color[0] = s->color[1] = s->color[2] = 0.5;
    if (hit) {
        s->value = value;
        s->opacity = 0.25;
        s->depth = depth;
        memcpy(s->gradient, n, sizeof n);
    } else {
        s->value = 0.45; /* outside every feature */
        s->depth = 1.0;
        s->gradient[2] = 1.0;
    }
    halo_probe_round_inputs(s, x, y);
}

/* The occluder band: an opaque sample in front of everything, in no feature. */
static void occluder_sample(int size, int x, int y, halo_emu_sample *s)
{
    memset(s, 0, sizeof *s);
    s->position[0] = s->position[1] = s->position[2] = 0.5;
    s->view[2] = 1.0;
    s->gradient[2] = 1.0;
    s->color[0] = 0.3;
    int band = y >= size / 3 && y < size / 2;
    s->value = 0.45;
    s->opacity = band ? 1.0 : 0.0;
    s->depth = band ? 0.1 : 1.0;
    halo_probe_round_inputs(s, x, y);
}

/* The host colour behind: smooth, brightness away from 0.5 (line_color_mode 2 switches
 * there): dark left half 0.1-0.3, light right half 0.7-0.9. */
static void host_colour(int size, int x, int y, double out[4])
{
    double t = (double)y / size, light = x >= size / 2;
    double base = light ? 0.7 : 0.1;
    out[0] = (float)(base + 0.2 * t);
    out[1] = (float)(base + 0.2 * (1.0 - t));
    out[2] = (float)(base + 0.1);
    out[3] = 1.0;
}

static int post_written(const halo_program *p, const char *image)
{
    for (size_t i = 0; i < halo_program_reflection(p).pass_count; ++i) {
        const halo_pass_info *pass = &halo_program_reflection(p).passes[i];
        if (pass->at && !strcmp(pass->output, image))
            return 1;
    }
    return 0;
}

static const halo_image_info *image_named(const halo_program *p, const char *name)
{
    for (size_t i = 0; i < halo_program_reflection(p).image_count; ++i)
        if (!strcmp(halo_program_reflection(p).images[i].name, name))
            return &halo_program_reflection(p).images[i];
    return NULL;
}

/* What the case is about, on the GPU's images: NULL if it holds, else why not. */
static const char *check_case(const outline_case *oc, int size, const float *importance, int channels,
                              const float *final, const float *host)
{
    double most = 0.0, band_most = 0.0, off_band = 0.0, final_change = 0.0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            size_t i = (size_t)y * size + (size_t)x;
            double v = 0.0;
            for (int k = 0; k < channels; ++k)
                v = fmax(v, importance[i * (size_t)channels + (size_t)k]);
            most = fmax(most, v);
            if (y >= size / 3 && y < size / 2)
                band_most = fmax(band_most, v);
            else
                off_band = fmax(off_band, v);
            for (int k = 0; k < 3; ++k)
                final_change = fmax(final_change, fabs(final[i * 4 + (size_t)k] - host[i * 4 + (size_t)k]));
        }
    switch (oc->shape) {
    case OUTLINE_FLAT:
        if (most > 1e-4 || final_change > 1e-4)
            return "a flat depth drew an outline";
        return NULL;
    case OUTLINE_DEPTH_ONE:
        if (most > 0.0)
            return "features at depth 1 drew an outline";
        return NULL;
    case OUTLINE_PIXEL: {
        size_t c = (size_t)(size / 2) * size + (size_t)(size / 2);
        /* a ring: lambda (G*D - D) > 0 at the 4-neighbours (0.1 at 64 x 64, sigma 1.8 px) */
        if (importance[(c + 1) * (size_t)channels] <= 0.0 || importance[(c - (size_t)size) * (size_t)channels] <= 0.0)
            return "no outline around the one-pixel feature";
        if (importance[c * (size_t)channels] > 0.0)
            return "an outline on the one-pixel feature itself (it lies in front of its blur)";
        return NULL;
    }
    default:
        break;
    }
    if (!strcmp(oc->name, "outline:hidden") && (band_most > 0.0 || off_band <= 0.0))
        return "hidden: outline under the occluder (or none elsewhere)";
    if (!strcmp(oc->name, "outline:front") && band_most <= 0.0)
        return "front: no outline under the occluder";
    if (most <= 0.0)
        return "no outline at all";
    return NULL;
}

/* The dashed style must lie between hidden and front: checked across rows. */
static double band_sum(int size, const float *importance, int channels)
{
    double sum = 0.0;
    for (int y = size / 3; y < size / 2; ++y)
        for (int x = 0; x < size; ++x)
            for (int k = 0; k < channels; ++k)
                sum += importance[((size_t)y * size + (size_t)x) * (size_t)channels + (size_t)k];
    return sum;
}

static void run_case(conform *c, const outline_case *oc, const char *probe_source, double band_sums[3])
{
    if (!row_selected(c, oc->name, "outlines") && !row_selected(c, oc->name, "outline"))
        return;
    int size = c->size, four = oc->shape == OUTLINE_FOUR, six = oc->shape == OUTLINE_SIX;
    size_t count = (size_t)size * (size_t)size;
    char json[2048], tolerance_text[32];
    snprintf(json, sizeof json, "{\"halo_scene\": 1, \"stages\": [{\"outline_feature\": {%s}}, {\"outlines\": {%s}}]}",
             six    ? SIX_FEATURES
             : four ? FOUR_FEATURES
                    : ONE_FEATURE,
             oc->outlines);
    snprintf(tolerance_text, sizeof tolerance_text, "%.0e+%.0er", oc->tol_abs, oc->tol_rel); /* conform_rows.c */
    halo_scene *scene = halo_scene_load(oc->name, json, c->lib, c->diag);
    halo_program *program = scene ? halo_link(&(halo_link_desc){.library = c->lib,
                                                                .scene = scene,
                                                                .host_source = probe_source,
                                                                .host_file = "probe.frag",
                                                                .target = c->target},
                                              c->diag)
                                  : NULL;
    halo_gl_frame *gframe = NULL;
    halo_emu_frame *eframe = NULL;
    frame_probe fp = {0};
    halo_emu_sample *samples = malloc(2 * count * sizeof *samples);
    float *host = malloc(count * 4 * sizeof *host), *gl_image = malloc(count * 4 * sizeof *gl_image);
    float *importance = malloc(count * 4 * sizeof *importance), *final = malloc(count * 4 * sizeof *final);
    unsigned host_texture = 0;
    int printed = 0; /* the row printed its line; else conform_row_end prints an error row */
    if (!program || !samples || !host || !gl_image || !importance || !final ||
        halo_diagnostics_describe(c->diag).errors > 0)
        goto done;
    int channels = halo_program_reflection(program).channel_count;
    if (!frame_probe_open(c, program, size, &fp))
        goto done;
    gframe = fp.gl_frame;
    eframe = fp.emu_frame;
    emu_set_axes(eframe);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            size_t i = (size_t)y * size + (size_t)x;
            feature_sample(oc->shape, size, x, y, &samples[i]);
            occluder_sample(size, x, y, &samples[count + i]);
        }
    halo_gl_frame_begin(gframe);
    halo_emu_frame_begin(eframe);
    int draws = oc->occluder_band ? 2 : 1, groups = halo_program_reflection(program).group_count;
    for (int g = 0; g < groups; ++g) {
        /* feature groups: the volume (here: the probe's samples) once per group */
        if (groups > 1) {
            if (halo_program_select_group(program, g) != HALO_OK)
                goto done;
            halo_gl_frame_begin_group(gframe);
            halo_emu_frame_begin_group(eframe);
        }
        for (int d = 0; d < draws; ++d) {
            if (frame_probe_draw(c, &fp, program, gframe, samples + (size_t)d * count, NULL) != HALO_OK)
                goto done;
            for (size_t i = 0; i < count; ++i) {
                halo_emu_sample s = samples[(size_t)d * count + i];
                if (halo_emu_apply(program, eframe, &s, c->diag) != HALO_OK)
                    goto done;
                halo_emu_frame_finish(eframe, &s);
            }
        }
        if (groups > 1) {
            halo_gl_frame_end_group(gframe);
            if (halo_emu_frame_end_group(eframe, c->diag) != HALO_OK)
                goto done;
        }
    }
    if (six && groups != 2) {
        HALO_REPORT_ERROR(c->diag, HALO_MSG_USAGE, "", 0, 0, "six features linked into %d feature groups, not 2",
                          groups);
        goto done;
    }
    /* the host colour, in both */
    double *ehost = halo_emu_frame_image(eframe, "host_color");
    if (!ehost)
        goto done;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            size_t i = (size_t)y * size + (size_t)x;
            double rgba[4];
            host_colour(size, x, y, rgba);
            for (int k = 0; k < 4; ++k)
                host[i * 4 + (size_t)k] = (float)rgba[k], ehost[i * 4 + (size_t)k] = rgba[k];
        }
    const halo_glfuncs *f = c->gl;
    f->GenTextures(1, &host_texture);
    f->BindTexture(GL_TEXTURE_2D, host_texture);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, size, size, 0, GL_RGBA, GL_FLOAT, host);
    f->BindTexture(GL_TEXTURE_2D, 0);
    halo_gl_frame_post(gframe, host_texture);
    GLenum gl_error = f->GetError();
    if (gl_error != GL_NO_ERROR) {
        HALO_REPORT_ERROR(c->diag, HALO_MSG_GL_LINK, "", 0, 0, "OpenGL error 0x%x in the post passes", gl_error);
        goto done;
    }
    if (halo_emu_frame_post(eframe, c->diag) != HALO_OK)
        goto done;
    row_stats stats = {0};
    const char *worst_image = "";
    size_t worst_over = SIZE_MAX;
    const char *worst_over_image = "";
    double worst_values[2] = {0, 0};
    for (size_t m = 0; m < halo_program_reflection(program).image_count; ++m) {
        const halo_image_info *info = &halo_program_reflection(program).images[m];
        if (!post_written(program, info->name))
            continue;
        if (halo_gl_frame_read(gframe, info->name, gl_image) != HALO_OK)
            goto done;
        const double *e = halo_emu_frame_image(eframe, info->name);
        size_t n = count * (size_t)info->channels;
        for (size_t i = 0; i < n; ++i) {
            double g = gl_image[i];
            if (!isfinite(g) || !isfinite(e[i])) {
                stats.nonfinite++;
                continue;
            }
            double error = fabs(g - e[i]);
            stats.sum_squares += error * error;
            stats.values++;
            if (error > stats.max_abs)
                stats.max_abs = error, stats.worst = i / (size_t)info->channels, worst_image = info->name;
            if (getenv("HALO_OUTLINE_DEBUG") && error > 1e-3)
                fprintf(stderr, "    %s (%zu, %zu)[%zu] gpu %.9g emu %.9g\n", info->name,
                        (i / (size_t)info->channels) % (size_t)size, (i / (size_t)info->channels) / (size_t)size,
                        i % (size_t)info->channels, g, e[i]);
            if (error > oc->tol_abs + oc->tol_rel * fabs(e[i]))
                stats.over++, worst_over = i / (size_t)info->channels, worst_over_image = info->name,
                              worst_values[0] = g, worst_values[1] = e[i];
        }
    }
    const halo_image_info *imp = image_named(program, "importance");
    if (!imp || halo_gl_frame_read(gframe, "importance", importance) != HALO_OK ||
        halo_gl_frame_read(gframe, "final", final) != HALO_OK)
        goto done;
    const char *broken = check_case(oc, size, importance, imp->channels, final, host);
    if (six) { /* every feature outlined in the frame's reduced image, whichever group it was in */
        if (halo_gl_frame_read(gframe, "reduced", gl_image) != HALO_OK)
            goto done;
        for (int k = 0; k < 6 && !broken; ++k) {
            double line = 0.0;
            int cx = (int)(six_centres[k][0] * size), cy = (int)(six_centres[k][1] * size), r = (int)(size * 0.12) + 3;
            for (int y = cy - r; y <= cy + r; ++y)
                for (int x = cx - r; x <= cx + r; ++x)
                    if (x >= 0 && y >= 0 && x < size && y < size)
                        line = fmax(line, 1.0 - gl_image[((size_t)y * size + (size_t)x) * 4]);
            if (line < 0.1)
                broken = k < 4 ? "a feature of the first group has no outline after both groups"
                               : "a feature of the second group has no outline after both groups";
        }
    }
    if (!strcmp(oc->name, "outline:hidden"))
        band_sums[0] = band_sum(size, importance, imp->channels);
    else if (!strcmp(oc->name, "outline:dashed"))
        band_sums[1] = band_sum(size, importance, imp->channels);
    else if (!strcmp(oc->name, "outline:front"))
        band_sums[2] = band_sum(size, importance, imp->channels);
    if (!strcmp(oc->name, "outline:front") && band_sums[1] >= 0.0 &&
        !(band_sums[0] < band_sums[1] && band_sums[1] < band_sums[2]))
        broken = "occlusion styles: hidden < dashed < front does not hold under the occluder";
    int pass = stats.over == 0 && stats.nonfinite == 0 && !broken;
    print_row(c, oc->name, &stats, tolerance_text, pass);
    if (broken)
        fprintf(stderr, "  %s: %s\n", oc->name, broken);
    if (c->verbose || !pass) {
        size_t w = worst_over != SIZE_MAX ? worst_over : stats.worst;
        if (worst_over != SIZE_MAX)
            fprintf(stderr, "  gpu %.9g emulation %.9g\n", worst_values[0], worst_values[1]);
        fprintf(stderr, "  %s at pixel (%zu, %zu) of image %s; tolerance: %s; channels %d\n",
                worst_over != SIZE_MAX ? "over tolerance" : "largest error", w % (size_t)size, w / (size_t)size,
                worst_over != SIZE_MAX ? worst_over_image : worst_image, oc->reason, channels);
    }
    printed = 1;
done:
    if (host_texture)
        c->gl->DeleteTextures(1, &host_texture);
    frame_probe_release(&fp); /* and the frames */
    free(samples);
    free(host);
    free(gl_image);
    free(importance);
    free(final);
    conform_row_end(c, oc->name, printed, program, scene);
}

/* The importance in the occluder band of the rows outline:hidden, :dashed and :front of
 * this run, in that order (-1: not run); outline:front checks their order. */
static double band_sums[3] = {-1.0, -1.0, -1.0};

void conform_outline_row(conform *c, const conform_row *row)
{
    const conform_outline_params *params = row->params;
    const outline_case oc = {row->name,        params->shape,      params->occluder_band,
                             params->outlines, row->tolerance_abs, row->tolerance_rel,
                             row->why};
    run_case(c, &oc, c->probe_source, band_sums);
}
