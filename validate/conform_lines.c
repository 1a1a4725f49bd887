/* Conformance rows for the line stages (see conform_lines.h). */
#include "conform_lines.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "halo.h"
#include "halo_gl_loader.h"
#include "gl/headless.h"
#include "hosts/host_common.h"
#include "hosts/lines.h"
#include "hosts/raycast.h"

/* The probe targets: PROBE_SIDE x PROBE_SIDE inputs per draw. */
#define PROBE_SIDE 64

typedef row_stats stats; /* conform_harness.h */

typedef struct rows {
    halo_glfuncs f;
    halo_library *lib;
    halo_diagnostics *diag;
    const char *only;
    int exact; /* only is one row's name, not a stage */
    int verbose, rows, failures;
} rows;

static void add_value(stats *s, double gpu, double emu, double allowed)
{
    s->values++;
    if (!isfinite(gpu) || !isfinite(emu)) {
        s->nonfinite++;
        return;
    }
    double e = fabs(gpu - emu);
    s->max_abs = fmax(s->max_abs, e);
    s->sum_squares += e * e;
    if (e > allowed)
        s->over++;
}

static void lines_print_row(rows *r, const char *row, const stats *s, const char *tolerance)
{
    int pass = s->over == 0 && s->nonfinite == 0 && s->values > 0;
    print_row_line(row, s, tolerance, pass);
    r->rows++;
    r->failures += !pass;
}

static void lines_print_error_row(rows *r, const char *row)
{
    printf("%-26s %10s %10s %8s %9s %17s FAIL\n", row, "-", "-", "-", "-", "-");
    fflush(stdout);
    halo_diagnostics_print(r->diag, stderr);
    halo_diagnostics_clear(r->diag);
    r->rows++;
    r->failures++;
}

static int selected(const rows *r, const char *row)
{
    if (!r->only)
        return 1;
    size_t n = strlen(r->only);
    return strcmp(r->only, row) == 0 || (!r->exact && strncmp(r->only, row, n) == 0 && row[n] == '@');
}

static uint64_t random_state;

static double random_uniform(void) /* splitmix64, [0, 1) */ { return conform_random_uniform(&random_state); }

static double f32(double x) { return (double)(float)x; }

/* ---- Float targets -------------------------------------------------------------------- */

typedef struct target {
    GLuint framebuffer, textures[2];
} target;

static int target_create(rows *r, target *t)
{
    const halo_glfuncs *f = &r->f;
    memset(t, 0, sizeof *t);
    f->GenTextures(2, t->textures);
    for (int i = 0; i < 2; ++i)
        halo_host_image_texture(f, t->textures[i], GL_RGBA32F, PROBE_SIDE, PROBE_SIDE, GL_RGBA, GL_FLOAT);
    f->BindTexture(GL_TEXTURE_2D, 0);
    f->GenFramebuffers(1, &t->framebuffer);
    f->BindFramebuffer(GL_FRAMEBUFFER, t->framebuffer);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->textures[0], 0);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, t->textures[1], 0);
    GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    f->DrawBuffers(2, buffers);
    int ok = f->CheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    return ok;
}

static void target_release(rows *r, target *t)
{
    if (t->framebuffer)
        r->f.DeleteFramebuffers(1, &t->framebuffer);
    if (t->textures[0])
        r->f.DeleteTextures(2, t->textures);
}

static void target_read(rows *r, target *t, float *out0, float *out1)
{
    const halo_glfuncs *f = &r->f;
    f->BindFramebuffer(GL_FRAMEBUFFER, t->framebuffer);
    f->PixelStorei(GL_PACK_ALIGNMENT, 4);
    f->ReadBuffer(GL_COLOR_ATTACHMENT0);
    f->ReadPixels(0, 0, PROBE_SIDE, PROBE_SIDE, GL_RGBA, GL_FLOAT, out0);
    f->ReadBuffer(GL_COLOR_ATTACHMENT1);
    f->ReadPixels(0, 0, PROBE_SIDE, PROBE_SIDE, GL_RGBA, GL_FLOAT, out1);
    f->ReadBuffer(GL_COLOR_ATTACHMENT0);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
}

