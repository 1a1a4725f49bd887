/* Emission of the linked program's text with origins (emit.c). Internal to libhalo. */
#ifndef HALO_EMIT_H
#define HALO_EMIT_H

#include "host_check.h"
#include "internal.h"
#include "strbuf.h"

/* Text being emitted, and the origin of each of its lines. */
typedef struct halo_emitter {
    halo_strbuf text;
    halo_line_origin *origins;
    int count, cap;
    int failed;
} halo_emitter;

/* Appends fmt's lines, each with the origin (file, line, original text). */
void halo_emit(halo_emitter *e, const char *file, int line, const char *original, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
/* Lines of libhalo's own. */
#define HALO_GEN(e, ...) halo_emit((e), halo_generated_file, 0, NULL, __VA_ARGS__)

/* A stage's parameters: compile-time constants, or uniforms (live; engine: left to the engine). */
void halo_emit_params(halo_emitter *e, const halo_program *p, const halo_linked_stage *st, int engine);
/* Module lines first..last, its private names renamed (rename), engine uniforms left out (engine). */
void halo_emit_module_lines(halo_emitter *e, const halo_module *m, int first, int last, int rename,
                            const halo_program *engine);
/* The helper functions the stages share. */
void halo_emit_helpers(halo_emitter *e, const halo_library *lib, const halo_program *p);
/* The halo channel type definitions for c channels. */
void halo_emit_channel_definitions(halo_emitter *e, int c);
/* The linker's product, libhalo's block (what replaces the host's marker) and its tail (after
 * the host's last line), into p->block and p->tail; then the whole program, p->source: the
 * version, the host with the block spliced in at its marker and the tail after its last
 * line. 0, or -1 when memory runs out. */
int halo_emit_program(halo_program *p, const char *host_source, char **host_lines, int host_count,
                      const halo_host_info *h, const halo_library *lib);

#endif
