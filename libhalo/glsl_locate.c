/* The column of each glslang error (glsl_locate.h). GLSL is free-form outside its
 * preprocessor directives, so the same text with every token on a line of its own
 * compiles to the same errors, and the line glslang reports names the token. */
#include "glsl_locate.h"

#include "glsl_lex.h"
#include "glslang_parse.h"
#include "internal.h"
#include "strbuf.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

/* Where a line of the split text came from: a token (line, column, length, and its
 * offset in the text) or a directive (column 0). */
typedef struct unit_place {
    int line, column, length;
    size_t offset;
} unit_place;

/* Length of the operator at p: GLSL's two- and three-character ones stay together. */
static size_t operator_length(const char *p)
{
    static const char *const operators[] = {"<<=", ">>=", "++", "--", "<<", ">>", "<=", ">=", "==", "!=", "&&",
                                            "||",  "^^",  "+=", "-=", "*=", "/=", "%=", "&=", "^=", "|=", "##"};
    for (size_t i = 0; i < sizeof operators / sizeof operators[0]; i++)
        if (!strncmp(p, operators[i], strlen(operators[i])))
            return strlen(operators[i]);
    return 1;
}

/* End of the directive that starts at src + at: its line, continued by backslashes and
 * by block comments that run on. */
static size_t directive_end(const char *src, size_t at)
{
    size_t i = at;
    while (src[i] && src[i] != '\n') {
        if (src[i] == '\\' && src[i + 1] == '\n')
            i += 2;
        else if (src[i] == '\\' && src[i + 1] == '\r' && src[i + 2] == '\n')
            i += 3;
        else if (src[i] == '/' && src[i + 1] == '/') {
            while (src[i] && src[i] != '\n')
                i++;
        } else if (src[i] == '/' && src[i + 1] == '*') {
            const char *close = strstr(src + i + 2, "*/");
            i = close ? (size_t)(close - src) + 2 : strlen(src);
        } else
            i++;
    }
    return i;
}

/* Is the directive at src + at (the '#') "#line"? */
static int is_line_directive(const char *src, size_t at)
{
    const char *p = src + at + 1;
    while (*p == ' ' || *p == '\t')
        p++;
    return !strncmp(p, "line", 4) && (p[4] == ' ' || p[4] == '\t');
}

/* The text split into units, one a line; places[i] is line i + 1's origin. -1: out of
 * memory; 1: the text cannot be split (it uses __LINE__ or #line). */
static int split_text(const char *src, halo_strbuf *out, unit_place **places, int *count)
{
    halo_token_list tokens;
    if (strstr(src, "__LINE__"))
        return 1;
    if (halo_lex(src, &tokens))
        return -1;
    unit_place *p = calloc(tokens.count + 1, sizeof *p);
    int n = 0, status = p ? 0 : -1;
    size_t skip_to = 0; /* tokens before this offset belong to the unit already written */
    for (size_t i = 0; i < tokens.count && !status; i++) {
        const halo_token *t = &tokens.items[i];
        if (t->offset < skip_to)
            continue;
        size_t start = t->offset, end = t->offset + t->length;
        int directive = src[start] == '#' && (i == 0 || tokens.items[i - 1].line < t->line);
        if (directive) {
            if (is_line_directive(src, start)) {
                status = 1;
                break;
            }
            end = directive_end(src, start);
        } else if (t->kind == HALO_TOK_PUNCT && src[start] == '"') {
            const char *close = strpbrk(src + start + 1, "\"\n");
            end = close && *close == '"' ? (size_t)(close - src) + 1 : end;
        } else if (t->kind == HALO_TOK_PUNCT) {
            end = start + operator_length(src + start);
        }
        for (size_t k = start; k < end; k++) /* a directive's continuations become spaces */
            halo_strbuf_append_n(out, src[k] == '\n' || src[k] == '\r' || (src[k] == '\\' && directive) ? " " : src + k,
                                 1);
        halo_strbuf_append(out, "\n");
        p[n++] = (unit_place){t->line, directive ? 0 : t->column, directive ? 0 : (int)(end - start), start};
        skip_to = end;
    }
    halo_token_list_free(&tokens);
    if (out->failed)
        status = -1;
    if (status) {
        free(p);
        return status;
    }
    *places = p;
    *count = n;
    return 0;
}

