/* The host's preprocessor structure (host_scan.h): comments, #if branches evaluated
 * under the target's predefined macros and the host's own object-like macros, and
 * #line. A small evaluator, not a preprocessor: what it cannot evaluate counts as
 * taken, so that it never reports a line that a compiler would see. */
#include "host_scan.h"
#include "internal.h"
#include "strbuf.h"

#include <ctype.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* ---- Comments ---- */

/* Splits source into code (comments blanked) and comment text (the rest blanked); both
 * keep every new line, so that line and column stay those of the source. */
static int split_comments(const char *source, halo_host_scan *s)
{
    size_t n = strlen(source);
    s->code = malloc(n + 1);
    s->comments = malloc(n + 1);
    if (!s->code || !s->comments)
        return -1;
    enum { CODE, LINE_COMMENT, BLOCK_COMMENT } state = CODE;
    for (size_t i = 0; i < n; i++) {
        char c = source[i];
        int delimiter = 0;
        if (state == CODE && c == '/' && (source[i + 1] == '/' || source[i + 1] == '*')) {
            state = source[i + 1] == '/' ? LINE_COMMENT : BLOCK_COMMENT;
            delimiter = 2;
        } else if (state == BLOCK_COMMENT && c == '*' && source[i + 1] == '/') {
            state = CODE;
            delimiter = 2;
        } else if (state == LINE_COMMENT && c == '\n') {
            state = CODE;
        }
        for (int k = 0; k < (delimiter ? 2 : 1); k++) {
            char at = source[i + (size_t)k];
            int keep = at == '\n' || at == '\r';
            s->code[i + (size_t)k] = keep || (!delimiter && state == CODE) ? at : ' ';
            s->comments[i + (size_t)k] = keep || (!delimiter && state != CODE) ? at : ' ';
        }
        if (delimiter)
            i++;
    }
    s->code[n] = s->comments[n] = '\0';
    return 0;
}

/* ---- Macros ---- */

static halo_host_macro *find_macro(const halo_host_scan *s, const char *name, size_t length)
{
    for (size_t i = 0; i < s->macro_count; i++)
        if (s->macros[i].length == length && !memcmp(s->macros[i].name, name, length))
            return &s->macros[i];
    return NULL;
}

static int define_macro(halo_host_scan *s, halo_host_macro m)
{
    halo_host_macro *old = find_macro(s, m.name, m.length);
    if (old) {
        *old = m;
        return 0;
    }
    if (s->macro_count == s->macro_cap) {
        size_t cap = s->macro_cap ? s->macro_cap * 2 : 16;
        halo_host_macro *l = realloc(s->macros, cap * sizeof *l);
        if (!l)
            return -1;
        s->macros = l;
        s->macro_cap = cap;
    }
    s->macros[s->macro_count++] = m;
    return 0;
}

static int predefine(halo_host_scan *s, const char *name, const char *value)
{
    return define_macro(
        s, (halo_host_macro){.name = name, .length = strlen(name), .value = value, .certain = 1, .predefined = 1});
}

static int predefine_target(halo_host_scan *s, halo_target target, halo_shader_kind kind)
{
    int err = 0;
    if (target == HALO_TARGET_ES300) {
        err |= predefine(s, "GL_ES", "1");
        err |= predefine(s, "__VERSION__", "300");
        if (kind == HALO_SHADER_FRAGMENT)
            err |= predefine(s, "GL_FRAGMENT_PRECISION_HIGH", "1");
    } else {
        err |= predefine(s, "GL_core_profile", "1");
        err |= predefine(s, "__VERSION__",
                         target == HALO_TARGET_GLSL450   ? "450"
                         : target == HALO_TARGET_GLSL150 ? "150"
                                                         : "330");
    }
    return err;
}

/* ---- #if expressions ---- */

typedef struct expr {
    const char *p;
    const halo_host_scan *scan;
    int depth;   /* macro expansion depth */
    int unknown; /* something the evaluator cannot decide */
    int nesting; /* of operands: bounded, for hostile input */
} expr;

static long parse_binary(expr *e, int min_prec);

static void skip_space(expr *e)
{
    while (*e->p == ' ' || *e->p == '\t' || *e->p == '\r')
        e->p++;
}

static size_t ident_length(const char *p)
{
    size_t n = 0;
    if (!isalpha((unsigned char)*p) && *p != '_')
        return 0;
    while (isalnum((unsigned char)p[n]) || p[n] == '_')
        n++;
    return n;
}

