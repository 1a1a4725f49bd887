/* Shared between halo-validate conform's files (conform.c, conform_outline.c): the
 * conformance context, row printing and the frame probe (a per-sample stage drawn once
 * per pixel through a GL frame, docs/accuracy.md). Not installed. */
#ifndef HALO_CONFORM_INTERNAL_H
#define HALO_CONFORM_INTERNAL_H

#include "halo.h"
#include "gl/glfuncs.h"
#include "gl/headless.h"

#include <stddef.h>

typedef struct row_stats {
    double max_abs, sum_squares;
    size_t values, over, nonfinite;
    size_t worst; /* sample index of max_abs */
} row_stats;

typedef struct conform {
    halo_library *lib;
    halo_headless *context;
    halo_gl *runtime;
    const halo_glfuncs *gl;
    halo_diagnostics *diag;
    int size, verbose;
    const char *only;
    int rows, failures, errors;
} conform;

int row_selected(const conform *c, const char *row, const char *stage);
void print_row(conform *c, const char *row, const row_stats *s, const char *tolerance, int pass);
/* A row that could not run (link or compile error): the diagnostics say why. */
void print_error_row(conform *c, const char *row);

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
} frame_probe;

/* The probe host (probe.frag) linked with p, c->size square. */
int frame_probe_init(conform *c, const halo_program *p, frame_probe *fp);
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
