/* The conformance harness (halo-validate conform, docs/accuracy.md), shared by the
 * family files (conform_sample.c, conform_frame.c, conform_render.c, conform_passes.c,
 * conform_outline.c, conform_slice.c, conform_feature.c, conform_lines.c, figure3.c):
 * what a row of the registry is, the run's context, row statistics and printing, the
 * probe's inputs (hard and random samples), the frame probe (a per-sample stage drawn
 * once per pixel through a GL frame) and the command line. Dependencies go one way:
 * the families use the harness, the harness calls none of them; the registry
 * (conform_rows.c) names the families' run functions, conform.c walks the registry.
 * Not installed. */
#ifndef HALO_CONFORM_HARNESS_H
#define HALO_CONFORM_HARNESS_H

#include "halo.h"
#include "halo_gl_loader.h"
#include "gl/headless.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

typedef struct conform conform;
typedef struct conform_row conform_row;

/* Runs one row of the registry (it may print several rows, e.g. a stage's variants):
 * checks row_selected itself, prints through print_row / print_error_row. */
typedef void conform_run_fn(conform *c, const conform_row *row);

/* One row of the registry (conform_rows.c). */
struct conform_row {
    const char *name;    /* as printed; a per-sample stage's row also prints its variants */
    const char *family;  /* sample, frame, render, pass, outline, slice, feature, lines, figure3 */
    const char *renders; /* what it renders and compares, in a line */
    /* The tolerance column: a printf format of (abs, rel), or plain text (no %). */
    const char *tolerance;
    double tolerance_abs, tolerance_rel;
    const char *why; /* the tolerance's reason */
    conform_run_fn *run;
    const void *params; /* the family's own parameters of this row (its header's type), or NULL */
};

/* The tolerance column of a row: its format applied to its numbers. */
void conform_tolerance_text(const conform_row *row, char *text, size_t size);

typedef struct row_stats {
    double max_abs, sum_squares;
    size_t values, over, nonfinite;
    size_t worst; /* sample index of max_abs */
} row_stats;

struct conform {
    halo_library *lib;
    halo_headless *context;
    halo_gl *runtime;
    const halo_glfuncs *gl;
    halo_diagnostics *diag;
    int size, verbose, list;
    int gradient_format; /* the slice and slab rows' halo_gradient_format (0: the hosts' default) */
    const char *only;
    char *raycast_source, *probe_source; /* the example hosts' fragment sources */
    const conform_row *registry;         /* every row, in order (conform_rows.c) */
    size_t registry_count;
    int rows, failures, errors;
    /* the context: OpenGL (es 0; rows linked for GLSL 330, the default) or OpenGL ES 3.0 /
     * 3.2 (es 30, 32: rows linked for GLSL ES 300; rows that need desktop OpenGL skipped) */
    int es;
    halo_target target;
    int skipped;
};
/* On an OpenGL ES context, a (selected) row that needs desktop OpenGL is skipped with the
 * reason: returns 1 (the caller returns) after printing it; 0 otherwise. */
int conform_skip_on_es(conform *c, const char *row, const char *why);

/* The command line of `halo-validate conform` (argv[0] is "conform"): fills c. Returns
 * -1 to go on, else the exit status (0 after --help, 2 on a usage error). */
int conform_parse_command_line(conform *c, int argc, char **argv);
/* Library, hosts, headless context and GL runtime; 0 on failure (diagnostics printed).
 * conform_close releases what conform_open made. */
int conform_open(conform *c);
void conform_close(conform *c);
/* Whether the registry holds a row of this name (a stage with rows of its own). */
int conform_has_row(const conform *c, const char *name);
/* A GL runtime on the context current in this thread, or else on a new 64x64 headless
 * one (*context, NULL when none was needed). NULL on failure: without a context *context
 * stays NULL and err says why; else the diagnostics do. */
halo_gl *conform_gl_current_or_headless(halo_headless **context, halo_diagnostics *diag, char *err, size_t size);

/* Adds sample index's n values to s: each passes within tolerance_abs + tolerance_rel
 * |emu| + condition[k] (condition may be NULL); a non-finite value counts once per
 * sample in nonfinite and not in the error. Returns 1 when a value is over. */
int row_stats_add(row_stats *s, size_t index, const double *gpu, const double *emu, const double *condition, int n,
                  double tolerance_abs, double tolerance_rel);
/* Adds one finite error of sample index to s; returns 1 when it is the largest so far. */
int row_stats_note(row_stats *s, size_t index, double error);
int row_selected(const conform *c, const char *row, const char *stage);
void print_header(void);
/* A row's line (stage max_abs rmse over_tol nonfinite tolerance PASS|FAIL) on stdout;
 * print_row also counts it in c. */
void print_row_line(const char *row, const row_stats *s, const char *tolerance, int pass);
void print_row(conform *c, const char *row, const row_stats *s, const char *tolerance, int pass);
/* A row that could not run (link or compile error): the diagnostics say why. */
void print_error_row(conform *c, const char *row);
/* Ends a row, after it freed the rest of what it made: its error row (print_error_row)
 * unless it printed its own line, the diagnostics cleared, its program and scene (either
 * may be NULL) destroyed. */
void conform_row_end(conform *c, const char *row, int printed, halo_program *program, halo_scene *scene);
/* Its line (dashes, FAIL; the tolerance column tolerance_width wide) and the diagnostics,
 * then cleared; counts nothing (for the families that keep their own counts). */
