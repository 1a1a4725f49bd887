/* halo_validate: one entry point over the four things libhalo validates with glslang, a
 * linked program, a stand-alone shader, a module (validate.c) and a shader an engine
 * composed from a program's pieces (compose.c). */
#include "diag.h"
#include "internal.h"

halo_status halo_validate(const halo_validate_desc *d, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, d, "desc", HALO_ERROR_INPUT);
    int what = (d->program != NULL) + (d->source != NULL) + (d->module != NULL);
    if (what != 1) {
        halo_diag_error(diag, USAGE, "", 0, 0,
                        "halo_validate: desc sets %s of program, source and module; set exactly one",
                        what ? "more than one" : "none");
        return HALO_ERROR_INPUT;
    }
    int composed = d->composed || d->composed_file || d->composer_pieces || d->composer_piece_count;
    if ((composed && !d->program) || (d->library && !d->module) || (d->file && !d->source)) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_validate: desc sets %s, which only %s takes",
                        composed && !d->program    ? "composed fields"
                        : d->library && !d->module ? "library"
                                                   : "file",
                        composed && !d->program    ? "program"
                        : d->library && !d->module ? "module"
                                                   : "source");
        return HALO_ERROR_INPUT;
    }
    if (d->module)
        return halo_validate_module(d->library, d->module, d->target, diag);
    if (d->source)
        return halo_validate_source(d->source, d->file, d->kind, d->target, diag);
    if (composed)
        return halo_validate_composed(d->program, d->composed, d->composed_file, d->composer_pieces,
                                      d->composer_piece_count, diag);
    return halo_validate_program(d->program, diag);
}