/* ":LINE:" at p: its length (0: none there), the line in *line. */
static size_t line_number_at(const char *p, int *line)
{
    if (*p != ':')
        return 0;
    const char *d = p + 1;
    while (isdigit((unsigned char)*d))
        d++;
    if (d == p + 1 || *d != ':')
        return 0;
    *line = atoi(p + 1);
    return (size_t)(d + 1 - p);
}

size_t halo_glsl_log_location(const char *rest, const char *file, size_t *name_len, int *line, int *numbered)
{
    size_t n = file ? strlen(file) : 0, len;
    *numbered = 0;
    if (n && !strncmp(rest, file, n) && (len = line_number_at(rest + n, line))) {
        *name_len = n; /* the text's own name, whatever characters it has */
        *numbered = 1;
        return n + len;
    }
    for (const char *c = strchr(rest, ':'); c; c = strchr(c + 1, ':')) {
        if (c == rest || memchr(rest, ' ', (size_t)(c - rest)))
            return 0;
        if ((len = line_number_at(c, line))) {
            *name_len = (size_t)(c - rest);
            *numbered = strspn(rest, "0123456789") == *name_len;
            return *name_len + len;
        }
    }
    return 0;
}

/* glslang's log line "ERROR: file:12: 'x' : text": severity (0 error, 1 warning; -1 not
 * a message), line (0 when none or in another file) and the message after the location. */
static int log_line(const char *line, const char *file, int *out_line, const char **message)
{
    int severity;
    const char *rest;
    if (!strncmp(line, "ERROR: ", 7)) {
        severity = 0;
        rest = line + 7;
    } else if (!strncmp(line, "WARNING: ", 9)) {
        severity = 1;
        rest = line + 9;
    } else
        return -1;
    size_t name_len;
    int at = 0, numbered;
    rest += halo_glsl_log_location(rest, file, &name_len, &at, &numbered);
    *out_line = numbered ? at : 0;
    while (*rest == ' ')
        rest++;
    *message = rest;
    return severity;
}

/* The token a message names ('x' : ...), or "". */
static void named_token(const char *message, char *token, size_t size)
{
    token[0] = '\0';
    const char *end = *message == '\'' ? strchr(message + 1, '\'') : NULL;
    if (end && (size_t)(end - message - 1) < size) {
        memcpy(token, message + 1, (size_t)(end - message - 1));
        token[end - message - 1] = '\0';
    }
}

/* Is unit u the token text? */
static int unit_is(const char *src, const unit_place *u, const char *text, size_t n)
{
    return u->column && (size_t)u->length == n && !strncmp(src + u->offset, text, n);
}

/* Does the text define name (n bytes) as a function-like macro ('#define name(')? */
static int defines_function_macro(const char *src, const char *name, size_t n)
{
    for (const char *p = src; p; p = strchr(p, '\n'), p = p ? p + 1 : NULL) {
        const char *q = p + strspn(p, " \t");
        if (*q != '#')
            continue;
        q += 1 + strspn(q + 1, " \t");
        if (strncmp(q, "define", 6) || (q[6] != ' ' && q[6] != '\t'))
            continue;
        q += 6 + strspn(q + 6, " \t");
        if (!strncmp(q, name, n) && q[n] == '(')
            return 1;
    }
    return 0;
}

/* The name of the call (or macro use) whose ')' is unit `end`: the identifier before its
 * '(' (-1: none, or a directive within). */
static int call_name(const char *src, const unit_place *places, int end)
{
    int depth = 0;
    for (int i = end; i >= 0 && places[i].column; i--) {
        if (unit_is(src, &places[i], ")", 1))
            depth++;
        else if (unit_is(src, &places[i], "(", 1) && --depth == 0)
            return i > 0 && places[i - 1].column &&
                           (isalpha((unsigned char)src[places[i - 1].offset]) || src[places[i - 1].offset] == '_')
                       ? i - 1
                       : -1;
    }
    return -1;
}