/* An integer literal (decimal, octal, hex, optional u); a float is unknown. */
static long parse_number(expr *e)
{
    char *end;
    long v = strtol(e->p, &end, 0);
    if (*end == 'u' || *end == 'U')
        end++;
    if (isalnum((unsigned char)*end) || *end == '.' || *end == '_') {
        e->unknown = 1;
        while (isalnum((unsigned char)*end) || *end == '.' || *end == '_')
            end++;
    }
    e->p = end;
    return v;
}

static long eval_macro(expr *e, const halo_host_macro *m)
{
    if (m->function_like || !m->certain || e->depth > 16) {
        e->unknown = 1;
        return 0;
    }
    expr inner = {m->value, e->scan, e->depth + 1, 0, e->nesting};
    long v = parse_binary(&inner, 1);
    skip_space(&inner);
    if (inner.unknown || *inner.p)
        e->unknown = 1;
    return v;
}

static long parse_unary(expr *e);

static long parse_operand(expr *e)
{
    skip_space(e);
    char c = *e->p;
    if (c == '!' || c == '-' || c == '+' || c == '~') {
        e->p++;
        long v = parse_unary(e);
        return c == '!' ? !v : c == '-' ? (long)(0UL - (unsigned long)v) : c == '~' ? ~v : v;
    }
    if (c == '(') {
        e->p++;
        long v = parse_binary(e, 1);
        skip_space(e);
        if (*e->p == ')')
            e->p++;
        else
            e->unknown = 1;
        return v;
    }
    if (isdigit((unsigned char)c))
        return parse_number(e);
    size_t n = ident_length(e->p);
    if (!n) {
        e->unknown = 1;
        if (c)
            e->p++;
        return 0;
    }
    const char *name = e->p;
    e->p += n;
    if (n == 7 && !memcmp(name, "defined", 7)) {
        skip_space(e);
        int paren = *e->p == '(';
        if (paren)
            e->p++;
        skip_space(e);
        size_t k = ident_length(e->p);
        const halo_host_macro *m = k ? find_macro(e->scan, e->p, k) : NULL;
        e->p += k;
        skip_space(e);
        if (paren && *e->p == ')')
            e->p++;
        else if (paren)
            e->unknown = 1;
        if (!k || (m && !m->certain))
            e->unknown = 1;
        return m != NULL;
    }
    const halo_host_macro *m = find_macro(e->scan, name, n);
    if (m)
        return eval_macro(e, m);
    e->unknown = 1; /* GLSL: an undefined name in #if is an error, not 0 */
    return 0;
}

static long parse_unary(expr *e)
{
    if (e->nesting >= 256) {
        e->unknown = 1;
        e->p += strlen(e->p);
        return 0;
    }
    e->nesting++;
    long v = parse_operand(e);
    e->nesting--;
    return v;
}

static const struct binary_op {
    const char *text;
    int prec;
} binary_ops[] = {
    {"||", 1}, {"&&", 2}, {"==", 6}, {"!=", 6}, {"<=", 7}, {">=", 7}, {"<<", 8}, {">>", 8}, {"|", 3},
    {"^", 4},  {"&", 5},  {"<", 7},  {">", 7},  {"+", 9},  {"-", 9},  {"*", 10}, {"/", 10}, {"%", 10},
};

/* Wrapping arithmetic, as unsigned: hostile input must not reach signed overflow. */
static long apply_op(expr *e, const char *op, long a, long b)
{
    unsigned long ua = (unsigned long)a, ub = (unsigned long)b;
    switch (op[0]) {
    case '|':
        return op[1] ? (a || b) : (a | b);
    case '&':
        return op[1] ? (a && b) : (a & b);
    case '=':
        return a == b;
    case '!':
        return a != b;
    case '<':
        return op[1] == '=' ? a <= b : op[1] == '<' ? (b >= 0 && b < 63 ? (long)(ua << b) : 0) : a < b;
    case '>':
        return op[1] == '=' ? a >= b : op[1] == '>' ? (b >= 0 && b < 63 ? a >> b : 0) : a > b;
    case '^':
        return a ^ b;
    case '+':
        return (long)(ua + ub);
    case '-':
        return (long)(ua - ub);
    case '*':
        return (long)(ua * ub);
    default:
        if (b == 0 || (b == -1 && a == LONG_MIN)) {
            e->unknown = 1;
            return 0;
        }
        return op[0] == '/' ? a / b : a % b;
    }
}

/* Precedence climbing over binary_ops. */
static long parse_binary(expr *e, int min_prec)
{
    long left = parse_unary(e);
    for (;;) {
        skip_space(e);
        const struct binary_op *op = NULL;
        for (size_t i = 0; i < sizeof binary_ops / sizeof binary_ops[0] && !op; i++)
            if (!strncmp(e->p, binary_ops[i].text, strlen(binary_ops[i].text)))
                op = &binary_ops[i];
        if (!op || op->prec < min_prec)
            return left;
        e->p += strlen(op->text);
        long right = parse_binary(e, op->prec + 1);
        left = apply_op(e, op->text, left, right);
    }
}

