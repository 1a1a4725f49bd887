/* The host shader's side of the link (host_check.c). Internal to libhalo. */
#ifndef HALO_HOST_CHECK_H
#define HALO_HOST_CHECK_H

#include "host_scan.h"
#include "internal.h"

/* What the linker learns of the host. */
typedef struct halo_host_info {
    int version_line; /* 0: none */
    int marker_line;
    int slices;              /* #pragma halo slices: the host draws slices or slabs and runs the passes itself */
    char *volume, *gradient; /* #pragma halo volume NAME / gradient NAME (owned) */
    int volume_line;
    halo_host_scan scan; /* comments, #if branches, #line and macros of the host */
    int compositing_mip; /* #pragma halo compositing mip: the line; the host composites no samples */
} halo_host_info;

/* A line that is '#pragma halo declarations' (the marker). */
int halo_host_is_marker_line(const char *l);
/* The host alone against the contract (h->scan already run): fills h, reports each
 * problem, returns the number of errors. */
int halo_host_check(const char *file, const char *source, char **lines, int count, halo_host_info *h,
                    halo_target target, halo_diagnostics *diag);
/* The host against the program: halo_apply and halo_finish called where needed, output
 * locations, macros that would rewrite the declarations. Each returns its error count. */
int halo_host_check_calls(const halo_program *p, const halo_host_info *h, const char *host, halo_diagnostics *diag);
int halo_host_check_outputs(const halo_program *p, const halo_host_info *h, const char *host, halo_diagnostics *diag);
/* The same checks of another text than the program's host (the shader a composer made of
 * the pieces, compose.c): its source, the file its diagnostics name, its lines, and what
 * the messages call it ("host", "composed shader"). */
typedef struct halo_host_text {
    const char *source;
    const char *file;
    char **lines;
    const char *what;
} halo_host_text;
int halo_host_check_calls_in(const halo_program *p, const halo_host_info *h, const halo_host_text *t,
                             halo_diagnostics *diag);
int halo_host_check_macros(const halo_program *p, const halo_host_info *h, halo_diagnostics *diag);
/* The host's #line directives: out of the compiled text, into the line map. 0, or -1 (memory). */
int halo_host_hide_line_directives(halo_program *p, const halo_host_info *h);
int halo_host_map_lines(halo_program *p, const halo_host_info *h);

#endif