/* glslang reports an error in a call or a macro use at its last token, the ')'. Where the
 * message names the call and the call starts on an earlier line, the error is at its
 * name, as clang puts it; where the message names no token of the use of a function-like
 * macro (the token came from the macro's body), at the macro's name. Returns the unit
 * (-1: unit `at` stays). */
static int call_unit(const char *src, const unit_place *places, int at, const char *message)
{
    char token[256];
    named_token(message, token, sizeof token);
    size_t n = strlen(token);
    if (!n || !unit_is(src, &places[at], ")", 1))
        return -1;
    int name = call_name(src, places, at);
    if (name < 0)
        return -1;
    const unit_place *u = &places[name];
    if (unit_is(src, u, token, n))
        return u->line != places[at].line ? name : -1;
    for (int i = name; i <= at; i++)
        if (unit_is(src, &places[i], token, n))
            return -1;
    return defines_function_macro(src, src + u->offset, (size_t)u->length) ? name : -1;
}

/* Adds the spot of one log line of the split compile. */
static int add_spot(halo_glsl_spots *out, const char *line, const char *file, const char *src, const unit_place *places,
                    int count)
{
    int at;
    const char *message;
    if (log_line(line, file, &at, &message) < 0)
        return 0;
    halo_glsl_spot spot = {0};
    if (at >= 1 && at <= count) {
        const unit_place *u = &places[at - 1];
        spot.reported_line = spot.line = u->line;
        spot.column = u->column;
        /* A missing ';': at the end of the token before, as clang puts it. */
        if (u->column && at >= 2 && places[at - 2].column && strstr(message, "syntax error") &&
            strstr(message, "expecting") && strstr(message, "SEMICOLON")) {
            spot.line = places[at - 2].line;
            spot.column = places[at - 2].column + places[at - 2].length;
            spot.moved = 1;
        }
        int name = spot.moved ? -1 : call_unit(src, places, at - 1, message);
        if (name >= 0) {
            spot.line = places[name].line;
            spot.column = places[name].column;
        }
    }
    spot.message = halo_strdup(message);
    for (size_t n = spot.message ? strlen(spot.message) : 0; n > 0 && strchr(" \r", spot.message[n - 1]); n--)
        spot.message[n - 1] = '\0';
    halo_glsl_spot *items = realloc(out->items, (size_t)(out->count + 1) * sizeof *items);
    if (!items || !spot.message) {
        free(spot.message);
        if (items)
            out->items = items;
        return -1;
    }
    out->items = items;
    out->items[out->count++] = spot;
    return 0;
}

int halo_glsl_locate(const char *source, int vertex, const char *file, halo_glsl_spots *out)
{
    out->items = NULL;
    out->count = 0;
    halo_strbuf text = {0};
    unit_place *places = NULL;
    int count = 0, split = split_text(source, &text, &places, &count);
    if (split) {
        halo_strbuf_free(&text);
        return split < 0 ? -1 : 0;
    }
    halo_glslang_result r; /* compiled as validate.c compiles it */
    int status = halo_glslang_compile(text.data ? text.data : "", vertex, file, HALO_GLSLANG_NO_LINK, &r);
    if (!status) {
        char *cursor = NULL; /* strtok_r: another thread may be reading its own log */
        for (char *line = strtok_r(r.log, "\n", &cursor); line && !status; line = strtok_r(NULL, "\n", &cursor))
            status = add_spot(out, line, file, source, places, count);
        halo_glslang_result_free(&r);
    }
    free(places);
    halo_strbuf_free(&text);
    return status;
}

