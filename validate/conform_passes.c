/* The pass family: halo_generate's image passes (median, gradient, spreading,
 * occlusion, several halos, halo images at 1/2 and 1/4 of the frame) on chosen seed
 * images, drawn through the frame probe by a test stage that writes its colour as the
 * seeds; the GPU's images against the emulated frame's. */
#include "conform_passes.h"

#include "halo.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A sample stage that writes its colour and opacity as the seeds: the pass rows draw any
 * seed image through the host and the frame's seed output. */
static const char conform_seed_module[] =
    "#pragma halo module conform_seed\n"
    "#pragma halo summary \"conformance: seeds = (r, g, b, opacity) of the sample\"\n"
    "#pragma halo hook sample\n"
    "#pragma halo provides seed channels\n"
    "#pragma halo output seed max\n"
    "void apply(inout halo_sample s) { s.seed = halo_channels_from(vec4(s.color, s.opacity)); }\n";

enum { SEED_EMPTY, SEED_FULL, SEED_PIXEL, SEED_BORDER, SEED_DISCS, SEED_NOISE, SEED_CASES };
static const char *const seed_case_names[SEED_CASES] = {"empty", "full", "single pixel", "border", "discs", "noise"};

/* Seed image case `which` for one channel, as floats (what the GPU's seed image holds). */
static double seed_case(int which, int x, int y, int size)
{
    int c0 = size / 2;
    switch (which) {
    case SEED_EMPTY:
        return 0.0;
    case SEED_FULL:
        return 1.0;
    case SEED_PIXEL:
        return x == c0 && y == c0 ? 1.0 : 0.0;
    case SEED_BORDER: {
        int last = size - 1;
        if ((x == 0 || x == last) && (y == 0 || y == last))
            return 1.0;
        if (x == 0 && y % 3 == 0)
            return 1.0;
        if (x == last && y % 4 == 1)
            return 0.75;
        if (y == 0 && x % 5 == 2)
            return 1.0;
        if (y == last && x % 2 == 0)
            return 0.5;
        return 0.0;
    }
    case SEED_DISCS: {
        static const double discs[][4] = {
            {0.25, 0.3, 1, 0.7}, {0.6, 0.35, 3, 1.0}, {0.35, 0.7, 6, 0.35}, {0.8, 0.8, 2, 1.0}};
        for (size_t d = 0; d < sizeof discs / sizeof discs[0]; ++d) {
            double dx = x - discs[d][0] * size, dy = y - discs[d][1] * size;
            if (dx * dx + dy * dy <= discs[d][2] * discs[d][2])
                return discs[d][3];
        }
        return 0.0;
    }
    default: {
        uint64_t z = (uint64_t)(y * size + x) * 0x9e3779b97f4a7c15ull + 0x1234567ull;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        z ^= z >> 31;
        double u = (double)(z >> 11) / 9007199254740992.0;
        return u < 0.3 ? 0.0 : (float)u;
    }
    }
}


