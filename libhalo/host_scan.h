/* Internal: what the host's preprocessor makes of its text, as far as the linker needs
 * it to report a host that would link silently wrong: which lines are comments, which
 * lie in #if branches not taken for the target, where #line directives say each line
 * comes from, and which object-like macros the host has defined at the marker. */
#ifndef HALO_HOST_SCAN_H
#define HALO_HOST_SCAN_H

#include "halo.h"
#include "glsl_lex.h"

/* Whether a line is compiled. Conditions the scan cannot evaluate count as taken. */
typedef enum halo_branch { HALO_BRANCH_NOT_TAKEN = 0, HALO_BRANCH_TAKEN, HALO_BRANCH_UNKNOWN } halo_branch;

typedef struct halo_host_line_info {
    unsigned char activity;       /* halo_branch */
    unsigned char line_directive; /* a #line the scan honoured (the linker emits it as a comment) */
    int condition_line;           /* NOT_TAKEN: the #if, #elif or #else that leaves the line out */
    int file;                     /* origin after #line: 0 the host's file, k names[k - 1] */
    int line;
} halo_host_line_info;

typedef struct halo_host_macro {
    const char *name; /* a view into the scan's code text */
    size_t length;
    const char *value; /* the replacement text, to the end of the line */
    int line, column;  /* of the name in the #define */
    int function_like;
    int certain;    /* defined on a line certainly compiled */
    int predefined; /* GL_ES, __VERSION__, ...; HALO_LINKED after the marker */
} halo_host_macro;

typedef struct halo_host_scan {
    char *code;     /* the source with comments blanked (new lines kept) */
    char *comments; /* the source with everything but the text of comments blanked */
    char **code_lines, **comment_lines;
    int line_count;
    halo_host_line_info *lines;     /* per line, 0-based */
    halo_token_list tokens;         /* of the code */
    halo_token_list comment_tokens; /* of the comments' text */
    int marker_line;                /* the first compiled marker line; 0 when none */
    halo_host_macro *macros;        /* defined while scanning (at the end: at the last line) */
    size_t macro_count, macro_cap;
    halo_host_macro *marker_macros; /* those defined at the marker line */
    size_t marker_macro_count;
    char **names; /* the file names of #line N "file" */
    size_t name_count;
} halo_host_scan;

typedef struct halo_host_scan_desc {
    const char *source;
    halo_target target;
    halo_shader_kind kind;
    int (*is_marker)(const char *line); /* is this code line '#pragma halo declarations'? */
} halo_host_scan_desc;

/* Returns 0, or -1 when memory ran out. Free with halo_host_scan_free in either case. */
int halo_host_scan_run(const halo_host_scan_desc *desc, halo_host_scan *out);
void halo_host_scan_free(halo_host_scan *s);

/* Where line (1-based, in the host's text) comes from after the #line directives. */
void halo_host_scan_origin(const halo_host_scan *s, const char *host_file, int line, const char **file,
                           int *origin_line);
int halo_host_scan_compiled(const halo_host_scan *s, int line);

/* A call of a function the host must make. */
typedef struct halo_host_hit {
    int line, column; /* 0 when none */
    int in_comment;   /* else in a branch not taken */
} halo_host_hit;

/* Returns 1 when a compiled line calls name; else *unused tells the first call that is
 * commented out or in a branch not taken (line 0 when none). */
int halo_host_scan_find_call(const halo_host_scan *s, const char *name, halo_host_hit *unused);

/* The host's global 'out' declarations without layout(location) on compiled lines:
 * returns how many there are, and the first max of them in at. */
size_t halo_host_scan_unlocated_outputs(const halo_host_scan *s, const char *source, halo_host_hit *at, size_t max);

/* The host's own macro named like text[0..length), defined at the marker, or NULL. */
const halo_host_macro *halo_host_scan_macro(const halo_host_scan *s, const char *text, size_t length);

#endif