/* Links one probe host with a scene (JSON text) into a vertex or fragment program. */
static halo_program *link_probe(rows *r, const char *host, halo_shader_kind kind, const char *scene_text)
{
    halo_scene *scene = halo_scene_load("conform-lines", scene_text, r->lib, r->diag);
    if (!scene)
        return NULL;
    const char *source = halo_host_embedded(host);
    if (!source)
        fprintf(stderr, "conform lines: the probe host %s is not embedded\n", host);
    halo_program *p =
        source ? halo_link(
                     &(halo_link_desc){
                         .library = r->lib, .scene = scene, .host_source = source, .host_file = host, .kind = kind},
                     r->diag)
               : NULL;
    halo_scene_destroy(scene);
    return p;
}

/* ---- line_vertex: points carrying the stage's output ------------------------------------- */

static const char point_fragment[] =
    "#version 330 core\n"
    "flat in vec4 probe_position;\n"
    "flat in vec4 probe_color;\n"
    "layout(location = 0) out vec4 out_position;\n"
    "layout(location = 1) out vec4 out_color;\n"
    "void main() { out_position = probe_position; out_color = probe_color; }\n";

static const char fullscreen_vertex[] =
    "#version 330 core\n"
    "void main() {\n"
    "    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));\n"
    "    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);\n"
    "}\n";

/* A probe: the probe host linked with the row's scene, its GL program and its target. */
typedef struct probe {
    halo_program *linked;
    GLuint program;
    target t;
} probe;

/* Opens the probe (a vertex probe drawn as points, or a fragment probe drawn over the
 * target) of the scene; 0 after the row's error line. */
static int open_probe(rows *r, const char *row, int vertex_probe, const char *scene_text, probe *pr)
{
    halo_program *p = vertex_probe ? link_probe(r, "line_probe.vert", HALO_SHADER_VERTEX, scene_text)
                                   : link_probe(r, "line_probe.frag", HALO_SHADER_FRAGMENT, scene_text);
    GLuint program = !p             ? 0
                     : vertex_probe ? halo_lines_build_program(&r->f, p, NULL, "line_probe.vert", NULL, point_fragment,
                                                               "point.frag", r->diag)
                                    : halo_lines_build_program(&r->f, NULL, fullscreen_vertex, "fullscreen.vert", p,
                                                               NULL, "line_probe.frag", r->diag);
    *pr = (probe){.linked = p, .program = program};
    if (program && target_create(r, &pr->t))
        return 1;
    if (program)
        r->f.DeleteProgram(program), target_release(r, &pr->t);
    halo_program_destroy(p);
    lines_print_error_row(r, row);
    return 0;
}

static void close_probe(rows *r, probe *pr)
{
    r->f.DeleteProgram(pr->program);
    target_release(r, &pr->t);
    halo_program_destroy(pr->linked);
}

/* Runs n <= PROBE_SIDE^2 vertices through line_probe.vert linked with the program and
 * compares them with the emulation (halo_emu_apply). Inputs are float-rounded first. */
