/* The module library: modules embedded at build time, plus any the user adds. */
#include "diag.h"
#include "internal.h"
#include "strbuf.h"

#include <errno.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

struct halo_embedded_file {
    const char *name;
    const char *text;
};
extern const struct halo_embedded_file halo_embedded_modules[];

static halo_status add_module(halo_library *lib, halo_module *m, halo_diagnostics *diag)
{
    const char *name = halo_module_name_of(m);
    const halo_module *old = halo_library_find(lib, name);
    if (old) {
        halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_MODULE_DUPLICATE, m->file, m->module_line, 1,
                                m->lines[m->module_line - 1], "a module named '%s' is already loaded from %s", name,
                                old->file);
        halo_module_free(m);
        return HALO_ERROR_INPUT;
    }
    halo_module **p = realloc(lib->modules, (lib->count + 1) * sizeof *p);
    if (!p) {
        halo_module_free(m);
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return HALO_ERROR_IO;
    }
    lib->modules = p;
    lib->modules[lib->count++] = m;
    return HALO_OK;
}

static halo_module *read_module(const char *path, halo_diagnostics *diag, halo_status *status)
{
    int not_text;
    char *text = halo_read_text(path, "module", NULL, &not_text, diag);
    if (!text) {
        /* a NUL byte is an error in the input; the rest, that the file cannot be read */
        *status = not_text ? HALO_ERROR_INPUT : HALO_ERROR_IO;
        return NULL;
    }
    halo_module *m = halo_module_parse(path, text, diag);
    free(text);
    *status = m ? HALO_OK : HALO_ERROR_INPUT;
    return m;
}

static halo_status replace_or_add(halo_library *lib, halo_module *m, halo_diagnostics *diag)
{
    /* A scene or program holds pointers into the module it would replace. */
    long users = atomic_load(&lib->refs) - 1;
    if (users > 0) {
        halo_diag_error(diag, USAGE, m->file, 0, 0,
                        "cannot replace module '%s': %ld scene%s or program%s made from this library still use its "
                        "modules; override modules before reading scenes or linking (halo.h, \"Lifetimes\")",
                        halo_module_name_of(m), users, users == 1 ? "" : "s", users == 1 ? "" : "s");
        halo_module_free(m);
        return HALO_ERROR_INPUT;
    }
    for (size_t i = 0; i < lib->count; i++)
        if (!strcmp(halo_module_name_of(lib->modules[i]), halo_module_name_of(m))) {
            halo_module_free(lib->modules[i]);
            lib->modules[i] = m;
            return HALO_OK;
        }
    return add_module(lib, m, diag);
}

/* Reads the module at path and puts it into lib with put (add_module or replace_or_add). */
static halo_status put_file(halo_library *lib, const char *path, halo_diagnostics *diag,
                            halo_status (*put)(halo_library *, halo_module *, halo_diagnostics *))
{
    halo_status st;
    halo_module *m = read_module(path, diag, &st);
    return m ? put(lib, m, diag) : st;
}

halo_status halo_library_add(halo_library *lib, const char *file, const char *source, halo_add_mode mode,
                             halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, lib, "library", HALO_ERROR_INPUT);
    if (mode != HALO_ADD_NEW && mode != HALO_ADD_REPLACE) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_library_add: mode %d is not a halo_add_mode", (int)mode);
        return HALO_ERROR_INPUT;
    }
    halo_status (*put)(halo_library *, halo_module *, halo_diagnostics *) =
        mode == HALO_ADD_REPLACE ? replace_or_add : add_module;
    if (!source) {
        HALO_REFUSE_NULL(diag, file, "file (a path, when source is NULL)", HALO_ERROR_INPUT);
        return put_file(lib, file, diag, put);
    }
    halo_module *m = halo_module_parse(file ? file : "module", source, diag);
    return m ? put(lib, m, diag) : HALO_ERROR_INPUT;
}

halo_library *halo_library_create(halo_diagnostics *diag)
{
    halo_library *lib = calloc(1, sizeof *lib);
    if (!lib) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return NULL;
    }
    atomic_init(&lib->refs, 1);
    for (const struct halo_embedded_file *f = halo_embedded_modules; f->name; f++) {
        if (halo_library_add(lib, f->name, f->text, HALO_ADD_NEW, diag) != HALO_OK) {
            halo_library_destroy(lib);
            return NULL;
        }
    }
    return lib;
}

void halo_library_retain(const halo_library *lib) { atomic_fetch_add(&((halo_library *)lib)->refs, 1); }

void halo_library_release(const halo_library *lib)
{
    halo_library *l = (halo_library *)lib;
    if (!l || atomic_fetch_sub(&l->refs, 1) != 1)
        return;
    for (size_t i = 0; i < l->count; i++)
        halo_module_free(l->modules[i]);
    free(l->modules);
    free(l);
}

void halo_library_destroy(halo_library *lib) { halo_library_release(lib); }

halo_library_info halo_library_describe(const halo_library *lib)
{
    halo_library_info info = {0};
    HALO_REFUSE_NULL(NULL, lib, "library", info);
    info.module_count = lib->count;
    info.modules = (const halo_module *const *)lib->modules;
    return info;
}

const halo_module *halo_library_find(const halo_library *lib, const char *name)
{
    HALO_REFUSE_NULL(NULL, lib, "library", NULL);
    HALO_REFUSE_NULL(NULL, name, "name", NULL);
    for (size_t i = 0; i < lib->count; i++)
        if (!strcmp(halo_module_name_of(lib->modules[i]), name))
            return lib->modules[i];
    return NULL;
}

const halo_module *halo_library_helpers(const halo_library *lib)
{
    for (size_t i = 0; lib && i < lib->count; i++)
        if (lib->modules[i]->is_library)
            return lib->modules[i];
    return NULL;
}
