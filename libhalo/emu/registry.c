/* The tables of the emulations: the stages by module name, the image passes by module
 * and entry. */
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

/* The image-pass emulations, looked up by module and entry: HALO_EMU_PASSES(X), generated
 * from the HALO_EMU_PASS(module, entry) definitions of the same files. */
#define HALO_EMU_DECLARE_PASS(module, entry) HALO_EMU_PASS(module, entry);
HALO_EMU_PASSES(HALO_EMU_DECLARE_PASS)
#define HALO_EMU_PASS_ENTRY(module, entry) {#module, #entry, halo_emu_##module##_##entry},

static const struct {
    const char *module, *entry;
    halo_emu_pass_fn fn;
} halo_emu_passes[] = {HALO_EMU_PASSES(HALO_EMU_PASS_ENTRY)};

halo_emu_pass_fn halo_emu_lookup_pass(const char *module, const char *entry)
{
    if (!module || !entry)
        return NULL;
    for (size_t i = 0; i < sizeof halo_emu_passes / sizeof halo_emu_passes[0]; ++i)
        if (strcmp(halo_emu_passes[i].module, module) == 0 && strcmp(halo_emu_passes[i].entry, entry) == 0)
            return halo_emu_passes[i].fn;
    return NULL;
}