static void vertex_row(rows *r, const char *row, const char *scene_text, halo_emu_line_vertex *in, size_t n,
                       const double depth_range[2])
{
    probe pr;
    if (!open_probe(r, row, 1, scene_text, &pr))
        return;
    const halo_glfuncs *f = &r->f;
    float *attributes = malloc(n * 12 * sizeof *attributes);
    float *out0 = malloc(PROBE_SIDE * PROBE_SIDE * 4 * sizeof *out0),
          *out1 = malloc(PROBE_SIDE * PROBE_SIDE * 4 * sizeof *out1);
    if (!attributes || !out0 || !out1) {
        free(attributes), free(out0), free(out1);
        close_probe(r, &pr);
        lines_print_error_row(r, row);
        return;
    }
    for (size_t i = 0; i < n; ++i) {
        halo_emu_line_vertex *v = &in[i];
        for (int c = 0; c < 3; ++c) {
            v->position[c] = f32(v->position[c]);
            v->direction[c] = f32(v->direction[c]);
            v->eye[c] = f32(v->eye[c]);
        }
        v->uv[0] = f32(v->uv[0]);
        v->uv[1] = f32(v->uv[1]);
        v->width = f32(v->width);
        v->color[0] = 0.25, v->color[1] = 0.5, v->color[2] = 0.75, v->opacity = 0.5;
        float *a = &attributes[i * 12];
        for (int c = 0; c < 3; ++c) {
            a[c] = (float)v->position[c];
            a[3 + c] = (float)v->direction[c];
            a[8 + c] = (float)v->eye[c];
        }
        a[6] = (float)v->uv[0], a[7] = (float)v->uv[1], a[11] = (float)v->width;
    }
    GLuint vao = 0, buffer = 0;
    f->GenVertexArrays(1, &vao);
    f->GenBuffers(1, &buffer);
    f->BindVertexArray(vao);
    f->BindBuffer(GL_ARRAY_BUFFER, buffer);
    f->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(n * 12 * sizeof(float)), attributes, GL_STATIC_DRAW);
    static const int sizes[4] = {3, 3, 2, 4}, offsets[4] = {0, 3, 6, 8};
    for (GLuint k = 0; k < 4; ++k) {
        f->EnableVertexAttribArray(k);
        f->VertexAttribPointer(k, sizes[k], GL_FLOAT, GL_FALSE, 12 * sizeof(float),
                               (const void *)(offsets[k] * sizeof(float)));
    }
    f->BindFramebuffer(GL_FRAMEBUFFER, pr.t.framebuffer);
    f->Viewport(0, 0, PROBE_SIDE, PROBE_SIDE);
    const float nan_fill[4] = {NAN, NAN, NAN, NAN};
    f->ClearBufferfv(GL_COLOR, 0, nan_fill);
    f->ClearBufferfv(GL_COLOR, 1, nan_fill);
    f->Disable(GL_DEPTH_TEST);
    f->Disable(GL_BLEND);
    f->UseProgram(pr.program);
    f->Uniform2i(f->GetUniformLocation(pr.program, "target_size"), PROBE_SIDE, PROBE_SIDE);
    f->Uniform2f(f->GetUniformLocation(pr.program, "halo_host_depth_range"), (float)depth_range[0],
                 (float)depth_range[1]);
    f->DrawArrays(GL_POINTS, 0, (GLsizei)n);
    f->UseProgram(0);
    f->BindVertexArray(0);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    target_read(r, &pr.t, out0, out1);
    double range[2] = {f32(depth_range[0]), f32(depth_range[1])};
    stats s = {0};
    /* the emulation's host uniform: the frame's (a line program has no images) */
    halo_emu_frame *frame = halo_emu_frame_create(pr.linked, 1, 1, r->diag);
    int emu_failed = !frame;
    if (frame && halo_emu_frame_set_host_uniform(frame, "depth_range", range, 2) != HALO_OK) {
        HALO_REPORT_ERROR(r->diag, HALO_MSG_EMU_MISSING, "", 0, 0,
                          "%s: the linked program has no host uniform depth_range for its emulation", row);
        emu_failed = 1;
    }
    halo_emu_sample sample = {0};
    for (size_t i = 0; i < n && !emu_failed; ++i) {
        sample.line_vertex = in[i];
        if (halo_emu_apply(pr.linked, frame, &sample, r->diag) != HALO_OK) {
            emu_failed = 1;
            break;
        }
        const halo_emu_line_vertex v = sample.line_vertex;
        const float *g = &out0[i * 4], *gc = &out1[i * 4];
        double scale = 1.0 + fabs(in[i].position[0]) + fabs(in[i].position[1]) + fabs(in[i].position[2]) +
                       fabs(in[i].eye[0]) + fabs(in[i].eye[1]) + fabs(in[i].eye[2]);
        double before = s.over;
        for (int c = 0; c < 3; ++c)
            add_value(&s, g[c], v.position[c], 4e-6 * scale);
        add_value(&s, g[3], v.width, 4e-6 * scale);
        for (int c = 0; c < 3; ++c)
            add_value(&s, gc[c], v.color[c], 1e-6);
        add_value(&s, gc[3], v.opacity, 1e-6);
        if (r->verbose && s.over > before)
            fprintf(stderr,
                    "  %s vertex %zu: p (%.9g %.9g %.9g) D (%.9g %.9g %.9g) uv (%g %g) eye (%.9g %.9g %.9g) w %g\n"
                    "    gpu (%.9g %.9g %.9g | %.9g) emulation (%.9g %.9g %.9g | %.9g)\n",
                    row, i, in[i].position[0], in[i].position[1], in[i].position[2], in[i].direction[0],
                    in[i].direction[1], in[i].direction[2], in[i].uv[0], in[i].uv[1], in[i].eye[0], in[i].eye[1],
                    in[i].eye[2], in[i].width, g[0], g[1], g[2], g[3], v.position[0], v.position[1], v.position[2],
                    v.width);
    }
    f->DeleteBuffers(1, &buffer);
    f->DeleteVertexArrays(1, &vao);
    free(attributes), free(out0), free(out1);
    halo_emu_frame_destroy(frame);
    close_probe(r, &pr);
    if (emu_failed)
        lines_print_error_row(r, row);
    else
        lines_print_row(r, row, &s, "4e-6*(1+|p|+|eye|)");
}

