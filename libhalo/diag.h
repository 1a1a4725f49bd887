/* Internal: collecting diagnostics. */
#ifndef HALO_DIAG_H
#define HALO_DIAG_H

#include "halo.h"

/* Adds a diagnostic; d may be NULL (then only the setup logger sees it).
 * text is printf-formatted. source_line may be NULL. */
void halo_diag_add(halo_diagnostics *d, halo_severity severity, halo_message_id id, const char *file, int line,
                   int column, const char *source_line, const char *fmt, ...)
    __attribute__((format(printf, 8, 9)));

#define halo_diag_error(d, id, file, line, col, ...) \
    halo_diag_add((d), HALO_SEVERITY_ERROR, HALO_MSG_##id, (file), (line), (col), NULL, __VA_ARGS__)

/* The setup logger (set by halo_setup). */
void halo_diag_set_logger(void (*logger)(const halo_diagnostic *, void *), void *user_data);

#endif