static halo_branch evaluate(const halo_host_scan *s, const char *text)
{
    expr e = {text, s, 0, 0, 0};
    long v = parse_binary(&e, 1);
    skip_space(&e);
    if (e.unknown || *e.p)
        return HALO_BRANCH_UNKNOWN;
    return v ? HALO_BRANCH_TAKEN : HALO_BRANCH_NOT_TAKEN;
}

/* ---- Conditional branches ---- */

typedef struct branch_frame {
    halo_branch parent, current, taken; /* taken: a previous branch of this #if was (maybe) taken */
    int condition_line;
} branch_frame;

/* Activity of a branch with condition c inside an enclosing activity. */
static halo_branch nested(halo_branch outer, halo_branch c)
{
    if (outer == HALO_BRANCH_NOT_TAKEN || c == HALO_BRANCH_NOT_TAKEN)
        return HALO_BRANCH_NOT_TAKEN;
    return outer == HALO_BRANCH_TAKEN && c == HALO_BRANCH_TAKEN ? HALO_BRANCH_TAKEN : HALO_BRANCH_UNKNOWN;
}

static halo_branch either(halo_branch a, halo_branch b)
{
    if (a == HALO_BRANCH_TAKEN || b == HALO_BRANCH_TAKEN)
        return HALO_BRANCH_TAKEN;
    return a == HALO_BRANCH_UNKNOWN || b == HALO_BRANCH_UNKNOWN ? HALO_BRANCH_UNKNOWN : HALO_BRANCH_NOT_TAKEN;
}

/* #elif and #else: the branch runs if no previous one was taken. */
static void next_branch(branch_frame *f, halo_branch c, int line)
{
    halo_branch rest = f->taken == HALO_BRANCH_TAKEN     ? HALO_BRANCH_NOT_TAKEN
                       : f->taken == HALO_BRANCH_UNKNOWN ? nested(HALO_BRANCH_UNKNOWN, c)
                                                         : c;
    f->current = nested(f->parent, rest);
    f->taken = either(f->taken, c);
    f->condition_line = line;
}

/* ---- Directives ---- */

typedef struct scan_state {
    branch_frame *stack;
    int depth, cap;
    int file, next_line; /* the origin of the next line */
} scan_state;

static halo_branch activity(const scan_state *st)
{
    return st->depth ? st->stack[st->depth - 1].current : HALO_BRANCH_TAKEN;
}

static int push_branch(scan_state *st, halo_branch c, int line)
{
    if (st->depth == st->cap) {
        int cap = st->cap ? st->cap * 2 : 8;
        branch_frame *f = realloc(st->stack, (size_t)cap * sizeof *f);
        if (!f)
            return -1;
        st->stack = f;
        st->cap = cap;
    }
    halo_branch outer = activity(st);
    st->stack[st->depth++] = (branch_frame){outer, nested(outer, c), c, line};
    return 0;
}

static int add_name(halo_host_scan *s, const char *name, size_t n)
{
    char **l = realloc(s->names, (s->name_count + 1) * sizeof *l);
    if (!l)
        return -1;
    s->names = l;
    char *copy = malloc(n + 1);
    if (!copy)
        return -1;
    memcpy(copy, name, n);
    copy[n] = '\0';
    s->names[s->name_count++] = copy;
    return (int)s->name_count;
}

/* #line N, #line N source-string, #line N "file" (GL_GOOGLE_cpp_style_line_directive).
 * In GLSL 330 and ES 300 on, N is the number of the next line. */
static int line_directive(halo_host_scan *s, scan_state *st, const char *args, int physical)
{
    while (*args == ' ' || *args == '\t')
        args++;
    if (!isdigit((unsigned char)*args))
        return 0;
    char *end;
    long n = strtol(args, &end, 10);
    while (*end == ' ' || *end == '\t')
        end++;
    if (*end == '"') {
        const char *close = strchr(end + 1, '"');
        if (!close)
            return 0;
        int k = add_name(s, end + 1, (size_t)(close - end - 1));
        if (k < 0)
            return -1;
        st->file = k;
    }
    st->next_line = n < 1 << 30 ? (int)n : 1 << 30; /* and no overflow counting on */
    s->lines[physical].line_directive = 1;
    return 0;
}