static void random_unit(double v[3])
{
    for (;;) {
        for (int c = 0; c < 3; ++c)
            v[c] = 2.0 * random_uniform() - 1.0;
        double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (n > 0.1 && n <= 1.0) {
            for (int c = 0; c < 3; ++c)
                v[c] /= n;
            return;
        }
    }
}

static const char strip_scene[] =
    "{\"halo_scene\": 1, \"stages\": [{\"line_strip\": {\"strip_width\": 0.05, \"depth_attenuation\": 0.6,"
    " \"taper\": 0.2}}]}";

static void run_strip_row(rows *r)
{
    const char *row = "line_strip";
    if (!selected(r, row))
        return;
    size_t n = PROBE_SIDE * PROBE_SIDE;
    halo_emu_line_vertex *in = calloc(n, sizeof *in);
    if (!in)
        return;
    random_state = 0x11e5;
    for (size_t i = 0; i < n; ++i) {
        halo_emu_line_vertex *v = &in[i];
        for (int c = 0; c < 3; ++c)
            v->position[c] = 2.0 * random_uniform() - 1.0;
        double e[3];
        random_unit(e);
        for (int c = 0; c < 3; ++c)
            v->eye[c] = 4.0 * e[c];
        /* well-conditioned: the line makes an angle of at least ~6 degrees with the view */
        double view[3] = {v->eye[0] - v->position[0], v->eye[1] - v->position[1], v->eye[2] - v->position[2]};
        double vn = sqrt(view[0] * view[0] + view[1] * view[1] + view[2] * view[2]);
        do {
            random_unit(v->direction);
        } while (fabs(view[0] * v->direction[0] + view[1] * v->direction[1] + view[2] * v->direction[2]) > 0.995 * vn);
        double length = 0.2 + 2.0 * random_uniform(); /* D need not be unit */
        for (int c = 0; c < 3; ++c)
            v->direction[c] *= length;
        v->uv[0] = random_uniform();
        v->uv[1] = (double)(i & 1);
        v->width = 0.5 + 1.5 * random_uniform();
    }
    vertex_row(r, row, strip_scene, in, n, (double[2]){2.0, 6.0});
    free(in);
}

/* Degenerate inputs: a line pointing straight at the eye (V x D = 0), zero-length
 * segments and coincident vertices (D = 0, as halo_lines_strip_attributes makes it),
 * a vertex at the eye (V = 0), vertices behind the eye and across the near plane, the
 * line ends (taper to zero width), zero width, and no depth range. */
