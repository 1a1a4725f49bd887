/* The stage emulations (per-sample, line and image-pass stages, in files of emu/) and
 * the few guards they share beyond emu.h. Internal: not installed. */
#ifndef HALO_EMU_STAGES_H
#define HALO_EMU_STAGES_H

#include "emu.h"

/* A per-sample or line stage's emulation, defined in its own file as HALO_EMU_STAGE(name) { ... }
 * at the start of a line, the file listed in libhalo/local.mk's halo_emu_stage_files:
 * the registry's list is generated from those definitions (build-aux/emu_registry.sh),
 * so adding a stage touches no other place of the emulation. */
#define HALO_EMU_STAGE(name) void halo_emu_##name(halo_emu_sample *s, const halo_emu_params *p)

/* An image pass's emulation (entry `entry` of image module `module`), defined as
 * HALO_EMU_PASS(module, entry) { ... } at the start of a line in a file of that list: the
 * registry's pass table is generated from those definitions too. */
#define HALO_EMU_PASS(module, entry) \
    void halo_emu_##module##_##entry(const halo_emu_pass_context *c, int x, int y, double out[4])

/* Mirrors halo_dot_clamped: the dot product clamped to [-1, 1] (emu/math.c). */
double halo_emu_dot_clamped(const double a[3], const double b[3]);

/* The GLSL test `v == vec3(0.0)`: a normal from halo_normalize is exactly zero when the
 * gradient has no direction. */
static inline int halo_emu_is_zero3(const double v[3]) { return v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0; }

#endif
