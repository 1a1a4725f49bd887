/* The slice host (slice.vert/slice.frag): view-aligned slices composited front to back,
 * as Bruckner & Groller 2007 render volumetric halos, and the slab ray caster
 * (slab.frag, slab.h) that advances every ray by M samples per draw. Not part of the
 * installed libhalo; every GL call goes through a halo_glfuncs table and the caller's
 * context must be current.
 *
 * Slices are planes perpendicular to the view axis, step voxels apart, from the front
 * of the volume's bounding sphere to its back. Per slice one full-screen draw: every
 * fragment samples where its pixel's ray meets the plane, runs halo_apply once and
 * halo_finish, and is blended front to back into colour buffer 0; the seed output is
 * blended into the seed image (halo_gl_frame_attach). After every M-th slice the
 * halo images are regenerated (halo_gl_frame_generate). */
#ifndef HALO_EXAMPLE_SLICE_H
#define HALO_EXAMPLE_SLICE_H

#include "hosts/raycast.h"

typedef struct halo_slice halo_slice;

/* The values the shaders run with, for an emulation: float values as uploaded. */
typedef struct halo_slice_state {
    int width, height;
    double inverse_view_projection[16];   /* column-major, clip space -> volume texture space */
    double eye[3];                        /* volume texture space */
    double view_axis[3];                  /* unit, from the eye into the scene */
    double screen_right[3], screen_up[3]; /* unit image-plane axes (host uniforms of halo_seed) */
    double first_distance;                /* plane of slice 0 along the view axis, from the eye */
    int slice_count;                      /* slice k at first_distance + k * step_size */
    double step_size;                     /* texture units */
    double unit_step;                     /* one voxel: the step transfer opacities are given for */
    int interval;                         /* M: slices between two generations (slab: samples per draw) */
    int slab;                             /* 1: the slab ray caster */
    double background[3];
    int transfer_texels;
    const float *transfer;
    int dims[3];
    const float *volume;
} halo_slice_state;

/* desc as for halo_raycast_create; the default shaders are slice.frag and slice.vert.
 * A program with extra outputs, images or passes gets a halo_gl_frame of the render
 * size (GL 4.0 per-buffer blending required: GL_PROC_MISSING otherwise). */
halo_slice *halo_slice_create(const halo_host_desc *desc, halo_diagnostics *diag);
void halo_slice_destroy(halo_slice *s);
/* As halo_raycast_set_volume / _set_render / _set_camera (same camera). The gradient
 * texture exists only when a linked stage reads the gradient (halo_slice_reads_gradients);
 * where the GL renders into its format it is built on the GPU from the volume texture at
 * the next render (halo_host_build_gradients), otherwise by set_volume on the CPU in
 * slabs. data is read by set_volume and handed out again by halo_slice_get_state (for an
 * emulation): free it after set_volume when neither is called again. */
int halo_slice_reads_gradients(const halo_slice *s);
/* How the gradient texture stores the voxels' central differences (per voxel step of
 * the [0,1] value, |g| <= 0.5 a component): 0 is the default, HALO_GRADIENT_FORMAT_DEFAULT. */
typedef enum halo_gradient_format {
    HALO_GRADIENT_DEFAULT = 0,
    HALO_GRADIENT_FLOAT,    /* RGB32F, 12 bytes a voxel: the exact floats */
    HALO_GRADIENT_HALF,     /* RGB16F, 6 (llvmpipe: 8) bytes a voxel, 11 significant bits (scaled when |g| > 1) */
    HALO_GRADIENT_SNORM8,   /* RGB8_SNORM, 3 (llvmpipe: 4) bytes a voxel, g / the volume's largest |component| */
    HALO_GRADIENT_PACKED16, /* RGBA16_SNORM holding the value too (the volume texture is dropped): 8 bytes a voxel for
                             * both, 16 bits each, one fetch for value and gradient (halo_host_build_packed) */
    HALO_GRADIENT_PACKED32, /* RGBA32F holding the value too: 16 bytes a voxel for both, floats, one fetch */
    HALO_GRADIENT_FORMAT_COUNT
} halo_gradient_format;
#define HALO_GRADIENT_FORMAT_DEFAULT HALO_GRADIENT_HALF
/* "float", "half", "snorm8"; NULL for another value. */
const char *halo_gradient_format_name(halo_gradient_format format);
/* The format named text, HALO_GRADIENT_FORMAT_COUNT for an unknown name. */
halo_gradient_format halo_gradient_format_from_name(const char *text);
/* The tools' --gradient-format value: 1 with *format set, or 0 with "--gradient-format:
 * 'TEXT' is not float, half or snorm8" in err. */