static void run_strip_degenerate_row(rows *r)
{
    const char *row = "line_strip@degenerate";
    if (!selected(r, row))
        return;
    /* Polylines with coincident points, through the host's strip attributes. */
    static const double coincident[] = {0, 0, 0, 0, 0, 0, 1, 0, 0,           /* a zero-length first segment */
                                        1, 1, 1, 1, 1, 1,                    /* two coincident vertices only */
                                        2, 0, 0, 2, 0, 0, 2, 0, 0, 3, 0, 0}; /* three coincident, then one */
    size_t first[4] = {0, 3, 5, 9};
    halo_polylines lines = {3, 9, first, (double *)coincident};
    double direction[27], u[9];
    halo_lines_strip_attributes(&lines, direction, u);
    halo_emu_line_vertex cases[64];
    size_t n = 0;
    const double eye[3] = {0.0, 0.0, 5.0};
    for (size_t k = 0; k < 9; ++k)
        for (int side = 0; side < 2; ++side) {
            halo_emu_line_vertex *v = &cases[n++];
            memset(v, 0, sizeof *v);
            memcpy(v->position, &coincident[3 * k], sizeof v->position);
            memcpy(v->direction, &direction[3 * k], sizeof v->direction);
            memcpy(v->eye, eye, sizeof v->eye);
            v->uv[0] = u[k], v->uv[1] = side, v->width = 1.0;
        }
    /* position, direction, uv.x, width, eye */
    static const double special[][11] = {
        {0, 0, 0, 0, 0, 1, 0.5, 1, 0, 0, 5},         /* pointing at the eye */
        {0, 0, 0, 0, 0, -3, 0.5, 1, 0, 0, 5},        /* pointing away from it */
        {0.5, 0.5, 0, 1, 1, 0, 0.5, 1, 0.5, 0.5, 4}, /* V x D = 0 off the axis */
        {0, 0, 0, 0, 0, 0, 0.5, 1, 0, 0, 5},         /* zero-length segment: D = 0 */
        {0, 0, 5, 1, 0, 0, 0.5, 1, 0, 0, 5},         /* at the eye: V = 0 */
        {0, 0, 5, 0, 0, 1, 0.5, 1, 0, 0, 5},         /* at the eye, D along the view axis */
        {0, 0, 4.999, 1, 0, 0, 0.5, 1, 0, 0, 5},     /* just in front of the eye (before the near plane) */
        {0, 0, 6, 1, 0, 0, 0.5, 1, 0, 0, 5},         /* behind the eye */
        {0, 0, 7, 0, 0, 1, 0.5, 1, 0, 0, 5},         /* behind the eye, on the axis */
        {0, 0, 0, 1, 0, 0, 0.0, 1, 0, 0, 5},         /* line start: zero width */
        {0, 0, 0, 1, 0, 0, 1.0, 1, 0, 0, 5},         /* line end: zero width */
        {0, 0, 0, 1, 0, 0, 0.5, 0, 0, 0, 5},         /* zero width unit */
        {1e-30, 0, 0, 1e-30, 0, 0, 0.5, 1, 0, 0, 5}, /* tiny direction */
        {0, 0, 0, 1e30, 1e30, 0, 0.5, 1, 0, 0, 5},   /* huge direction */
    };
    for (size_t i = 0; i < sizeof special / sizeof special[0]; ++i)
        for (int side = 0; side < 2; ++side) {
            halo_emu_line_vertex *v = &cases[n++];
            memset(v, 0, sizeof *v);
            const double *c = special[i];
            v->position[0] = c[0], v->position[1] = c[1], v->position[2] = c[2];
            v->direction[0] = c[3], v->direction[1] = c[4], v->direction[2] = c[5];
            v->uv[0] = c[6], v->uv[1] = side, v->width = c[7];
            v->eye[0] = c[8], v->eye[1] = c[9], v->eye[2] = c[10];
        }
    /* no depth range: the host uniform unset */
    vertex_row(r, row, strip_scene, cases, n, (double[2]){0.0, 0.0});
}

/* ---- line_fragment: a probe reading its inputs from float textures ---------------------- */