static void run_pass_row(conform *c, halo_library *lib, const conform_row *row)
{
    const conform_pass_params *r = row->params;
    char json[512], tolerance_text[32];
    snprintf(json, sizeof json, "{\"halo_scene\": 1, \"stages\": [\"conform_seed\", {\"halo_generate\": %s}]}",
             r->generate);
    conform_tolerance_text(row, tolerance_text, sizeof tolerance_text);
    halo_scene *scene = halo_scene_load("(conformance pass scene)", json, lib, c->diag);
    halo_program *program = NULL;
    halo_gl_frame *gframe = NULL;
    halo_emu_frame *eframe = NULL;
    frame_probe fp = {0};
    size_t count = (size_t)c->size * (size_t)c->size;
    halo_emu_sample *samples = calloc(count, sizeof *samples);
    float *image = malloc(count * 4 * sizeof *image);
    int printed = 0; /* the row printed its line; else conform_row_end prints an error row */
    if (!scene || !samples || !image)
        goto done;
    program = halo_link(&(halo_link_desc){.library = lib,
                                          .scene = scene,
                                          .host_source = c->probe_source,
                                          .host_file = "probe.frag",
                                          .image_scale = r->scale,
                                          .target = c->target},
                        c->diag);
    if (!program || halo_diagnostics_describe(c->diag).errors > 0)
        goto done;
    int channels = halo_program_reflection(program).channel_count;
    if (!frame_probe_open(c, program, c->size, &fp))
        goto done;
    gframe = fp.gl_frame;
    eframe = fp.emu_frame;
    row_stats stats = {0};
    int worst_case = -1;
    for (int which = 0; which < SEED_CASES; ++which) {
        halo_gl_frame_begin(gframe);
        halo_emu_frame_begin(eframe);
        for (int g = 0; g < r->generations; ++g) {
            int base = (which + g) % SEED_CASES;
            double *seed = halo_emu_frame_image(eframe, "seed");
            for (int y = 0; y < c->size; ++y)
                for (int x = 0; x < c->size; ++x) {
                    size_t i = (size_t)y * (size_t)c->size + (size_t)x;
                    halo_emu_sample *s = &samples[i];
                    memset(s, 0, sizeof *s);
                    double v[4] = {0, 0, 0, 0};
                    for (int h = 0; h < channels; ++h)
                        v[h] = seed_case((base + h) % SEED_CASES, x, y, c->size);
                    s->color[0] = v[0], s->color[1] = v[1], s->color[2] = v[2], s->opacity = v[3];
                    s->view[2] = 1.0;
                    for (int h = 0; h < channels; ++h)
                        seed[i * (size_t)channels + (size_t)h] = v[h];
                }
            if (frame_probe_draw(c, &fp, program, gframe, samples, NULL) != HALO_OK)
                goto done;
            halo_gl_frame_generate(gframe);
            if (halo_emu_frame_generate(eframe, c->diag) != HALO_OK)
                goto done;
        }
        for (int k = 0; k < 3 && r->compare[k]; ++k) {
            if (halo_gl_frame_read(gframe, r->compare[k], image) != HALO_OK)
                goto done;
            const double *e = halo_emu_frame_image(eframe, r->compare[k]);
            int scale = 1;
            for (size_t m = 0; m < halo_program_reflection(program).image_count; ++m)
                if (!strcmp(halo_program_reflection(program).images[m].name, r->compare[k]))
                    scale = halo_program_reflection(program).images[m].scale;
            size_t side = (size_t)((c->size + scale - 1) / scale), compared = side * side;
            for (size_t i = 0; i < compared; ++i) {
                int over = 0, nonfinite = 0;
                for (int h = 0; h < channels; ++h) {
                    double gv = image[i * (size_t)channels + (size_t)h], ev = e[i * (size_t)channels + (size_t)h];
                    if (!isfinite(gv)) {
                        nonfinite = 1;
                        continue;
                    }
                    double error = fabs(gv - ev);
                    if (row_stats_note(&stats, i, error))
                        worst_case = which;
                    if (error > row->tolerance_abs)
                        over = 1;
                }
                stats.over += (size_t)over;
                stats.nonfinite += (size_t)nonfinite;
            }
        }
    }
    int pass = stats.over == 0 && stats.nonfinite == 0;
    print_row(c, row->name, &stats, tolerance_text, pass);
    if ((c->verbose || !pass) && worst_case >= 0)
        fprintf(stderr, "  largest error at texel %zu (row-major in its image) of seed case '%s'; tolerance: %s\n",
                stats.worst, seed_case_names[worst_case], row->why);
    printed = 1;
done:
    frame_probe_release(&fp); /* and the frames */
    free(samples);
    free(image);
    conform_row_end(c, row->name, printed, program, scene);
}


/* The test module lives in a library of its own, so that it gets no stage row. */
void conform_pass_row(conform *c, const conform_row *row)
{
    if (!row_selected(c, row->name, NULL))
        return;
    halo_library *lib = halo_library_create(c->diag);
    if (!lib ||
        halo_library_add(lib, "(conformance seed module)", conform_seed_module, HALO_ADD_NEW, c->diag) != HALO_OK) {
        print_error_row(c, row->name);
        halo_library_destroy(lib);
        return;
    }
    run_pass_row(c, lib, row);
    halo_library_destroy(lib);
}

/* ---- Every other image-pass stage: its passes on noise ---------------------------------- */

/* A value in [0, 1) for texel i of image k: the inputs of the generic image rows. */
static double image_noise(size_t i, size_t k)
{
    uint64_t z = (uint64_t)i * 0x9e3779b97f4a7c15ull + (uint64_t)(k + 1) * 0xda942042e4dd58b5ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double)(float)((double)(z >> 11) / 9007199254740992.0);
}

/* Whether one of the program's passes writes the image. */
static int pass_written(const halo_program *p, const char *image)
{
    halo_reflection r = halo_program_reflection(p);
    for (size_t i = 0; i < r.pass_count; ++i)
        if (!strcmp(r.passes[i].output, image))
            return 1;
    return 0;
}

/* The image's texel count (an image at 1/scale of the frame has fewer). */
static size_t image_texels(const halo_image_info *info, int size)
{
    size_t side = (size_t)((size + info->scale - 1) / info->scale);
    return side * side;
}

/* Stage m alone, through the frame probe: every image no pass writes (the host's colour,
 * the outputs of the sample stages it reads) filled with the same noise in GL and in the
 * emulation, the generation passes, then the post and final ones; every image its passes
 * write compared. */
