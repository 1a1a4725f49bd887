/* The C side of the example hosts: the GPU ray caster (raycast.vert/raycast.frag) and
 * the conformance probe (probe.frag). Not part of the installed libhalo: the examples,
 * halo-validate and the tests link it from a convenience library.
 *
 * Every GL call goes through a halo_glfuncs table; the caller's context must be
 * current (see libhalo/gl/headless.h for one without a window). */
#ifndef HALO_EXAMPLE_RAYCAST_H
#define HALO_EXAMPLE_RAYCAST_H

#include "halo.h"
#include "halo_gl_loader.h"

/* ---- Host shader texts ------------------------------------------------------- */

/* The text of an example host shader embedded at build time ("raycast.frag",
 * "raycast.vert", "probe.frag"), or NULL. */
const char *halo_host_embedded(const char *name);
/* A copy (free() it) of the file at override_path when given, else of the embedded
 * host `name`; NULL with an IO_READ diagnostic when neither exists. */
char *halo_host_load(const char *name, const char *override_path, halo_diagnostics *diag);
/* The MIP variant of mip_iso_caster.frag (a copy to free()): its two commented mode lines,
 * `#define MIP` and `#pragma halo compositing mip`, switched on; NULL when the text has
 * no such lines or memory runs out. */
char *halo_host_mip_variant(const char *source);

/* ---- Programs ------------------------------------------------------------------ */

typedef struct halo_host_desc {
    const halo_glfuncs *gl;      /* required; the context must be current */
    halo_gl *runtime;            /* required with program */
    const halo_program *program; /* the host linked by halo_link, or NULL ... */
    const char *fragment_source; /* ... for this unlinked text (default: the embedded host) */
    const char *fragment_file;   /* for diagnostics (default: the host's name) */
    const char *vertex_source;   /* default: the embedded raycast.vert */
    const char *vertex_file;     /* default "raycast.vert" */
    int width, height;           /* render target size, required */
} halo_host_desc;

/* ---- The ray caster -------------------------------------------------------------- */

typedef struct halo_raycast halo_raycast;

/* The values the ray caster's shader runs with, for an emulation of it. The matrix
 * and vectors hold exactly the float values uploaded. */
typedef struct halo_raycast_state {
    int width, height;
    double inverse_view_projection[16];   /* column-major, clip space -> volume texture space */
    double eye[3];                        /* volume texture space */
    double screen_right[3], screen_up[3]; /* unit image-plane axes (host uniforms of halo_seed) */
    double step_size;                     /* texture units */
    double unit_step;                     /* the step transfer opacities are given for (one voxel) */
    double background[3];
    int transfer_texels;   /* HALO_RAYCAST_TRANSFER_TEXELS */
    const float *transfer; /* transfer_texels RGBA texels as uploaded */
    int dims[3];           /* volume size in voxels */
    const float *volume;   /* the values uploaded (x fastest), NULL before upload */
} halo_raycast_state;

#define HALO_RAYCAST_TRANSFER_TEXELS 256
/* Field of view across the smaller image side at zoom 1, in degrees. */
#define HALO_RAYCAST_FIELD_OF_VIEW   30.0

/* Builds the program (linked or raw) and the render target. Returns NULL with
 * diagnostics (GL_COMPILE, GL_LINK, OUT_OF_MEMORY, USAGE) on failure. */
halo_raycast *halo_raycast_create(const halo_host_desc *desc, halo_diagnostics *diag);
void halo_raycast_destroy(halo_raycast *r);
/* Uploads a volume of values already normalized to [0,1] (x fastest); the ray
 * caster keeps a reference to data for halo_raycast_get_state (an emulation reads it
 * there; rendering does not): keep it alive while get_state's volume is read. */
halo_status halo_raycast_set_volume(halo_raycast *r, const float *data, int nx, int ny, int nz, halo_diagnostics *diag);
/* Transfer function (control points linearly interpolated into a 256-texel table;
 * none: a grey ramp), background and step (voxels; <= 0 means 0.5) from a scene's
 * render settings. */
halo_status halo_raycast_set_render(halo_raycast *r, const halo_render_settings *settings, halo_diagnostics *diag);
/* Perspective camera looking at the volume centre from azimuth (about +y, 0 = on
 * the +z side) and elevation (degrees); zoom 1 fits the bounding sphere in view. */
void halo_raycast_set_camera(halo_raycast *r, double azimuth, double elevation, double zoom);
/* Renders into the RGBA32F target and reads it back: width*height*4 floats, rows
 * bottom-up, premultiplied colour over the background; for a program with at=post passes
 * (outlines), their result (halo_host_post_image). */
halo_status halo_raycast_render(halo_raycast *r, float *rgba, halo_diagnostics *diag);
void halo_raycast_get_state(const halo_raycast *r, halo_raycast_state *state);
/* The image the program's last at=post pass writes (outlines: "final"), or NULL. */
const halo_image_info *halo_host_post_image(const halo_program *p);
/* Runs the at=post passes (outlines) on the host's colour (color_texture: RGBA, over the
 * background, the frame's size); rgba (width*height*4) becomes their last image (an image
 * of fewer than three channels: grey levels of its largest channel). HALO_OK without
 * such passes. */
halo_status halo_host_post_passes(halo_gl_frame *frame, const halo_program *p, unsigned color_texture, int width,
                                  int height, float *rgba, halo_diagnostics *diag);