static int define_directive(halo_host_scan *s, const char *args, const char *line_text, int physical, halo_branch act)
{
    while (*args == ' ' || *args == '\t')
        args++;
    size_t n = ident_length(args);
    if (!n)
        return 0;
    const char *value = args + n;
    halo_host_macro m = {
        args, n, value, physical + 1, (int)(args - line_text) + 1, *value == '(', act == HALO_BRANCH_TAKEN, 0};
    if (m.function_like) {
        const char *close = strchr(value, ')');
        m.value = close ? close + 1 : value + strlen(value);
    }
    return define_macro(s, m);
}

static void undef_directive(halo_host_scan *s, const char *args, halo_branch act)
{
    while (*args == ' ' || *args == '\t')
        args++;
    size_t n = ident_length(args);
    halo_host_macro *m = n ? find_macro(s, args, n) : NULL;
    if (!m)
        return;
    if (act != HALO_BRANCH_TAKEN) {
        m->certain = 0;
        return;
    }
    *m = s->macros[--s->macro_count];
}

/* One line's directive, if any. */
static int directive(halo_host_scan *s, scan_state *st, int i)
{
    const char *text = s->code_lines[i], *p = text;
    while (*p == ' ' || *p == '\t')
        p++;
    if (*p != '#')
        return 0;
    p++;
    while (*p == ' ' || *p == '\t')
        p++;
    size_t n = ident_length(p);
    const char *args = p + n;
#define IS(word) (n == sizeof word - 1 && !memcmp(p, word, n))
    halo_branch act = activity(st);
    if (IS("if"))
        return push_branch(st, evaluate(s, args), i + 1);
    if (IS("ifdef") || IS("ifndef")) {
        while (*args == ' ' || *args == '\t')
            args++;
        size_t k = ident_length(args);
        const halo_host_macro *m = k ? find_macro(s, args, k) : NULL;
        halo_branch c = !k || (m && !m->certain)     ? HALO_BRANCH_UNKNOWN
                        : (m != NULL) == IS("ifdef") ? HALO_BRANCH_TAKEN
                                                     : HALO_BRANCH_NOT_TAKEN;
        return push_branch(st, c, i + 1);
    }
    if (IS("elif") && st->depth)
        next_branch(&st->stack[st->depth - 1], evaluate(s, args), i + 1);
    else if (IS("else") && st->depth)
        next_branch(&st->stack[st->depth - 1], HALO_BRANCH_TAKEN, i + 1);
    else if (IS("endif") && st->depth)
        st->depth--;
    else if (act == HALO_BRANCH_NOT_TAKEN)
        return 0;
    else if (IS("define"))
        return define_directive(s, args, text, i, act);
    else if (IS("undef"))
        undef_directive(s, args, act);
    else if (IS("line"))
        return line_directive(s, st, args, i);
#undef IS
    return 0;
}

#define STRING_OF(x)   #x
#define NUMBER_TEXT(x) STRING_OF(x)

/* The macros the libhalo declarations see; after them HALO_LINKED and
 * HALO_CONTRACT_VERSION are defined. */
static int marker(halo_host_scan *s, int i)
{
    s->marker_line = i + 1;
    s->marker_macros = malloc((s->macro_count + 1) * sizeof *s->marker_macros);
    if (!s->marker_macros)
        return -1;
    memcpy(s->marker_macros, s->macros, s->macro_count * sizeof *s->macros);
    s->marker_macro_count = s->macro_count;
    return predefine(s, "HALO_LINKED", "1") | predefine(s, "HALO_CONTRACT_VERSION", NUMBER_TEXT(HALO_CONTRACT_VERSION));
}

int halo_host_scan_run(const halo_host_scan_desc *desc, halo_host_scan *s)
{
    memset(s, 0, sizeof *s);
    if (split_comments(desc->source, s) || halo_lex(s->comments, &s->comment_tokens))
        return -1;
    int n = halo_split_lines(s->code, &s->code_lines);
    if (n < 0 || halo_split_lines(s->comments, &s->comment_lines) != n)
        return -1;
    s->line_count = n;
    s->lines = calloc((size_t)n + 1, sizeof *s->lines);
    if (!s->lines || halo_lex(desc->source, &s->tokens) || predefine_target(s, desc->target, desc->kind))
        return -1;
    scan_state st = {.next_line = 1};
    int err = 0;
    for (int i = 0; i < n && !err; i++) {
        halo_host_line_info *l = &s->lines[i];
        l->file = st.file;
        l->line = st.next_line++;
        halo_branch before = activity(&st);
        err = directive(s, &st, i);
        halo_branch after = activity(&st);
        /* A directive line is compiled when either side of it is. */
        l->activity = (unsigned char)either(before, after);
        for (int k = 0; k < st.depth && l->activity == HALO_BRANCH_NOT_TAKEN && !l->condition_line; k++)
            if (st.stack[k].current == HALO_BRANCH_NOT_TAKEN)
                l->condition_line = st.stack[k].condition_line;
        if (!err && !s->marker_line && before != HALO_BRANCH_NOT_TAKEN && desc->is_marker(s->code_lines[i]))
            err = marker(s, i);
    }
    free(st.stack);
    return err ? -1 : 0;
}