int halo_gradient_format_option(const char *text, halo_gradient_format *format, char *err, size_t errlen);
/* Whether a frame skips the work it can skip exactly (on by default): generations when no
 * slice since the last one met the volume and the halo images are still zero, and, on a
 * software renderer, the pixels of each pass that stay zero (the seeds' box grown by the
 * passes' reach: halo_gl_frame_set_readback_bounds), and the slice host's pixels whose
 * samples are empty: each slice is scissored to its plane's section of the volume (with
 * the box where the halo images read can be nonzero, halo_gl_frame_info.read_box) when
 * every linked per-sample stage leaves an empty sample empty, and the colour of a program
 * with feature groups, written in the first group's pass only. docs/performance.md,
 * "Work skipped". Off runs every generation and draws every slice and pass over the
 * whole image, for measuring. */
void halo_slice_set_generation_skip(halo_slice *s, int on);
/* Takes effect at the next set_volume; an unknown value means the default. */
void halo_slice_set_gradient_format(halo_slice *s, halo_gradient_format format);
/* The effective format (never HALO_GRADIENT_DEFAULT). */
halo_gradient_format halo_slice_gradient_format(const halo_slice *s);
halo_status halo_slice_set_volume(halo_slice *s, const float *data, int nx, int ny, int nz, halo_diagnostics *diag);
halo_status halo_slice_set_render(halo_slice *s, const halo_render_settings *settings, halo_diagnostics *diag);
void halo_slice_set_camera(halo_slice *s, double azimuth, double elevation, double zoom);
/* A segmentation on the volume's grid (label ids as floats, nx*ny*nz, x fastest), bound
 * as the host uniform "labels" (outline_feature's label features) on texture unit
 * HALO_SLICE_LABEL_UNIT while rendering. NULL data (and the default, for a program
 * that declares "labels") is a segmentation where no voxel has a label id (>= 0). */
#define HALO_SLICE_LABEL_UNIT    15
/* The precomputed gradients (set_volume) are on this unit while rendering. */
#define HALO_SLICE_GRADIENT_UNIT 14
halo_status halo_slice_set_labels(halo_slice *s, const float *labels, int nx, int ny, int nz, halo_diagnostics *diag);
/* M, the slices between two halo generations (slab caster: samples per draw). 0 (the
 * default) takes the program's halo_generate.interval, or 4 (the paper's) when the
 * program has none. */
void halo_slice_set_interval(halo_slice *s, int interval);
int halo_slice_interval(const halo_slice *s);
/* The cap on the halo field of a frame drawn over it (one_draw: halo_gl_segments_desc.
 * field_max_bytes; 0: libhalo's default). */
void halo_slice_set_field_max_bytes(halo_slice *s, size_t bytes);
/* Progress of a render: after each slice (slab caster: each slab) is drawn, and the
 * halo images regenerated where due, fn(done, total, user) with done = 1..total, the
 * slices (slabs) drawn so far and in all. The draws are queued, not necessarily
 * executed: fn may call glFinish before reporting. fn must not change the GL state.
 * NULL (the default) reports nothing. */
typedef void (*halo_slice_progress_fn)(int done, int total, void *user);
void halo_slice_set_progress(halo_slice *s, halo_slice_progress_fn fn, void *user);
/* For tests of libhalo's runtime (issue 26): untidy(user, 0) before each call of the
 * halo_gl_frame functions that neither depend on the host's GL state nor change it
 * (begin, begin_group, generate, end_group, read_region), and untidy(user, 1) when it has
 * returned. The hook may leave any state at 0 and must give the host's back at 1. NULL:
 * off. */
void halo_slice_set_untidy(halo_slice *s, void (*untidy)(void *user, int returned), void *user);
/* Renders and reads back width*height*4 floats, rows bottom-up, premultiplied colour
 * composited over the background (alpha 1). */
halo_status halo_slice_render(halo_slice *s, float *rgba, halo_diagnostics *diag);
void halo_slice_get_state(const halo_slice *s, halo_slice_state *state);
unsigned halo_slice_gl_program(const halo_slice *s);
/* The halo images (NULL for a program without them): halo_gl_frame_read, _pass_draws. */
halo_gl_frame *halo_slice_frame(const halo_slice *s);
/* Draws of the last render: slices (or slabs), and image passes. */
long halo_slice_draws(const halo_slice *s);
long halo_slice_pass_draws(const halo_slice *s);

/* Internal: shared by halo_slice_create and halo_slab_create (slab.h). */
halo_slice *halo_slice_create_mode(const halo_host_desc *desc, int slab, halo_diagnostics *diag);

#endif
