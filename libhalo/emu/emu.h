/* Internal interface of the C emulation: one function per stage, in double precision,
 * computing the paper's formula with exactly the guards the GLSL module applies. */
#ifndef HALO_EMU_H
#define HALO_EMU_H

#include "halo.h"

/* A stage's current parameter values, looked up by the name used in the module. */
typedef struct halo_emu_params halo_emu_params;

/* Returns the values (count elements of the parameter's components each) or NULL. */
const double *halo_emu_param(const halo_emu_params *p, const char *name, int *count);
/* The first component of a scalar parameter (0 if absent). */
double halo_emu_scalar(const halo_emu_params *p, const char *name);

typedef void (*halo_emu_stage_fn)(halo_emu_sample *s, const halo_emu_params *p);

/* The emulation of stage `name`, or NULL. Table in emu/registry.c. */
halo_emu_stage_fn halo_emu_lookup(const char *name);

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
