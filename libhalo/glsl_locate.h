/* Internal: the column of each glslang error. glslang 12 reports a line, not a column;
 * compiling the text again with one token per line turns its line into the token. */
#ifndef HALO_GLSL_LOCATE_H
#define HALO_GLSL_LOCATE_H

#include <stddef.h>

typedef struct halo_glsl_spot {
    int reported_line; /* the compiled line of the token glslang stopped at */
    int line, column;  /* where the error is, in the compiled text, 1-based; column 0: unknown */
    int moved;         /* a missing ';' (or ','): the spot is the end of the token before */
    char *message;     /* glslang's message, without its location */
    int used;          /* taken by halo_glsl_place */
} halo_glsl_spot;

typedef struct halo_glsl_spots {
    halo_glsl_spot *items;
    int count;
} halo_glsl_spots;

/* The messages of source compiled with one token per line, as halo_glslang_compile
 * compiles it (vertex, file). Directives keep their lines; a text using __LINE__ or #line
 * is not split (no spots). Returns 0, -1 when memory ran out or glslang failed. */
int halo_glsl_locate(const char *source, int vertex, const char *file, halo_glsl_spots *out);

/* Where glslang says a message is, in rest (a log line after "ERROR: "): "FILE:LINE: "
 * (file: the name the text was compiled under), "N:LINE: " (N a source string number),
 * or, after a GL_GOOGLE_cpp_style_line_directive '#line L "name"', "name:LINE: ".
 * Returns the length of the location (0: none), the name's length in *name_len, its line
 * in *line, and in *numbered whether it is a line of the text itself (not a '#line' name
 * or an included file). */
size_t halo_glsl_log_location(const char *rest, const char *file, size_t *name_len, int *line, int *numbered);

/* Where a message glslang reported at compiled line *line is: the spot with the same
 * message and line, not taken before. *line moves to the line before for a missing ';';
 * *column is in the compiled line (0: unknown), at_end when it is a token's end. */
void halo_glsl_place(halo_glsl_spots *spots, const char *message, int *line, int *column, int *at_end);

/* The column in original (the line as its author wrote it, before the linker renamed
 * names) of the message at compiled line `line`, column `column` of source: the token
 * the message names nearest there, counted in both lines; without a column, the first
 * whole token the message names. 0 when unknown. */
int halo_glsl_original_column(const char *source, int line, int column, int at_end, const char *message,
                              const char *original);

/* The message for the reader: no empty token ('' :), renamed names as written in
 * original (may be NULL). Caller frees. */
char *halo_glsl_message(const char *message, const char *original);

/* Whether an error after another on the same line is taken as following from it
 * (glslang goes on with a placeholder): all but another undeclared name. */
int halo_glsl_follows_earlier_error(const char *message);

void halo_glsl_spots_free(halo_glsl_spots *s);

#endif
