/* Internal: one compile (and link) through glslang's C++ interface, as glslangValidator
 * compiles: the source text is given to the shader and parsed once, the preprocessor
 * running inside the parse. glslang 12's C interface instead parses the text its
 * preprocessor wrote out, which rewrites string escapes (a false error in debugPrintfEXT)
 * and loses what a directive like '#line __FILE__ + 2' got wrong. */
#ifndef HALO_GLSLANG_PARSE_H
#define HALO_GLSLANG_PARSE_H

#ifdef __cplusplus
extern "C" {
#endif

/* When halo_glslang_compile links the shader: never, after a compile without errors, or
 * after compile errors too (as glslangValidator -l does: a missing main, interface errors). */
typedef enum halo_glslang_link {
    HALO_GLSLANG_NO_LINK,
    HALO_GLSLANG_LINK_IF_COMPILED,
    HALO_GLSLANG_LINK_ALWAYS
} halo_glslang_link;

typedef struct halo_glslang_result {
    int compiled;   /* 1: the compile reported no error */
    int linked;     /* 1: linked, or not asked to; 0: the link failed */
    char *log;      /* the compile's info log ("ERROR: 0:LINE: message" lines) */
    char *link_log; /* the link's; NULL when not linked */
} halo_glslang_result;

/* Compiles source as a vertex (vertex != 0) or fragment shader: GLSL ES 1.00 without a
 * '#version', cascading errors on (validate.c drops the ones that follow from an
 * earlier error), glslang's default resource limits, no client and no target language.
 * The text is compiled under the name file, as glslangValidator names it after its file:
 * the log says "file:LINE:" (NULL or "": "0:LINE:") and '__FILE__' is the name.
 * '#include "name"' is looked up in the folder of the file that includes it, then in
 * those of the files that include that one: the shader's own is file's folder (the
 * working directory for a name without '/'), whatever the working directory is. The caller holds glslang (HALO_WITH_GLSLANG). Returns 0 and
 * fills *out (halo_glslang_result_free), or -1 when memory ran out or glslang failed. */
int halo_glslang_compile(const char *source, int vertex, const char *file, halo_glslang_link link,
                         halo_glslang_result *out);

void halo_glslang_result_free(halo_glslang_result *r);

#ifdef __cplusplus
}
#endif

#endif
