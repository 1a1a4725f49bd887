/* Runs the emulation of a linked program's stages on one sample. */
#include "diag.h"
#include "emu.h"
#include "internal.h"

#include <string.h>

const double *halo_emu_param(const halo_emu_params *p, const char *name, int *count)
{
    const halo_module *m = p->stage->module;
    for (size_t i = 0; i < m->param_count; i++)
        if (!strcmp(m->params[i].name, name)) {
            if (count)
                *count = p->stage->values[i].count;
            return p->stage->values[i].value;
        }
    if (count)
        *count = 0;
    return NULL;
}

double halo_emu_scalar(const halo_emu_params *p, const char *name)
{
    const double *v = halo_emu_param(p, name, NULL);
    return v ? v[0] : 0.0;
}

const double *halo_emu_channel_param(const halo_emu_params *p, const char *name, int h)
{
    const halo_module *m = p->stage->module;
    for (size_t i = 0; i < m->param_count; i++)
        if (!strcmp(m->params[i].name, name)) {
            int count = p->stage->values[i].count;
            if (count < 1)
                return NULL;
            if (h > count - 1)
                h = count - 1;
            if (h < 0)
                h = 0;
            return p->stage->values[i].value + (size_t)h * (size_t)m->params[i].components;
        }
    return NULL;
}

double halo_emu_channel(const halo_emu_params *p, const char *name, int h)
{
    const double *v = halo_emu_channel_param(p, name, h);
    return v ? v[0] : 0.0;
}

int halo_emu_channel_count(const halo_emu_params *p)
{
    int c = p->program ? p->program->channel_count : 1;
    return c < 1 ? 1 : c > 4 ? 4 : c;
}

/* The stages of the program in order: each runs on the sample (a line host's stages on
 * its line_vertex or line_fragment); image-hook stages have no per-sample code. */
static halo_status run_stages(const halo_program *p, halo_emu_frame *f, halo_emu_sample *s, halo_diagnostics *diag)
{
    memset(s->normal, 0, sizeof s->normal);
    s->gradient_magnitude = 0;
    memset(s->seed, 0, sizeof s->seed);
    for (size_t i = 0; i < p->stage_count; i++) {
        const halo_linked_stage *st = &p->stages[i];
        if (st->module->hook == HALO_HOOK_IMAGE)
            continue;
        halo_emu_stage_fn fn = halo_emu_lookup(st->module->name);
        if (!fn) {
            halo_diag_error(diag, EMU_MISSING, st->module->file, st->module->module_line, 1,
                            "stage '%s' has no C emulation", st->module->name);
            return HALO_ERROR_INPUT;
        }
        halo_emu_params params = {p, st, f};
        fn(s, &params);
    }
    return HALO_OK;
}

halo_status halo_emu_apply(const halo_program *p, halo_emu_frame *f, halo_emu_sample *s, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, p, "program", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(diag, s, "sample", HALO_ERROR_INPUT);
    halo_status st = run_stages(p, f, s, diag);
    if (st != HALO_OK || !f)
        return st;
    /* The linker folds each output's field after halo_apply (emu/frame.c). */
    return halo_emu_frame_fold(p, s, diag);
}

static int module_emulated(const halo_module *m)
{
    if (m->is_library)
        return 0;
    if (m->hook == HALO_HOOK_IMAGE) {
        for (size_t i = 0; i < m->pass_count; i++)
            if (!halo_emu_lookup_pass(m->name, m->passes[i].entry))
                return 0;
        return m->pass_count > 0;
    }
    return halo_emu_lookup(m->name) != NULL;
}

/* In the emulation's file: what a module is includes whether it has an emulation. */
halo_module_info halo_module_describe(const halo_module *m)
{
    halo_module_info info = {0};
    info.hook = HALO_HOOK_COUNT;
    if (!m)
        return info;
    info.name = halo_module_name_of(m);
    info.file = m->file;
    info.summary = m->summary;
    info.hook = m->hook;
    info.param_count = m->param_count;
    info.params = m->params;
    info.has_emulation = module_emulated(m);
    info.output_count = m->output_count;
    info.image_count = m->image_count;
    info.host_uniform_count = m->host_uniform_count;
    return info;
}