/* Column (1-based) of the occurrence-th whole token `name` (n bytes) in line, or 0. */
static int token_column(const char *line, const char *name, size_t n, int occurrence)
{
    halo_token_list t;
    if (!line || !n || halo_lex(line, &t))
        return 0;
    int column = 0;
    for (size_t i = 0; i < t.count && !column; i++)
        if (t.items[i].length == n && !memcmp(line + t.items[i].offset, name, n) && occurrence-- == 0)
            column = t.items[i].column;
    halo_token_list_free(&t);
    return column;
}

/* The name a reader wrote for a name the linker renamed: halo_<stage>_helper is helper
 * where the original line has helper and not the long name. Returns its offset in name
 * (0: not renamed). */
static size_t written_name(const char *original, const char *name, size_t n)
{
    if (n <= 5 || strncmp(name, "halo_", 5) || token_column(original, name, n, 0))
        return 0;
    for (size_t i = 5; i + 1 < n; i++)
        if (name[i] == '_' && token_column(original, name + i + 1, n - i - 1, 0))
            return i + 1;
    return 0;
}

/* The message with renamed names as the original line writes them. */
static char *unrenamed(const char *message, const char *original)
{
    halo_strbuf b = {0};
    for (const char *p = message; *p;) {
        size_t n = 0;
        if ((isalpha((unsigned char)*p) || *p == '_') &&
            (p == message || !(isalnum((unsigned char)p[-1]) || p[-1] == '_')))
            while (isalnum((unsigned char)p[n]) || p[n] == '_')
                n++;
        if (!n) {
            halo_strbuf_append_n(&b, p++, 1);
            continue;
        }
        size_t skip = original ? written_name(original, p, n) : 0;
        halo_strbuf_append_n(&b, p + skip, n - skip);
        p += n;
    }
    halo_strbuf_append(&b, "");
    return halo_strbuf_take(&b);
}

/* Column in the original line of the token at column `column` of the compiled line
 * (or of its end, with at_end): the same column where the linker left the line as it
 * was, else the same token counted in both lines. 0 when unknown. */
static int original_column(const char *compiled, const char *original, int column, int at_end)
{
    if (!compiled || !original || column < 1)
        return 0;
    if (!strcmp(compiled, original))
        return column;
    halo_token_list a, b;
    if (halo_lex(compiled, &a))
        return 0;
    if (halo_lex(original, &b)) {
        halo_token_list_free(&a);
        return 0;
    }
    int result = 0;
    for (size_t k = 0; k < a.count && !result; k++) {
        const halo_token *t = &a.items[k];
        if ((at_end ? t->column + (int)t->length : t->column) != column)
            continue;
        if (a.count == b.count) {
            result = b.items[k].column + (at_end ? (int)b.items[k].length : 0);
        } else {
            /* the same occurrence of the same (written) name */
            const char *name = compiled + t->offset;
            size_t n = t->length, skip = written_name(original, name, n);
            int occurrence = 0;
            for (size_t j = 0; j < k; j++)
                occurrence += a.items[j].length == n && !memcmp(compiled + a.items[j].offset, name, n);
            int c = token_column(original, name + skip, n - skip, occurrence);
            result = c && at_end ? c + (int)(n - skip) : c;
        }
    }
    halo_token_list_free(&a);
    halo_token_list_free(&b);
    return result;
}

/* Line `line` (1-based) of text, copied; NULL when there is none. */
static char *text_line(const char *text, int line)
{
    for (int i = 1; text && i < line; i++) {
        text = strchr(text, '\n');
        if (text)
            text++;
    }
    if (!text || line < 1)
        return NULL;
    size_t n = strcspn(text, "\n");
    char *s = malloc(n + 1);
    if (s) {
        memcpy(s, text, n);
        s[n] = '\0';
    }
    return s;
}

/* glslang puts some errors at the token where it found them (a call's ')', a
 * declaration's name) while the message names another ('f', '='): the named token
 * nearest before the column on the compiled line, else the first after it. */