void halo_host_scan_free(halo_host_scan *s)
{
    free(s->code);
    free(s->comments);
    free(s->code_lines);
    free(s->comment_lines);
    free(s->lines);
    halo_token_list_free(&s->tokens);
    halo_token_list_free(&s->comment_tokens);
    free(s->macros);
    free(s->marker_macros);
    for (size_t i = 0; i < s->name_count; i++)
        free(s->names[i]);
    free(s->names);
    memset(s, 0, sizeof *s);
}

/* ---- Queries ---- */

void halo_host_scan_origin(const halo_host_scan *s, const char *host_file, int line, const char **file,
                           int *origin_line)
{
    *file = host_file;
    *origin_line = line;
    if (line < 1 || line > s->line_count)
        return;
    const halo_host_line_info *l = &s->lines[line - 1];
    if (l->file > 0)
        *file = s->names[l->file - 1];
    *origin_line = l->line;
}

int halo_host_scan_compiled(const halo_host_scan *s, int line)
{
    return line < 1 || line > s->line_count || s->lines[line - 1].activity != HALO_BRANCH_NOT_TAKEN;
}

static int is_directive(const halo_host_scan *s, int line)
{
    const char *text = s->code_lines[line - 1];
    return text[strspn(text, " \t")] == '#';
}

/* First `name (`, or name in a #define (a call through a macro), in tokens on lines that
 * are compiled (want 1) or not (want 0); s NULL: any line. */
static const halo_token *find_call_in(const char *text, const halo_token_list *t, const halo_host_scan *s,
                                      const char *name, int want)
{
    for (size_t i = 0; i < t->count; i++) {
        const halo_token *k = &t->items[i];
        if (k->kind != HALO_TOK_IDENT || !halo_token_is(text, k, name))
            continue;
        int called =
            (i + 1 < t->count && halo_token_is(text, &t->items[i + 1], "(")) || (s && is_directive(s, k->line));
        if (called && (!s || halo_host_scan_compiled(s, k->line) == want))
            return k;
    }
    return NULL;
}

int halo_host_scan_find_call(const halo_host_scan *s, const char *name, halo_host_hit *unused)
{
    *unused = (halo_host_hit){0};
    if (find_call_in(s->code, &s->tokens, s, name, 1))
        return 1;
    const halo_token *dead = find_call_in(s->code, &s->tokens, s, name, 0);
    const halo_token *commented = find_call_in(s->comments, &s->comment_tokens, NULL, name, 1);
    if (commented && (!dead || commented->line < dead->line))
        *unused = (halo_host_hit){commented->line, commented->column, 1};
    else if (dead)
        *unused = (halo_host_hit){dead->line, dead->column, 0};
    return 0;
}

const halo_host_macro *halo_host_scan_macro(const halo_host_scan *s, const char *text, size_t length)
{
    for (size_t i = 0; i < s->marker_macro_count; i++) {
        const halo_host_macro *m = &s->marker_macros[i];
        if (m->length == length && !memcmp(m->name, text, length))
            return m->predefined ? NULL : m;
    }
    return NULL;
}

size_t halo_host_scan_unlocated_outputs(const halo_host_scan *s, const char *source, halo_host_hit *at, size_t max)
{
    const halo_token *out = NULL;
    int located = 0;
    size_t n = 0;
    for (size_t i = 0; i < s->tokens.count; i++) {
        const halo_token *k = &s->tokens.items[i];
        if (!halo_host_scan_compiled(s, k->line) || is_directive(s, k->line))
            continue;
        if (halo_token_is(source, k, "location"))
            located = 1;
        if (k->depth == 0 && halo_token_is(source, k, "out") && !out)
            out = k;
        /* A global declaration ends at its ';'; a function body or a block resets. */
        if (k->depth ||
            !(halo_token_is(source, k, ";") || halo_token_is(source, k, "{") || halo_token_is(source, k, "}")))
            continue;
        if (out && !located && halo_token_is(source, k, ";")) {
            if (n < max)
                at[n] = (halo_host_hit){out->line, out->column, 0};
            n++;
        }
        out = NULL;
        located = 0;
    }
    return n;
}
