/* The library's version and the GLSL targets' names and #version lines: what every build
 * has, the WebAssembly one (adapters/web) included, which has no glslang (setup.c). */
#include "diag.h"
#include "internal.h"

const char *halo_version(void) { return PACKAGE_VERSION; }

static const char *const target_names[HALO_TARGET_COUNT] = {"330", "330", "450", "es300", "150"};

const char *halo_target_name(halo_target t) { return (unsigned)t < HALO_TARGET_COUNT ? target_names[t] : "?"; }

halo_target halo_target_from_name(const char *name)
{
    HALO_REFUSE_NULL(NULL, name, "name", HALO_TARGET_COUNT);
    for (int t = HALO_TARGET_GLSL330; t < HALO_TARGET_COUNT; t++)
        if (name && !__builtin_strcmp(name, target_names[t]))
            return (halo_target)t;
    return HALO_TARGET_COUNT;
}

const char *halo_target_version_line(halo_target t)
{
    static const char *const lines[HALO_TARGET_COUNT] = {"#version 330 core", "#version 330 core", "#version 450 core",
                                                         "#version 300 es", "#version 150 core"};
    return (unsigned)t < HALO_TARGET_COUNT ? lines[t] : lines[0];
}
