#include "glsl_lex.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

static int push(halo_token_list *out, size_t *cap, halo_token t)
{
    if (out->count == *cap) {
        size_t c = *cap ? *cap * 2 : 256;
        halo_token *p = realloc(out->items, c * sizeof *p);
        if (!p)
            return -1;
        out->items = p;
        *cap = c;
    }
    out->items[out->count++] = t;
    return 0;
}

int halo_lex(const char *src, halo_token_list *out)
{
    size_t cap = 0, i = 0;
    int line = 1, col = 1, depth = 0, brace = 0;
    out->items = NULL;
    out->count = 0;
#define ADVANCE()             \
    do {                      \
        if (src[i] == '\n') { \
            line++;           \
            col = 1;          \
        } else                \
            col++;            \
        i++;                  \
    } while (0)
    while (src[i]) {
        char c = src[i];
        if (c == '\\' && src[i + 1] == '\n') {
            ADVANCE();
            ADVANCE();
            continue;
        }
        if (isspace((unsigned char)c)) {
            ADVANCE();
            continue;
        }
        if (c == '/' && src[i + 1] == '/') {
            while (src[i] && src[i] != '\n')
                ADVANCE();
            continue;
        }
        if (c == '/' && src[i + 1] == '*') {
            ADVANCE();
            ADVANCE();
            while (src[i] && !(src[i] == '*' && src[i + 1] == '/'))
                ADVANCE();
            if (src[i]) {
                ADVANCE();
                ADVANCE();
            }
            continue;
        }
        halo_token t = {.offset = i, .line = line, .column = col, .depth = depth, .brace_depth = brace};
        if (isalpha((unsigned char)c) || c == '_') {
            t.kind = HALO_TOK_IDENT;
            while (isalnum((unsigned char)src[i]) || src[i] == '_')
                ADVANCE();
        } else if (isdigit((unsigned char)c) || (c == '.' && isdigit((unsigned char)src[i + 1]))) {
            t.kind = HALO_TOK_NUMBER;
            /* an exponent's sign belongs to the number, except in a hexadecimal one (0x1e-3
             * is 0x1e minus 3) */
            int hex = c == '0' && (src[i + 1] == 'x' || src[i + 1] == 'X');
            while (isalnum((unsigned char)src[i]) || src[i] == '.' || src[i] == '_' ||
                   (!hex && (src[i] == '+' || src[i] == '-') && (src[i - 1] == 'e' || src[i - 1] == 'E')))
                ADVANCE();
        } else {
            t.kind = HALO_TOK_PUNCT;
            if (c == '(' || c == '[' || c == '{')
                depth++;
            if (c == '{')
                brace++;
            if ((c == ')' || c == ']' || c == '}') && depth > 0) {
                depth--;
                t.depth = depth;
            }
            if (c == '}' && brace > 0) {
                brace--;
                t.brace_depth = brace;
            }
            ADVANCE();
        }
        t.length = i - t.offset;
        if (push(out, &cap, t)) {
            halo_token_list_free(out);
            return -1;
        }
    }
#undef ADVANCE
    return 0;
}

void halo_token_list_free(halo_token_list *t)
{
    free(t->items);
    t->items = NULL;
    t->count = 0;
}

int halo_token_is(const char *src, const halo_token *t, const char *text)
{
    size_t n = strlen(text);
    return t->length == n && memcmp(src + t->offset, text, n) == 0;
}

int halo_is_glsl_keyword(const char *s, size_t n)
{
    static const char *const words[] = {
        "const",  "uniform",  "in",        "out",     "inout",  "highp", "mediump", "lowp",  "precision", "flat",
        "smooth", "centroid", "invariant", "layout",  "struct", "void",  "float",   "int",   "uint",      "bool",
        "vec2",   "vec3",     "vec4",      "ivec2",   "ivec3",  "ivec4", "uvec2",   "uvec3", "uvec4",     "bvec2",
        "bvec3",  "bvec4",    "mat2",      "mat3",    "mat4",   "if",    "else",    "for",   "while",     "do",
        "return", "break",    "continue",  "discard", "true",   "false", "switch",  "case",  "default",   NULL};
    for (int i = 0; words[i]; i++)
        if (strlen(words[i]) == n && memcmp(words[i], s, n) == 0)
            return 1;
    return 0;
}

int halo_is_glsl_reserved(const char *name)
{
    /* GLSL 4.60 and GLSL ES 3.20: keywords, type names and words reserved for future
     * use, the lower-case ones (a libhalo name is [a-z][a-z0-9_]*). */
    static const char *const words[] = {
        "const",     "uniform",    "buffer",    "shared",    "attribute",     "varying",
        "coherent",  "volatile",   "restrict",  "readonly",  "writeonly",     "atomic_uint",
        "layout",    "centroid",   "flat",      "smooth",    "noperspective", "patch",
        "sample",    "invariant",  "precise",   "break",     "continue",      "do",
        "for",       "while",      "switch",    "case",      "default",       "if",
        "else",      "subroutine", "in",        "out",       "inout",         "int",
        "void",      "bool",       "true",      "false",     "float",         "double",
        "discard",   "return",     "uint",      "lowp",      "mediump",       "highp",
        "precision", "struct",     "common",    "partition", "active",        "asm",
        "class",     "union",      "enum",      "typedef",   "template",      "this",
        "resource",  "goto",       "inline",    "noinline",  "public",        "static",
        "extern",    "external",   "interface", "long",      "short",         "half",
        "fixed",     "unsigned",   "superp",    "input",     "output",        "filter",
        "sizeof",    "cast",       "namespace", "using",     "demote",        "terminate",
        NULL};
    for (int i = 0; words[i]; i++)
        if (!strcmp(words[i], name))
            return 1;
    /* vecN, bvecN, ivecN, uvecN, dvecN, hvecN, fvecN; matN, matNxM, dmat... */
    const char *p = name;
    if (strchr("bdiufh", *p) && !strncmp(p + 1, "vec", 3))
        p++;
    if (!strncmp(p, "vec", 3) && p[3] >= '2' && p[3] <= '4' && !p[4])
        return 1;
    p = name[0] == 'd' ? name + 1 : name;
    if (!strncmp(p, "mat", 3) && p[3] >= '2' && p[3] <= '4' &&
        (!p[4] || (p[4] == 'x' && p[5] >= '2' && p[5] <= '4' && !p[6])))
        return 1;
    /* the language's own prefix, and double underscores */
    return !strncmp(name, "gl_", 3) || strstr(name, "__") != NULL;
}