static void run_image_stage_row(conform *c, const halo_module *m, const conform_row *row)
{
    const char *stage = halo_module_describe(m).name;
    char name[128], tolerance_text[32];
    snprintf(name, sizeof name, "pass:%s", stage);
    if (!row_selected(c, name, stage))
        return;
    conform_tolerance_text(row, tolerance_text, sizeof tolerance_text);
    halo_scene *scene = halo_scene_create(c->lib);
    halo_program *program = NULL;
    frame_probe fp = {0};
    const halo_glfuncs *f = c->gl;
    GLuint host_texture = 0;
    float *texels = NULL;
    int printed = 0;
    size_t most = (size_t)c->size * (size_t)c->size * 4;
    if (!halo_module_describe(m).has_emulation) {
        HALO_REPORT_ERROR(c->diag, HALO_MSG_EMU_MISSING, halo_module_describe(m).file, 0, 0,
                          "stage '%s' has no C emulation of every pass", stage);
        goto done;
    }
    if (!scene || halo_scene_enable(scene, stage, 1, c->diag) != HALO_OK)
        goto done;
    program = halo_link(&(halo_link_desc){.library = c->lib,
                                          .scene = scene,
                                          .host_source = c->probe_source,
                                          .host_file = "probe.frag",
                                          .target = c->target},
                        c->diag);
    if (!program || halo_diagnostics_describe(c->diag).errors > 0 || !frame_probe_open(c, program, c->size, &fp))
        goto done;
    texels = malloc(most * sizeof *texels);
    if (!texels)
        goto done;
    halo_reflection r = halo_program_reflection(program);
    halo_gl_frame_begin(fp.gl_frame);
    halo_emu_frame_begin(fp.emu_frame);
    for (size_t k = 0; k < r.image_count; ++k) {
        const halo_image_info *info = &r.images[k];
        if (pass_written(program, info->name))
            continue;
        double *e = halo_emu_frame_image(fp.emu_frame, info->name);
        size_t n = image_texels(info, c->size) * (size_t)info->channels;
        if (!e || n > most)
            goto done;
        for (size_t i = 0; i < n; ++i)
            texels[i] = (float)(e[i] = image_noise(i, k));
        static const GLenum formats[5] = {0, GL_RED, GL_RG, GL_RGB, GL_RGBA};
        int side = (c->size + info->scale - 1) / info->scale;
        GLuint texture = info->host ? 0 : halo_gl_frame_texture(fp.gl_frame, info->name);
        if (info->host) {
            f->GenTextures(1, &host_texture);
            texture = host_texture;
            f->BindTexture(GL_TEXTURE_2D, texture);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, side, side, 0, formats[info->channels], GL_FLOAT, texels);
        } else if (texture) {
            f->BindTexture(GL_TEXTURE_2D, texture);
            f->TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, side, side, formats[info->channels], GL_FLOAT, texels);
        }
        f->BindTexture(GL_TEXTURE_2D, 0);
    }
    int generates = 0;
    for (size_t i = 0; i < r.pass_count; ++i)
        generates |= r.passes[i].at == HALO_PASS_AT_GENERATE;
    if (generates) {
        halo_gl_frame_generate(fp.gl_frame);
        if (halo_emu_frame_generate(fp.emu_frame, c->diag) != HALO_OK)
            goto done;
    }
    halo_gl_frame_post(fp.gl_frame, host_texture);
    if (halo_emu_frame_post(fp.emu_frame, c->diag) != HALO_OK)
        goto done;
    GLenum gl_error = f->GetError();
    if (gl_error != GL_NO_ERROR) {
        HALO_REPORT_ERROR(c->diag, HALO_MSG_GL_LINK, "", 0, 0, "OpenGL error 0x%x in the passes of %s", gl_error,
                          stage);
        goto done;
    }
    row_stats stats = {0};
    const char *worst_image = "";
    for (size_t k = 0; k < r.image_count; ++k) {
        const halo_image_info *info = &r.images[k];
        if (!pass_written(program, info->name))
            continue;
        if (halo_gl_frame_read(fp.gl_frame, info->name, texels) != HALO_OK)
            goto done;
        const double *e = halo_emu_frame_image(fp.emu_frame, info->name);
        size_t n = image_texels(info, c->size) * (size_t)info->channels;
        for (size_t i = 0; i < n; ++i) {
            double g = texels[i];
            if (!isfinite(g) || !isfinite(e[i])) {
                stats.nonfinite++;
                continue;
            }
            double error = fabs(g - e[i]);
            if (row_stats_note(&stats, i / (size_t)info->channels, error))
                worst_image = info->name;
            if (error > row->tolerance_abs + row->tolerance_rel * fabs(e[i]))
                stats.over++;
        }
    }
    int pass = stats.over == 0 && stats.nonfinite == 0;
    print_row(c, name, &stats, tolerance_text, pass);
    if ((c->verbose || !pass) && stats.values)
        fprintf(stderr, "  largest error at texel %zu of image %s; tolerance: %s\n", stats.worst, worst_image,
                row->why);
    printed = 1;
done:
    if (host_texture)
        f->DeleteTextures(1, &host_texture);
    free(texels);
    frame_probe_release(&fp);
    conform_row_end(c, name, printed, program, scene);
}

void conform_image_other_rows(conform *c, const conform_row *row)
{
    const char *const *own = row->params; /* the image stages with families of their own */
    for (size_t i = 0; i < halo_library_describe(c->lib).module_count; ++i) {
        const halo_module *m = halo_library_describe(c->lib).modules[i];
        if (halo_module_describe(m).hook != HALO_HOOK_IMAGE)
            continue;
        int listed = 0;
        for (size_t k = 0; own && own[k]; ++k)
            listed |= !strcmp(own[k], halo_module_describe(m).name);
        if (!listed)
            run_image_stage_row(c, m, row);
    }
}
