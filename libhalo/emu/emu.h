/* Internal interface of the C emulation: one function per stage, in double precision,
 * computing the paper's formula with exactly the guards the GLSL module applies. */
#ifndef HALO_EMU_H
#define HALO_EMU_H

#include "halo.h"

struct halo_program_stage; /* internal.h: halo_linked_stage */

/* A stage's current parameter values, looked up by the name used in the module, and the
 * frame (images, host uniforms) the stage runs in: NULL for plain halo_emu_apply, where
 * images read as 0 and host uniforms as zero vectors (as unset GL uniforms). */
typedef struct halo_emu_params {
    const halo_program *program;
    const struct halo_program_stage *stage;
    halo_emu_frame *frame;
} halo_emu_params;

/* Returns the values (count elements of the parameter's components each) or NULL. */
const double *halo_emu_param(const halo_emu_params *p, const char *name, int *count);
/* The first component of a scalar parameter (0 if absent). */
double halo_emu_scalar(const halo_emu_params *p, const char *name);
/* Element h of a per-halo parameter (`channels`, or an array named in per_halo): its
 * components, the last element where h is beyond the list (as the linker extends it);
 * NULL if absent. Mirrors halo_channel(v, h) and v[h]. */
const double *halo_emu_channel_param(const halo_emu_params *p, const char *name, int h);
/* halo_channel(v, h) of a `channels` parameter (0 if absent). */
double halo_emu_channel(const halo_emu_params *p, const char *name, int h);
/* halo_channel_count: the program's channel count, 1..4. */
int halo_emu_channel_count(const halo_emu_params *p);

/* halo_read_NAME(fragcoord): the image's value at the pixel ivec2(fragcoord) (truncated
 * as GLSL does), 0 outside the image or without a frame. Writes 4 values (channels
 * beyond the program's count are 0). */
void halo_emu_read_image(const halo_emu_params *p, const char *name, const double fragcoord[2], double out[4]);
/* halo_host_NAME (short name): up to 4 components, zeros when unset or without a frame. */
const double *halo_emu_host_uniform(const halo_emu_params *p, const char *name);

typedef void (*halo_emu_stage_fn)(halo_emu_sample *s, const halo_emu_params *p);

/* The emulation of stage `name`, or NULL. Table in emu/registry.c. */
halo_emu_stage_fn halo_emu_lookup(const char *name);

/* ---- Image passes (docs/image-passes.md) ---- */

/* What a pass entry sees: its stage's parameters, its inputs (width * height * channels
 * doubles each, row 0 at the bottom, in the order of the pass's `inputs=`), and the
 * repetition (halo_pass_index 1..halo_pass_count). */
typedef struct halo_emu_pass_context {
    const halo_emu_params *params;
    int width, height, channels;
    int pass_index, pass_count;
    int input_count;
    const double *inputs[HALO_MAX_PASS_INPUTS];
    int input_components[HALO_MAX_PASS_INPUTS]; /* per input: its image's components */
    int pass_channel;                           /* halo_pass_channel (each=channel passes) */
    int scale;                                  /* halo_pass_scale: the output is 1/scale of the frame */
    int input_width[HALO_MAX_PASS_INPUTS], input_height[HALO_MAX_PASS_INPUTS];
    int input_down[HALO_MAX_PASS_INPUTS]; /* input larger by this: max over the block */
    int input_up[HALO_MAX_PASS_INPUTS];   /* input smaller by this: its pixel / up */
} halo_emu_pass_context;

/* halo_input(k, pixel) / halo_input4 for one component: 0 outside the image (zero
 * padding) and beyond the image's components; an input larger than the output gives the
 * max over the pixel's block, a smaller one its pixel / up (docs/image-passes.md). */
double halo_emu_input(const halo_emu_pass_context *c, int k, int x, int y, int channel);

/* A sampler3D host uniform given by halo_emu_frame_set_volume (NULL if unset). */
const float *halo_emu_host_volume(const halo_emu_params *p, const char *name, int dims[3]);
/* Folds the sample's output fields into its accumulators (halo_apply's epilogue). */
halo_status halo_emu_frame_fold(const halo_program *p, halo_emu_sample *s, halo_diagnostics *diag);

/* One pass entry at pixel (x, y): writes the pixel's `channels` values to out. */
typedef void (*halo_emu_pass_fn)(const halo_emu_pass_context *c, int x, int y, double out[4]);

/* The emulation of entry `entry` of image module `module`, or NULL (emu/registry.c). */
halo_emu_pass_fn halo_emu_lookup_pass(const char *module, const char *entry);

/* Guards shared with glsl/halo_math.glsl; each mirrors the GLSL helper of the same name. */
double halo_emu_pow(double x, double e);
double halo_emu_saturate(double x);
double halo_emu_clamp(double x, double lo, double hi);
void halo_emu_normalize(const double v[3], double out[3]);
double halo_emu_dot(const double a[3], const double b[3]);
double halo_emu_mix(double a, double b, double t);
void halo_emu_rgb_to_hsv(const double rgb[3], double hsv[3]);
void halo_emu_hsv_to_rgb(const double hsv[3], double rgb[3]);

#endif