void print_error_row_line(const char *row, int tolerance_width, halo_diagnostics *diag);
/* A row without numbers (figure3): dashes, the tolerance text, the result. */
void print_plain_row(conform *c, const char *row, const char *tolerance, int pass);

/* ---- The probe's inputs ---- */

/* The relative input change that models the GPU's intermediate rounding (the
 * conditioning term of the tolerances, docs/accuracy.md). */
#define CONFORM_INPUT_PERTURBATION (1.0 / 2097152.0) /* 2^-21 */

/* Fills width x height samples: first every hard case (direction pairs x depths x
 * opacities, colours cycling), then random samples (fixed seed). Inputs are rounded to
 * the floats the probe uploads. */
void conform_fill_samples(halo_emu_sample *samples, int width, int height);
void conform_normalize3(double v[3]);
/* splitmix64: the next number in [0, 1) of the sequence *state (each row family keeps
 * its own fixed seed, so that every run draws the same inputs). */
double conform_random_uniform(uint64_t *state);
/* The inputs of a sample, the GPU's and the emulation's colour and opacity, on stderr. */
void conform_print_sample(const char *label, const halo_emu_sample *s, const float *gpu, const double *emu);
/* For a live variant: arrays get several elements (up to 4), including a zero vector
 * where the range allows it, so `<name>_count` and every element are used. */
void conform_set_live_arrays(halo_program *p, const halo_module *m, halo_diagnostics *diag);

/* ---- The example hosts in double (whole-render emulations) ---- */

/* The transfer texture lookup of the hosts' classify() (texels RGBA texels, linear,
 * clamped to the edge), in double. */
void conform_transfer_lookup(const float *transfer, int texels, double value, double rgba[4]);
/* The lookup texture(transfer, vec2(clamp(value, 0, 1), 0.5)) of the hosts in the styles of
 * the wild (no texel-centre correction: the edge texels cover half a texel more), in double. */
void conform_transfer_texture(const float *transfer, int texels, double value, double rgba[4]);
/* out = m v, m column-major (OpenGL's order). */
void conform_transform(const double m[16], const double v[4], double out[4]);
/* The ray of pixel (x, y) as the example hosts build it from inverse_view_projection:
 * its origin on the near plane and its unit direction. */
void conform_pixel_ray(const double inverse_view_projection[16], int width, int height, int x, int y, double origin[3],
                       double direction[3]);
/* The emulated frame of a host's program, begun, with halo_seed's image-plane axes set;
 * NULL when the program has no images, outputs or samplers (*ok stays 1) or on failure
 * (*ok 0, diagnostics in diag). */
halo_emu_frame *conform_host_frame(const halo_program *p, int width, int height, const double screen_right[3],
                                   const double screen_up[3], int *ok, halo_diagnostics *diag);

/* Premultiplied rgba (pixels x 4) over the background, as the hosts end a frame: alpha 1. */
void conform_over_background(double *rgba, size_t pixels, const double background[3]);
/* Fills in one pixel's ray of a whole-render emulation (x, y: the pixel; context: the caller's). */
typedef void conform_ray_init(void *context, int x, int y, void *ray);
/* conform_host_frame (*frame) and an array of width x height rays of ray_size bytes (x
 * fastest), each filled in by init, for a whole-render emulation; NULL on failure
 * (diagnostics in diag). */
void *conform_host_frame_rays(const halo_program *p, int width, int height, const double screen_right[3],
                              const double screen_up[3], size_t ray_size, conform_ray_init *init, void *context,
                              halo_emu_frame **frame, halo_diagnostics *diag);

/* ---- The frame probe ---- */

/* Sampler host uniforms of the frame rows (e.g. outline_feature's "labels"): a small
 * volume of integer labels, the same in GL (unit 15) and in the emulation; sampler2D
 * host uniforms get a 1x1 texture on unit 14. */
enum { PROBE_VOLUME_X = 5, PROBE_VOLUME_Y = 4, PROBE_VOLUME_Z = 3, PROBE_UNIT_3D = 15, PROBE_UNIT_2D = 14 };
const float *probe_label_volume(void);

typedef struct frame_probe {
    const halo_glfuncs *f;
    GLuint program, framebuffer, color, inputs[4], vertex_array;
    GLuint host_textures[2]; /* sampler3D, sampler2D host uniforms */
    int size;
    float *staging;
    halo_gl_frame *gl_frame; /* the frames of frame_probe_open (NULL after frame_probe_init) */
    halo_emu_frame *emu_frame;
} frame_probe;

/* The probe host (probe.frag) linked with p, c->size square. */
int frame_probe_init(conform *c, const halo_program *p, frame_probe *fp);
/* frame_probe_init after the GL and emulated frames of p, size x size (fp->gl_frame,
 * fp->emu_frame); 0 on failure, fp still to release (from a zeroed fp). */
int frame_probe_open(conform *c, const halo_program *p, int size, frame_probe *fp);
/* Releases the probe and the frames of frame_probe_open. */
void frame_probe_release(frame_probe *fp);
/* Draws one fragment per pixel from samples (c->size^2, row 0 at the bottom) with the
 * frame's outputs attached (blended into its images); rgba (may be NULL): colour read back. */
halo_status frame_probe_draw(conform *c, frame_probe *fp, const halo_program *p, halo_gl_frame *frame,
                             const halo_emu_sample *samples, float *rgba);
/* The image-plane axes the frame rows use, and the same host uniforms in the emulation. */
void host_axes(double right[3], double up[3]);
void emu_set_axes(halo_emu_frame *ef);
void emu_set_probe_volumes(const halo_program *p, halo_emu_frame *ef);

#endif
