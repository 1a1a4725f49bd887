/* Runs the emulation of a linked program's stages on one sample. */
#include "diag.h"
#include "emu.h"
#include "internal.h"

#include <string.h>

struct halo_emu_params {
    const halo_program *program;
    const halo_linked_stage *stage;
};

const double *halo_emu_param(const halo_emu_params *p, const char *name, int *count) {
    const halo_module *m = p->stage->module;
    for (size_t i = 0; i < m->param_count; i++)
        if (!strcmp(m->params[i].name, name)) {
            if (count) *count = p->stage->values[i].count;
            return p->stage->values[i].value;
        }
    if (count) *count = 0;
    return NULL;
}

double halo_emu_scalar(const halo_emu_params *p, const char *name) {
    const double *v = halo_emu_param(p, name, NULL);
    return v ? v[0] : 0.0;
}

halo_status halo_emu_apply(const halo_program *p, halo_emu_sample *s, halo_diagnostics *diag) {
    memset(s->normal, 0, sizeof s->normal);
    s->gradient_magnitude = 0;
    for (size_t i = 0; i < p->stage_count; i++) {
        const halo_linked_stage *st = &p->stages[i];
        halo_emu_stage_fn fn = halo_emu_lookup(st->module->name);
        if (!fn) {
            halo_diag_error(diag, EMU_MISSING, st->module->file, st->module->module_line, 1,
                            "stage '%s' has no C emulation", st->module->name);
            return HALO_ERROR_INPUT;
        }
        halo_emu_params params = {p, st};
        fn(s, &params);
    }
    return HALO_OK;
}

int halo_module_has_emulation(const halo_module *m) { return !m->is_library && halo_emu_lookup(m->name) != NULL; }
