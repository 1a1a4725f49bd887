/* Conformance of segmented ray casting (host contract 2): the emulation of raycast.frag
 * and of the hosts in the styles of the wild (examples/hosts/) drawn by
 * halo_gl_frame_draw in depth segments (conform_segment.c). */
#ifndef HALO_CONFORM_SEGMENT_H
#define HALO_CONFORM_SEGMENT_H

#include "conform_harness.h"
#include "halo.h"
#include "hosts/raycast.h"

/* How a host classifies and shades a sample. */
typedef enum conform_segment_shading {
    CONFORM_SHADE_TRANSFER, /* the transfer function's colour and opacity */
    CONFORM_SHADE_TF2D,     /* tf2d_caster.frag: value x |g| transfer function, Phong headlight */
    CONFORM_SHADE_ISO,      /* mip_iso_caster.frag: opaque at and above its iso value, diffuse */
    CONFORM_SHADE_MIP       /* its MIP variant: the ray's largest value, classified once, no stage */
} conform_segment_shading;

/* What the emulation models of a host: where the example hosts differ from raycast.frag
 * (conform_segment_raycast; the others are conform_segment_webgl, _exit_points, _tf2d,
 * _iso and _mip). */
typedef struct conform_segment_host {
    const char *file;   /* an embedded example host */
    halo_target target; /* the target it is linked for and drawn with */
    conform_segment_shading shading;
    double threshold;       /* early ray termination at this accumulated opacity ... */
    int strict_threshold;   /* ... reached (>=), or passed (>) */
    int counted_steps;      /* ceil((t_exit - t_first) / step) samples, else those with t <= t_exit */
    int centred_lookup;     /* the transfer table read at texel centres, else texture(tf, vec2(v, 0.5)) */
    int derived_view;       /* halo_view_at (the frame's camera), else normalize(eye - P) */
    int derived_depth;      /* halo_depth_at (planar), else the distance to the eye (radial) */
    int opacity_correction; /* 1 - (1 - a)^(step / unit_step), else a as it is */
    int exit_points;        /* two passes: the exit from a texture of the box's back faces */
} conform_segment_host;

extern const conform_segment_host conform_segment_raycast, conform_segment_webgl, conform_segment_exit_points,
    conform_segment_tf2d, conform_segment_iso, conform_segment_mip;

/* The host and the values of the decisions that a row brackets: the termination
 * threshold, every ray's exit and the isosurface value, each moved by a small amount. */
typedef struct conform_segment_model {
    const conform_segment_host *host; /* NULL: raycast.frag */
    double jitter;                    /* the uniform `jitter` (webgl_caster.frag) */
    double threshold_move, exit_move, iso_move;
    double layer_move; /* the phi of the planes between segments (one_draw: the stack layer a
                        * sample reads), moved by this */
    int layer_pattern; /* 0: every plane moved the same way; p > 0: plane b moved by
                        * -layer_move where bit p - 1 of b is 0 (each plane's decision is
                        * its own float rounding, not one direction for all) */
} conform_segment_model;

/* The depth segments of a frame as docs/host-contract.md defines them, derived here from the
 * contract, apart from the runtime's own plan (so a row checks the runtime's planes too):
 * phi(P) = dot(plane.xyz, P) + plane.w grows away from the eye; the planes phi = front +
 * k step from the front of the box's bounding sphere; segment j takes the samples with
 * start + j length <= phi < start + (j + 1) length. */
typedef struct conform_segment_plan {
    double eye[4];      /* the eye (w = 1), or the unit direction towards the viewer (w = 0) */
    double plane[4];    /* |xyz| = 1 */
    double front, back; /* phi at the front and back of the unit box's bounding sphere */
    int segments;       /* 1: drawn once */
    double start, length;
} conform_segment_plan;
/* The plan of a host drawn with this camera (clip space -> volume texture space, as the
 * host hands it: float) and step, in `segments` (0: as the program asks). 0 for a camera
 * that cannot be inverted. */
int conform_segment_plan_make(const float inverse_view_projection[16], float step, int segments, const halo_program *p,
                              conform_segment_plan *plan);

/* The frame of the model's host drawn by the plan (conform_segment_plan_make with the state's
 * camera and step), in double: out gets width*height*4 values over the background.
 * Returns 0 with diagnostics (a stage without emulation, out of memory). */
int halo_conform_segment_emulate(const halo_raycast_state *s, const halo_program *p, const conform_segment_plan *plan,
                                 const conform_segment_model *model, double *out, halo_diagnostics *diag);

/* A row: a host (NULL: raycast.frag) with the scene; segments > 0: linked with
 * force_segments and drawn in exactly that many, against the same host in one draw;
 * 0: drawn as the program needs, against the emulation. --stage segments selects them all. */
typedef struct conform_segment_params {
    const char *scene;
    int segments, orthographic;
    const conform_segment_host *host;
    float jitter;
    int one_draw;    /* linked with one_draw (host contract 3): the field before the one draw, its march's
                   * gradient of this precision (32 or 16: halo_gl_segments_desc.gradient_precision) */
    int image_scale; /* halo_link_desc.image_scale (0: 1); with one_draw, the march at that scale too */
} conform_segment_params;
void conform_segment_row(conform *c, const conform_row *row);

#endif
