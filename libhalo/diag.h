/* Internal: collecting diagnostics. */
#ifndef HALO_DIAG_H
#define HALO_DIAG_H

#include "halo.h"

/* Adding a diagnostic is halo.h's halo_diagnostics_report. */

/* Whether a diagnostic of this severity added now would be kept (not past the cap):
 * where finding its place costs, the place is found only then. */
int halo_diag_kept(const halo_diagnostics *d, halo_severity severity);

#define halo_diag_error(d, id, file, line, col, ...) \
    halo_diagnostics_report((d), HALO_SEVERITY_ERROR, HALO_MSG_##id, (file), (line), (col), NULL, __VA_ARGS__)

/* A required argument is NULL (halo.h: "every function refuses NULL objects"): adds
 * USAGE "function: argument is NULL" to d; with d NULL only the setup logger sees it. */
void halo_diag_null(halo_diagnostics *d, const char *function, const char *argument);

/* Returns value from the calling function, after halo_diag_null, when pointer is NULL;
 * argument is the name a reader of halo.h knows ("scene", "program"). */
#define HALO_REFUSE_NULL(d, pointer, argument, value)  \
    do {                                               \
        if (!(pointer)) {                              \
            halo_diag_null((d), __func__, (argument)); \
            return value;                              \
        }                                              \
    } while (0)
#define HALO_REFUSE_NULL_VOID(d, pointer, argument)    \
    do {                                               \
        if (!(pointer)) {                              \
            halo_diag_null((d), __func__, (argument)); \
            return;                                    \
        }                                              \
    } while (0)

/* After halo_read_file(path) failed: one diagnostic naming the file and why, from errno
 * (EFBIG: INPUT_TOO_LARGE naming HALO_MAX_FILE_BYTES; ENOMEM: OUT_OF_MEMORY; else
 * IO_READ "cannot read WHAT: reason"). what: "scene", "module", "polyline file". */
void halo_diag_read_failed(halo_diagnostics *d, const char *path, const char *what);
/* halo_read_text_file without the NULL check: *not_text (may be NULL) 1 when the file was read
 * and holds a NUL byte (INPUT_NUL_BYTE at its line and column), else 0. */
char *halo_read_text(const char *path, const char *what, size_t *len, int *not_text, halo_diagnostics *d);

/* calloc(1, size), or NULL after OUT_OF_MEMORY "out of memory creating WHAT" in d. */
void *halo_diag_calloc(halo_diagnostics *d, size_t size, const char *what);

/* The calling thread's setup logger: halo_setup installs desc's (a NULL desc keeps the
 * one installed); the thread's last halo_shutdown removes it. */
void halo_diag_thread_setup(const halo_setup_desc *desc);
void halo_diag_thread_shutdown(void);

#endif