static void run_halo_row(rows *r, int profile)
{
    static const char *const names[3] = {"line_halo@linear", "line_halo@smooth", "line_halo@step"};
    const char *row = names[profile];
    if (!selected(r, row))
        return;
    char scene[256];
    const double core = 0.4;
    snprintf(scene, sizeof scene,
             "{\"halo_scene\": 1, \"stages\": [{\"line_halo\": {\"core\": %g, \"d_max\": 0.07, \"profile\": %d}}]}",
             core, profile);
    probe pr;
    if (!open_probe(r, row, 0, scene, &pr))
        return;
    const halo_glfuncs *f = &r->f;
    size_t n = PROBE_SIDE * PROBE_SIDE;
    halo_emu_line_fragment *in = calloc(n, sizeof *in);
    float *inputs = malloc(n * 12 * sizeof *inputs), *out0 = malloc(n * 4 * sizeof *out0),
          *out1 = malloc(n * 4 * sizeof *out1);
    GLuint textures[3] = {0, 0, 0};
    if (in && inputs && out0 && out1) {
        random_state = 0xa10 + (uint64_t)profile;
        for (size_t i = 0; i < n; ++i) {
            halo_emu_line_fragment *g = &in[i];
            /* v over [0, 1] including its ends and centre */
            g->uv[0] = f32(random_uniform());
            g->uv[1] = i % 97 == 0 ? 0.5 : i % 89 == 0 ? 0.0 : i % 83 == 0 ? 1.0 : f32(random_uniform());
            g->depth = f32(i % 101 == 0 ? 1.0 : random_uniform());
            for (int c = 0; c < 3; ++c) {
                g->color[c] = f32(random_uniform());
                g->background[c] = f32(random_uniform());
            }
            g->opacity = f32(random_uniform());
            g->fragcoord[0] = (double)(i % PROBE_SIDE) + 0.5;
            g->fragcoord[1] = (double)(i / PROBE_SIDE) + 0.5;
            float *a = &inputs[i * 4], *b = &inputs[(n + i) * 4], *c = &inputs[(2 * n + i) * 4];
            a[0] = (float)g->uv[0], a[1] = (float)g->uv[1], a[2] = (float)g->depth, a[3] = 0.0f;
            b[0] = (float)g->color[0], b[1] = (float)g->color[1], b[2] = (float)g->color[2], b[3] = (float)g->opacity;
            c[0] = (float)g->background[0], c[1] = (float)g->background[1], c[2] = (float)g->background[2], c[3] = 1.0f;
        }
        static const char *const samplers[3] = {"uv_depth", "color_opacity", "background_color"};
        f->GenTextures(3, textures);
        f->UseProgram(pr.program);
        for (int k = 0; k < 3; ++k) {
            f->ActiveTexture(GL_TEXTURE0 + (GLenum)k);
            f->BindTexture(GL_TEXTURE_2D, textures[k]);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            f->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
            f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, PROBE_SIDE, PROBE_SIDE, 0, GL_RGBA, GL_FLOAT,
                          &inputs[k * n * 4]);
            f->Uniform1i(f->GetUniformLocation(pr.program, samplers[k]), k);
        }
        GLuint vao = 0;
        f->GenVertexArrays(1, &vao);
        f->BindVertexArray(vao);
        f->BindFramebuffer(GL_FRAMEBUFFER, pr.t.framebuffer);
        f->Viewport(0, 0, PROBE_SIDE, PROBE_SIDE);
        f->Disable(GL_DEPTH_TEST);
        f->Disable(GL_BLEND);
        f->DrawArrays(GL_TRIANGLES, 0, 3);
        f->BindFramebuffer(GL_FRAMEBUFFER, 0);
        f->BindVertexArray(0);
        f->DeleteVertexArrays(1, &vao);
        for (int k = 2; k >= 0; --k) {
            f->ActiveTexture(GL_TEXTURE0 + (GLenum)k);
            f->BindTexture(GL_TEXTURE_2D, 0);
        }
        f->UseProgram(0);
        target_read(r, &pr.t, out0, out1);
        stats s = {0};
        size_t excluded = 0;
        int emu_failed = 0;
        halo_emu_sample sample = {0};
        for (size_t i = 0; i < n && !emu_failed; ++i) {
            /* where 2|v - 0.5| is within float rounding of the core's edge, the branch may
             * go either way: leave the pixel out */
            double x = 2.0 * fabs(in[i].uv[1] - 0.5);
            if (fabs(x - core) < 1e-6) {
                excluded++;
                continue;
            }
            sample.line_fragment = in[i];
            if (halo_emu_apply(pr.linked, NULL, &sample, r->diag) != HALO_OK) {
                emu_failed = 1;
                break;
            }
            const halo_emu_line_fragment e = sample.line_fragment;
            const float *gc = &out0[i * 4], *gd = &out1[i * 4];
            double before = s.over;
            for (int c = 0; c < 3; ++c)
                add_value(&s, gc[c], e.color[c], 1e-6);
            add_value(&s, gc[3], e.opacity, 1e-6);
            add_value(&s, gd[0], e.depth, 1e-6);
            if (r->verbose && s.over > before)
                fprintf(
                    stderr,
                    "  %s pixel %zu: v %.9g depth %.9g: gpu (%.9g %.9g %.9g %.9g | %.9g) emulation (%.9g %.9g %.9g %.9g | %.9g)\n",
                    row, i, in[i].uv[1], in[i].depth, gc[0], gc[1], gc[2], gc[3], gd[0], e.color[0], e.color[1],
                    e.color[2], e.opacity, e.depth);
        }
        if (r->verbose && excluded)
            fprintf(stderr, "  %s: %zu pixels at the core's edge left out\n", row, excluded);
        if (emu_failed)
            lines_print_error_row(r, row);
        else
            lines_print_row(r, row, &s, "1e-6");
    } else {
        lines_print_error_row(r, row);
    }
    if (textures[0])
        f->DeleteTextures(3, textures);
    free(in), free(inputs), free(out0), free(out1);
    close_probe(r, &pr);
}

/* ---- Images through the line host ---------------------------------------------------------- */