static int named_token_column(const char *source, int line, const char *token, int column)
{
    char *compiled = text_line(source, line);
    halo_token_list t;
    if (!compiled || halo_lex(compiled, &t)) {
        free(compiled);
        return column;
    }
    int before = 0, after = 0;
    for (size_t i = 0; i < t.count; i++) {
        const halo_token *k = &t.items[i];
        size_t n = strlen(token);
        /* a punctuator token of glslang ('+=') spans several of the lexer's */
        if (strncmp(compiled + k->offset, token, n) || (k->kind != HALO_TOK_PUNCT && k->length != n))
            continue;
        if (k->column <= column)
            before = k->column;
        else if (!after)
            after = k->column;
    }
    halo_token_list_free(&t);
    free(compiled);
    return before ? before : after ? after : column;
}

/* A later error on a line that already has one follows from it (glslang goes on with a
 * placeholder: a float for a failed call, a syntax error after an unknown type name):
 * one problem, one message, as clang. Another undeclared name is another problem. */
int halo_glsl_follows_earlier_error(const char *message) { return !strstr(message, "undeclared identifier"); }


void halo_glsl_place(halo_glsl_spots *spots, const char *message, int *line, int *column, int *at_end)
{
    *column = *at_end = 0;
    for (int i = 0; spots && i < spots->count; i++) {
        halo_glsl_spot *s = &spots->items[i];
        if (s->used || s->reported_line != *line || strcmp(s->message, message))
            continue;
        s->used = 1;
        if (!s->column)
            return;
        *line = s->line;
        *column = s->column;
        *at_end = s->moved;
        return;
    }
}

int halo_glsl_original_column(const char *source, int line, int column, int at_end, const char *message,
                              const char *original)
{
    char token[256];
    named_token(message, token, sizeof token);
    if (column && !at_end && token[0])
        column = named_token_column(source, line, token, column);
    char *compiled = column ? text_line(source, line) : NULL;
    int result = column ? original_column(compiled, original, column, at_end) : 0;
    free(compiled);
    if (!result && token[0] == '#')
        result = token_column(original, "#", 1, 0); /* a directive */
    if (!result && token[0] && original) {
        size_t skip = written_name(original, token, strlen(token));
        result = token_column(original, token + skip, strlen(token) - skip, 0);
    }
    return result;
}

/* glslang writes a type as ' temp mediump int': its storage (temp, global) and
 * precision are its own bookkeeping and make one error read differently per target
 * (check prints an error once for the targets that share its text). In place. */
static void plain_types(char *s)
{
    static const char *const bookkeeping[] = {"temp", "global", "highp", "mediump", "lowp"};
    char *out = s;
    int quoted = 0;
    for (const char *p = s; *p;) {
        if (!quoted && p[0] == ' ' && p[1] == ' ') { /* "'=' :  cannot": one space */
            p++;
            continue;
        }
        if (p[0] != '\'' || quoted || p[1] != ' ') {
            quoted ^= *p == '\'';
            *out++ = *p++;
            continue;
        }
        *out++ = *p++; /* an opening quote and a space: a type's words, without the bookkeeping */
        int first = 1;
        while (*p == ' ') {
            const char *word = p + 1;
            size_t n = strcspn(word, " '");
            int drop = 0;
            for (size_t i = 0; i < sizeof bookkeeping / sizeof bookkeeping[0]; i++)
                drop |= strlen(bookkeeping[i]) == n && !strncmp(word, bookkeeping[i], n);
            if (!drop) {
                if (!first)
                    *out++ = ' ';
                memmove(out, word, n);
                out += n;
                first = 0;
            }
            p = word + n;
        }
        if (*p == '\'')
            *out++ = *p++; /* its closing quote */
    }
    *out = '\0';
}

char *halo_glsl_message(const char *message, const char *original)
{
    if (!strncmp(message, "'' :", 4)) { /* an empty token says nothing */
        message += 4;
        while (*message == ' ')
            message++;
    }
    char *text = unrenamed(message, original);
    if (text)
        plain_types(text);
    return text;
}

void halo_glsl_spots_free(halo_glsl_spots *s)
{
    for (int i = 0; i < s->count; i++)
        free(s->items[i].message);
    free(s->items);
    s->items = NULL;
    s->count = 0;
}
