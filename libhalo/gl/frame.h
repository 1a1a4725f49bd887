/* frame.c's accessors of a halo_gl_frame, for the segmented drawing in segments.c and the
 * one-draw field in field.c (which draw a host through the frame's images and passes), and
 * camera.c's plans. Internal. */
#ifndef HALO_GL_FRAME_H
#define HALO_GL_FRAME_H

#include "halo.h"
#include "internal.h"
#include "gl/glfuncs.h"
#include "gl/runtime.h" /* halo_gl_fetch_binding */

halo_gl *halo_gl_frame_runtime(const halo_gl_frame *fr);
const halo_program *halo_gl_frame_program(const halo_gl_frame *fr);
void halo_gl_frame_size(const halo_gl_frame *fr, int *width, int *height);
/* The ray-state texture: next 0, the one read by this segment; 1, the one it writes. */
unsigned halo_gl_frame_state(halo_gl_frame *fr, int next);
void halo_gl_frame_state_flip(halo_gl_frame *fr);
/* halo_gl_frame_draw's bracket (change 1 on entry, 0 on return; they nest): while a draw
 * runs, halo_gl_frame_destroy only asks; on the outermost return, whether it was asked.
 * change -1 only queries: -1 when a destroy was asked for. */
int halo_gl_frame_drawing(halo_gl_frame *fr, int change);
void halo_gl_frame_segments_reset(halo_gl_frame *fr);
/* Host contract 3, a frame that reuses its field: every image but the field's (read from
 * its stacks) back to its clear value, as halo_gl_frame_begin would. */
void halo_gl_frame_begin_host(halo_gl_frame *fr);

/* Host contract 3 (field.c): a one_draw program's stacks of the depth segments' images. */
typedef struct halo_gl_field halo_gl_field;
typedef struct halo_gl_frame_image {
    unsigned texture;    /* the current texture */
    int internal_format; /* its GL internal format */
    int width, height;
    int box[4]; /* x0, y0, x1, y1: outside it the texture holds 0 */
} halo_gl_frame_image;
/* The current texture of an image, without taking it from the frame's bookkeeping (unlike
 * halo_gl_frame_texture); 0 for an unknown or host image. */
int halo_gl_frame_image_view(const halo_gl_frame *fr, const char *name, halo_gl_frame_image *view);
halo_gl_field *halo_gl_frame_field(const halo_gl_frame *fr);
/* The frame keeps field (field.c makes it at the first draw), destroys it with destroy, and
 * counts its GPU memory with bytes (halo_gl_frame_info.gpu_bytes). */
void halo_gl_frame_set_field(halo_gl_frame *fr, halo_gl_field *field,
                             void (*destroy)(halo_gl_frame *fr, halo_gl_field *field),
                             size_t (*bytes)(const halo_gl_field *field));
/* halo_gl_frame_attach for the outputs of program p (the frame's, or its march); colour 0:
 * draw buffer 0 is GL_NONE. */
void halo_gl_frame_attach_outputs(halo_gl_frame *fr, const halo_program *p, unsigned framebuffer, int colour);
/* Blending per draw buffer (OpenGL 4.0, ES 3.2); else one switch for all (ES 3.0), which
 * halo_gl_frame_attach_outputs turns off for the host's outputs: the draw gives it back. */
int halo_gl_blend_per_buffer(const halo_glfuncs *f);
/* camera.c: the volume's box of a segments desc (all zero: the unit cube). */
void halo_segments_box(const halo_gl_segments_desc *d, double low[3], double high[3]);
/* camera.c: the checks of a segments desc (USAGE in diag, as function's). */
int halo_segments_desc_valid(const halo_gl_segments_desc *d, const char *function, halo_diagnostics *diag);
int halo_segments_arguments_valid(const void *object, const char *object_name, const halo_gl_segments_desc *d,
                                  const char *function, halo_diagnostics *diag);
/* camera.c: the camera uniforms of halo_view_at and halo_depth_at, from a plan. */
void halo_segment_camera_set(const halo_glfuncs *f, unsigned program, const halo_segment_plan *plan);
/* One frame: the field before the host draws, then the host drawn once (halo_gl_frame_draw);
 * the field is computed again only when what it depends on changed (field.c: field_key). */
halo_status halo_gl_field_draw(halo_gl_frame *fr, unsigned gl_program, const halo_gl_segments_desc *d,
                               halo_diagnostics *diag);
/* 1 where the frame reads its images back to bound them (halo_gl_desc.readback: by default
 * on a software renderer, whose cost is the pixels, not the draws). */
int halo_gl_frame_reads_back(const halo_gl_frame *fr);
/* Where the frame reads its images back to bound them (halo_gl_frame_set_readback_bounds):
 * box (x0 y0 x1 y1) shrunk to the nonzero pixels of the read framebuffer's colour
 * attachment 0 (an image of width x height, channels floats a pixel), 1; else 0, the box
 * unchanged. */
int halo_gl_frame_nonzero_box(halo_gl_frame *fr, int channels, int width, int height, int box[4]);
/* The format and type glTexImage takes with an internal format of the frame's images (R,
 * RG, RGBA at 8, 16 or 32 bits), and bytes a texel. */
void halo_gl_image_upload_format(GLint internal, GLenum *format, GLenum *type);
size_t halo_gl_image_texel_bytes(GLint internal);
/* Pass index of p's reflection compiled and linked (vertex_source NULL: the pass's own;
 * define: a name #defined in its fragment shader, or NULL; counting its fetches where
 * the runtime does: halo_gl_desc.count_fetches), its inputs' samplers set to units 0, 1,
 * ... (the program is left current); 0 after a diagnostic in diag. */
GLuint halo_gl_pass_build(const halo_gl *gl, const halo_program *p, size_t index, const char *vertex_source,
                          const char *define, halo_diagnostics *diag);
/* The image a pass reads as its input k at repetition rep (the frame's and the atlas's rule):
 * `named`, the input's own image index; for "previous" (named < 0), `first` at the first
 * repetition drawn (start) where the pass has one (>= 0), else its output. */
int halo_gl_pass_input(int named, int rep, int start, int first, int output);
/* A pass program's repetition uniforms (halo_pass_index, halo_pass_count; -1: unused). */
void halo_gl_pass_repetition(const halo_glfuncs *f, GLint index_location, GLint count_location, int rep, int repeat);
/* Pass draws made outside frame.c (field_atlas.c), counted as the frame's (its info). */
void halo_gl_frame_count_pass_draws(halo_gl_frame *fr, long draws);
/* Around pass draws (frame.c, field_atlas.c): with halo_gl_desc.count_fetches the frame's
 * counter bound and zeroed, then read into its pass_fetches and the binding put back;
 * otherwise nothing. */
void halo_gl_frame_fetches_begin(halo_gl_frame *fr, halo_gl_fetch_binding *saved);
void halo_gl_frame_fetches_end(halo_gl_frame *fr, const halo_gl_fetch_binding *saved);
/* The fields a one-draw frame has computed (its draws that reused the field are not counted). */
int halo_gl_field_computed(const halo_gl_frame *fr);

#endif