/* Renders lines with the line host linked to scene_text; rgba gets size*size*4 floats. */
static int render_lines(rows *r, const char *scene_text, const halo_polylines *lines, const halo_lines_view *view,
                        int size, float *rgba, halo_lines_state *state)
{
    halo_program *vp = NULL, *fp = NULL;
    if (halo_lines_link(r->lib, NULL, scene_text, NULL, NULL, &vp, &fp, r->diag) != HALO_OK)
        return 0;
    halo_lines *l = halo_lines_create(
        &(halo_lines_desc){.gl = &r->f, .vertex_program = vp, .fragment_program = fp, .width = size, .height = size},
        r->diag);
    int ok = l && halo_lines_set_data(l, lines, r->diag) == HALO_OK && halo_lines_draw(l, view, r->diag) == HALO_OK &&
             halo_lines_read(l, rgba, r->diag) == HALO_OK;
    if (ok && state)
        halo_lines_get_state(l, NULL, state);
    halo_lines_destroy(l);
    halo_program_destroy(vp);
    halo_program_destroy(fp);
    return ok;
}

#define GAP_SIZE 256

/* Two crossing lines, the back one `gap` (normalized depth) behind the front one: is the
 * back line visible inside the front line's halo? Returns 1 visible, 0 hidden, -1 error. */
static int back_line_visible(rows *r, double gap, double d_max, int *nonfinite)
{
    char scene[512];
    snprintf(scene, sizeof scene,
             "{\"halo_scene\": 1, \"stages\": [{\"line_strip\": {\"strip_width\": 0.2, \"depth_attenuation\": 0,"
             " \"taper\": 0}}, {\"line_halo\": {\"core\": 0.4, \"d_max\": %.17g, \"profile\": 2}}]}",
             d_max);
    /* bounds: centre 0, radius 1, so normalized depth 1 is 2 world units along the view */
    double z_front = 0.2, z_back = z_front - 2.0 * gap;
    double points[2 * 17 * 3];
    for (int k = 0; k < 17; ++k) {
        double t = -0.8 + 0.1 * k;
        double *front = &points[3 * k], *back = &points[3 * (17 + k)];
        front[0] = t, front[1] = 0.0, front[2] = z_front;
        back[0] = 0.0, back[1] = t, back[2] = z_back;
    }
    size_t first[3] = {0, 17, 34};
    halo_polylines lines = {2, 34, first, points};
    halo_lines_view view = {.zoom = 1.0, .radius = 1.0, .background = {1, 1, 1}, .line_color = {0, 0, 0}};
    float *rgba = malloc(GAP_SIZE * GAP_SIZE * 4 * sizeof *rgba);
    halo_lines_state state;
    if (!rgba || !render_lines(r, scene, &lines, &view, GAP_SIZE, rgba, &state)) {
        free(rgba);
        return -1;
    }
    for (size_t i = 0; i < GAP_SIZE * GAP_SIZE * 4; ++i)
        *nonfinite += !isfinite(rgba[i]);
    /* In the front line's halo: 0.35 strip widths from its centre (2|v - 0.5| = 0.7),
     * on the back line's centre line. */
    double probe[3] = {0.0, 0.35 * 0.2, z_front}, pixel[2];
    /* the projection needs a renderer; recompute from the state */
    const double *m = state.view_projection;
    double clip[4];
    for (int row = 0; row < 4; ++row)
        clip[row] = m[row] * probe[0] + m[4 + row] * probe[1] + m[8 + row] * probe[2] + m[12 + row];
    pixel[0] = (clip[0] / clip[3] * 0.5 + 0.5) * GAP_SIZE;
    pixel[1] = (clip[1] / clip[3] * 0.5 + 0.5) * GAP_SIZE;
    int x = (int)floor(pixel[0]), y = (int)floor(pixel[1]);
    double luminance = 1.0;
    if (x >= 0 && y >= 0 && x < GAP_SIZE && y < GAP_SIZE) {
        const float *c = &rgba[((size_t)y * GAP_SIZE + (size_t)x) * 4];
        luminance = (c[0] + c[1] + c[2]) / 3.0;
    }
    free(rgba);
    return luminance < 0.5;
}

static void run_depth_gap_row(rows *r)
{
    const char *row = "lines@depth_gap";
    if (!selected(r, row))
        return;
    const double d_max = 0.05;
    static const double gaps[] = {0.0, 0.01, 0.02, 0.03, 0.04, 0.045, 0.055, 0.06, 0.08, 0.12, 0.2, 0.3};
    stats s = {0};
    int nonfinite = 0;
    for (size_t i = 0; i < sizeof gaps / sizeof gaps[0]; ++i) {
        int visible = back_line_visible(r, gaps[i], d_max, &nonfinite);
        if (visible < 0) {
            lines_print_error_row(r, row);
            return;
        }
        int expected = gaps[i] < d_max; /* a halo gap only beyond d_max */
        add_value(&s, visible, expected, 0.5);
        if (r->verbose)
            fprintf(stderr, "  %s: gap %.3f (d_max %.3f): back line %s (expected %s)\n", row, gaps[i], d_max,
                    visible ? "visible" : "interrupted", expected ? "visible" : "interrupted");
    }
    s.nonfinite += (size_t)nonfinite;
    lines_print_row(r, row, &s, "gap>d_max hides");
}

