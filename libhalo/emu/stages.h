/* The per-sample and line stage emulations (one file each in emu/), and the few guards they share
 * beyond emu.h. Internal: not installed. */
#ifndef HALO_EMU_STAGES_H
#define HALO_EMU_STAGES_H

#include "emu.h"

/* A per-sample or line stage's emulation, defined in its own file as HALO_EMU_STAGE(name) { ... }
 * at the start of a line, the file listed in libhalo/local.mk's halo_emu_stage_files:
 * the registry's list is generated from those definitions (build-aux/emu_registry.sh),
 * so adding a stage touches no other place of the emulation. */
#define HALO_EMU_STAGE(name) void halo_emu_##name(halo_emu_sample *s, const halo_emu_params *p)

/* The image passes of halo_generate (emu/halo_generate.c). */
void halo_emu_halo_generate_median(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_halo_generate_gradient(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_halo_generate_spread(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_halo_generate_spread_seed(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_halo_generate_spread_on(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_halo_generate_spread_wide(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_halo_generate_occlusion(const halo_emu_pass_context *c, int x, int y, double out[4]);

/* Outlines (emu/outline.c): the feature buffers and the passes of glsl/outline/outline.glsl. */
void halo_emu_outline_blur_x(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_outline_blur_y(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_outline_min_x(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_outline_min_y(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_outline_normal_blur_x(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_outline_normal_blur_y(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_outline_importance(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_outline_reduce(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_outline_compose(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_outline_final_blur_x(const halo_emu_pass_context *c, int x, int y, double out[4]);
void halo_emu_outline_final_blur_y(const halo_emu_pass_context *c, int x, int y, double out[4]);

/* Mirrors halo_dot_clamped: the dot product clamped to [-1, 1] (emu/math.c). */
double halo_emu_dot_clamped(const double a[3], const double b[3]);

/* The GLSL test `v == vec3(0.0)`: a normal from halo_normalize is exactly zero when the
 * gradient has no direction. */
static inline int halo_emu_is_zero3(const double v[3]) { return v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0; }

#endif
