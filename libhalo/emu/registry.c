/* The table of stage emulations, looked up by module name. */
#include <string.h>

#include "feature_internal.h"
#include "stages.h"

/* The per-sample and line stages with an emulation, by module name: HALO_EMU_STAGES(X),
 * generated from the HALO_EMU_STAGE(name) definitions of libhalo/local.mk's
 * halo_emu_stage_files (build-aux/emu_registry.sh). */
#include "registry_list.h"

#define HALO_EMU_DECLARE(name) HALO_EMU_STAGE(name);
HALO_EMU_STAGES(HALO_EMU_DECLARE)
#define HALO_EMU_ENTRY(name) {#name, halo_emu_##name},

static const struct {
    const char *name;
    halo_emu_stage_fn fn;
} halo_emu_stages[] = {HALO_EMU_STAGES(HALO_EMU_ENTRY)};

halo_emu_stage_fn halo_emu_lookup(const char *name)
{
    if (!name)
        return NULL;
    for (size_t i = 0; i < sizeof halo_emu_stages / sizeof halo_emu_stages[0]; ++i)
        if (strcmp(halo_emu_stages[i].name, name) == 0)
            return halo_emu_stages[i].fn;
    return NULL;
}

/* The image-pass emulations, looked up by module and entry. */
static const struct {
    const char *module, *entry;
    halo_emu_pass_fn fn;
} halo_emu_passes[] = {
    {"halo_generate", "median_pass", halo_emu_halo_generate_median},
    {"halo_generate", "gradient_pass", halo_emu_halo_generate_gradient},
    {"halo_generate", "spread_pass", halo_emu_halo_generate_spread},
    {"halo_generate", "spread_seed_pass", halo_emu_halo_generate_spread_seed},
    {"halo_generate", "spread_on_pass", halo_emu_halo_generate_spread_on},
    {"halo_generate", "spread_wide_pass", halo_emu_halo_generate_spread_wide},
    {"halo_generate", "occlusion_pass", halo_emu_halo_generate_occlusion},
    {"outlines", "blur_x_pass", halo_emu_outline_blur_x},
    {"outlines", "blur_y_pass", halo_emu_outline_blur_y},
    {"outlines", "min_x_pass", halo_emu_outline_min_x},
    {"outlines", "min_y_pass", halo_emu_outline_min_y},
    {"outlines", "normal_blur_x_pass", halo_emu_outline_normal_blur_x},
    {"outlines", "normal_blur_y_pass", halo_emu_outline_normal_blur_y},
    {"outlines", "importance_pass", halo_emu_outline_importance},
    {"outlines", "reduce_pass", halo_emu_outline_reduce},
    {"outlines", "compose_pass", halo_emu_outline_compose},
    {"outlines", "final_blur_x_pass", halo_emu_outline_final_blur_x},
    {"outlines", "final_blur_y_pass", halo_emu_outline_final_blur_y},
};

halo_emu_pass_fn halo_emu_lookup_pass(const char *module, const char *entry)
{
    if (!module || !entry)
        return NULL;
    for (size_t i = 0; i < sizeof halo_emu_passes / sizeof halo_emu_passes[0]; ++i)
        if (strcmp(halo_emu_passes[i].module, module) == 0 && strcmp(halo_emu_passes[i].entry, entry) == 0)
            return halo_emu_passes[i].fn;
    return NULL;
}