/* A strip through the eye and across the near plane, a line pointing at the eye and
 * zero-length segments, rendered through the line host: every pixel finite, and the
 * image not empty. */
static void run_near_plane_row(rows *r)
{
    const char *row = "lines@near_plane";
    if (!selected(r, row))
        return;
    static const char scene[] =
        "{\"halo_scene\": 1, \"stages\": [{\"line_strip\": {\"strip_width\": 0.1}},"
        " {\"line_halo\": {\"profile\": 1}}]}";
    /* eye on +z at 1/sin(15 deg) = 3.86 from the origin (radius 1) */
    static const double points[] = {0.3,  0.2,  -1.0, 0.3,  0.2,  10.0, /* through the near plane, past the eye */
                                    0.0,  0.0,  3.0,  0.0,  0.0,  1.0,  0.0, 0.0,  -1.0, /* pointing at the eye */
                                    -0.5, -0.5, 0.0,  -0.5, -0.5, 0.0,  0.5, -0.5, 0.0,  /* a zero-length segment */
                                    0.5,  0.5,  0.5,  0.5,  0.5,  0.5,                   /* two coincident vertices */
                                    -0.6, 0.4,  0.0,  -0.2, 0.4,  0.0};
    size_t first[] = {0, 2, 5, 8, 10, 12};
    halo_polylines lines = {5, 12, first, (double *)points};
    halo_lines_view view = {.zoom = 1.0, .radius = 1.0, .background = {1, 1, 1}, .line_color = {0, 0, 0}};
    float *rgba = malloc(128 * 128 * 4 * sizeof *rgba);
    if (!rgba || !render_lines(r, scene, &lines, &view, 128, rgba, NULL)) {
        free(rgba);
        lines_print_error_row(r, row);
        return;
    }
    stats s = {0};
    size_t dark = 0;
    for (size_t i = 0; i < 128 * 128; ++i) {
        for (int c = 0; c < 4; ++c)
            add_value(&s, rgba[4 * i + c], rgba[4 * i + c], 0.0);
        dark += rgba[4 * i] < 0.5f;
    }
    if (dark == 0) /* nothing drawn at all */
        s.over++;
    if (r->verbose)
        fprintf(stderr, "  %s: %zu line pixels\n", row, dark);
    free(rgba);
    lines_print_row(r, row, &s, "finite");
}

static int run_rows(const char *only, int exact, int verbose, int *failed)
{
    rows r = {.only = only, .exact = exact, .verbose = verbose};
    r.diag = halo_diagnostics_create();
    const char *missing = NULL;
    if (!halo_glfuncs_load(&r.f, sizeof r.f, halo_headless_get_proc_address, &missing) ||
        !(r.lib = halo_library_create(r.diag))) {
        if (missing)
            fprintf(stderr, "conform lines: OpenGL entry point %s missing\n", missing);
        lines_print_error_row(&r, "line_strip");
    } else {
        run_strip_row(&r);
        run_strip_degenerate_row(&r);
        for (int profile = 0; profile < 3; ++profile)
            run_halo_row(&r, profile);
        run_depth_gap_row(&r);
        run_near_plane_row(&r);
    }
    halo_library_destroy(r.lib);
    halo_diagnostics_destroy(r.diag);
    if (failed)
        *failed += r.failures;
    return r.rows;
}

int halo_conform_line_rows_select(const char *only, int verbose, int *failed)
{
    return run_rows(only, 0, verbose, failed);
}

int halo_conform_line_rows(int verbose, int *failed) { return halo_conform_line_rows_select(NULL, verbose, failed); }

void conform_lines_row(conform *c, const conform_row *row)
{
    rows selection = {.only = c->only};
    if (c->only && (strncmp(c->only, "line", 4) || !selected(&selection, row->name)))
        return;
    if (conform_skip_on_es(c, row->name, "the line host (examples/hosts/line.vert, .frag) is GLSL 330"))
        return;
    c->rows += run_rows(row->name, 1, c->verbose, &c->failures);
}
