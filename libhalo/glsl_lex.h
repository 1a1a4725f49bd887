/* Internal: a small GLSL tokenizer. Comments and white space are skipped; every token
 * keeps its offset, line and column, so rewriting copies the text between tokens
 * verbatim and every output line keeps its origin. */
#ifndef HALO_GLSL_LEX_H
#define HALO_GLSL_LEX_H

#include <stddef.h>

typedef enum halo_token_kind { HALO_TOK_IDENT, HALO_TOK_NUMBER, HALO_TOK_PUNCT } halo_token_kind;

typedef struct halo_token {
    halo_token_kind kind;
    size_t offset, length;
    int line, column; /* 1-based */
    int depth;        /* nesting of (), [] and {} before the token */
    int brace_depth;  /* nesting of {} before the token */
} halo_token;

typedef struct halo_token_list {
    halo_token *items;
    size_t count;
} halo_token_list;

/* Tokenizes src. Returns 0 on success, -1 if memory ran out. Unterminated comments end
 * at the end of the text. */
int halo_lex(const char *src, halo_token_list *out);
void halo_token_list_free(halo_token_list *t);
int halo_token_is(const char *src, const halo_token *t, const char *text);
int halo_is_glsl_keyword(const char *s, size_t n);
/* A GLSL keyword, type name or reserved word (any GLSL version libhalo targets): no
 * name of a libhalo parameter or field. */
int halo_is_glsl_reserved(const char *name);

#endif