/* The frame of a program with images, outputs or segments (host contract 2), else NULL. */
halo_gl_frame *halo_raycast_frame(const halo_raycast *r);
/* Segments (host contract 2): M planes per segment (0: the program's halo_generate.interval,
 * or 4), or exactly `segments` of them (> 0: a program linked with force_segments). */
void halo_raycast_set_segments(halo_raycast *r, int interval, int segments);
/* An orthographic camera for the next halo_raycast_set_camera (default: perspective). */
void halo_raycast_set_orthographic(halo_raycast *r, int orthographic);
/* Host contract 3 (a program linked with one_draw): the march's empty-space bound
 * (halo_gl_segments_desc.seed_epsilon; default 0, exact). */
void halo_raycast_set_seed_epsilon(halo_raycast *r, float epsilon);
/* ... and the precision of the gradient libhalo derives for its march
 * (halo_gl_segments_desc.gradient_precision: 32, 16, or 0, the default). */
void halo_raycast_set_gradient_precision(halo_raycast *r, int bits);
/* ... and a piece of a distributed volume (halo_gl_segments_desc.piece_min, _max,
 * exchange): the march reads this piece (nx * ny * nz values, x fastest; copied to a
 * texture) covering piece_min..piece_max of the volume's texture space, while the host
 * still draws the whole volume of halo_raycast_set_volume; exchange is called once a frame
 * with the seeds. data or exchange NULL: no piece. */
halo_status halo_raycast_set_piece(halo_raycast *r, const float *data, int nx, int ny, int nz, const float piece_min[3],
                                   const float piece_max[3],
                                   void (*exchange)(void *user, float *values, size_t count, halo_blend blend),
                                   void *user, halo_diagnostics *diag);
/* The most bytes one exchange call carries (halo_gl_segments_desc.exchange_max_bytes;
 * 0: libhalo's default). */
void halo_raycast_set_exchange_max_bytes(halo_raycast *r, size_t bytes);
/* The cap on a one-draw frame's halo field (halo_gl_segments_desc.field_max_bytes; 0:
 * libhalo's default). */
void halo_raycast_set_field_max_bytes(halo_raycast *r, size_t bytes);
/* A host that leaves its GL state untidy (tests/libhalo/gl/test_segments, issue 26): with
 * untidy set, the host's draw sets the state it needs itself (no culling, depth, stencil,
 * blending, scissor or rasterizer discard, filled polygons, every colour written) and
 * afterwards calls untidy(user, 0), which may leave any state for the libhalo calls that
 * follow; before each of its draws it calls untidy(user, 1) (where the switches can be
 * checked: libhalo binds the host's program, framebuffer and textures for the draw), and
 * when halo_gl_frame_draw has returned untidy(user, 2) (all of it given back). NULL: off. */
void halo_raycast_set_untidy(halo_raycast *r, void (*untidy)(void *user, int before_draw), void *user);
/* The uniform `jitter` of a host that jitters its first sample (webgl_caster.frag; default 0). */
void halo_raycast_set_jitter(halo_raycast *r, float jitter);
/* Two-pass hosts (exit_point_caster.frag): from now on each render first draws the
 * volume box's back faces into a texture of texture-space exit points, bound to unit 2
 * as the uniform `exit_points` (xyz, a = 1 where the box covers the pixel). */
halo_status halo_raycast_set_exit_points(halo_raycast *r, halo_diagnostics *diag);
/* Hosts that classify before they interpolate (niivue_caster.frag): colour and opacity per
 * voxel (nx * ny * nz RGBA texels as floats in [0,1], x fastest; stored RGBA8, filtered
 * linearly), bound to unit 3 as the uniform `color_volume` from now on. */
halo_status halo_raycast_set_classified(halo_raycast *r, const float *rgba, int nx, int ny, int nz,
                                        halo_diagnostics *diag);
/* Another renderer's camera instead of the orbit camera (a viewer's, to draw what it drew):
 * inverse_view_projection (column-major, clip space -> volume texture space), and the step
 * in texture units (> 0; else the render settings' step stays). The screen axes are the
 * directions clip +x and +y map to; the eye, for a perspective camera, the point clip
 * (0, 0, 1, 0) maps to, for an orthographic one a point ten units back from the volume's
 * centre against the view. Until the next halo_raycast_set_camera. */
void halo_raycast_set_view(halo_raycast *r, const double inverse_view_projection[16], double step);
unsigned halo_raycast_gl_program(const halo_raycast *r);

/* ---- The conformance probe ----------------------------------------------------- */

typedef struct halo_probe halo_probe;

/* As halo_raycast_create, with probe.frag as the default fragment host. */
halo_probe *halo_probe_create(const halo_host_desc *desc, halo_diagnostics *diag);
void halo_probe_destroy(halo_probe *p);
/* One sample per pixel (width*height of them, row y at samples[y*width]; pixel (x,y)
 * has gl_FragCoord (x+0.5, y+0.5)): uploads position, value, gradient, depth, view,
 * colour and opacity as float, renders probe.frag and reads back colour and opacity
 * (width*height*4 floats). */
halo_status halo_probe_run(halo_probe *p, const halo_emu_sample *samples, float *rgba, halo_diagnostics *diag);
/* Rounds the host-filled fields of s to the floats halo_probe_run uploads and sets
 * fragcoord to the pixel centre, so an emulation sees exactly the GPU's inputs. */
void halo_probe_round_inputs(halo_emu_sample *s, int x, int y);

#endif
