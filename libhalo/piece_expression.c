/* The composer's expressions of a link from pieces (halo_pieces_desc: position, value,
 * ..., volume): each must be one GLSL expression of the kind its field needs, since the
 * sample piece passes it as one argument of a call (and writes the colour back to it).
 * Without this check `p); discard; (p`, `p //` or `; uniform float evil` went into the
 * piece as written: a piece that does not compile, or does something else.
 *
 * Checked here, without the engine's declarations: the characters (no statement end,
 * block, comment, preprocessor line or line break), the grammar of one expression (no
 * top-level comma, no assignment or ++/--: libhalo evaluates position several times),
 * balanced brackets, an lvalue for color and a plain designator for the samplers, and
 * the type where the expression itself says it (literals, constructors, a trailing
 * swizzle, texture(): `position=p.xy` is a vec2). The types of the engine's own names
 * are checked when the composed shader is validated (halo_validate with composed).
 * Each problem is reported at the expression as the file "NAME=EXPR" (what
 * `halo-validate link --sample` takes), line 1, at the column of the offending token. */
#include "diag.h"
#include "glsl_lex.h"
#include "internal.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

/* What the expression's value is, as far as its own text tells. */
typedef enum expr_type {
    TYPE_UNKNOWN = 0,
    TYPE_FLOAT, /* float, vec2, vec3, vec4: TYPE_FLOAT + components - 1 */
    TYPE_VEC2,
    TYPE_VEC3,
    TYPE_VEC4,
    TYPE_INT,
    TYPE_BOOL,
    TYPE_OTHER /* and after it: the other constructors' types (type_names), no field's */
} expr_type;

static const char *const type_names[] = {
    "?",      "float",  "vec2",   "vec3",   "vec4",   "int",    "bool",   "mat2",  "mat3",  "mat4",  "mat2x2", "mat2x3",
    "mat2x4", "mat3x2", "mat3x3", "mat3x4", "mat4x2", "mat4x3", "mat4x4", "ivec2", "ivec3", "ivec4", "uint",   "uvec2",
    "uvec3",  "uvec4",  "bvec2",  "bvec3",  "bvec4",  "double", "dvec2",  "dvec3", "dvec4", "dmat2", "dmat3",  "dmat4"};
#define TYPE_COUNT ((int)(sizeof type_names / sizeof type_names[0]))

/* The field's kind: a value of a type, a vec4 lvalue, or a sampler designator. */
typedef enum field_kind { FIELD_VALUE, FIELD_LVALUE, FIELD_SAMPLER } field_kind;

typedef struct token {
    size_t offset, length;
    int ident, number;
} token;

typedef struct parser {
    const char *text;
    token *tokens;
    size_t count, at;
    int failed;       /* an error was reported: stop */
    const char *name; /* the field */
    halo_diagnostics *diag;
    int es; /* GLSL ES: no implicit int -> float */
} parser;

typedef struct result {
    expr_type type;
    int designator; /* a name with [index] and .field only: an lvalue, or a sampler */
} result;

static void report(parser *ps, size_t offset, const char *fmt, const char *arg) __attribute__((format(printf, 3, 0)));
static void report(parser *ps, size_t offset, const char *fmt, const char *arg)
{
    if (ps->failed)
        return;
    ps->failed = 1;
    size_t n = strlen(ps->name);
    char *file = malloc(n + strlen(ps->text) + 2);
    if (file)
        sprintf(file, "%s=%s", ps->name, ps->text);
    halo_diagnostics_report(ps->diag, HALO_SEVERITY_ERROR, HALO_MSG_PIECE_EXPRESSION, file ? file : ps->name, 1,
                            (int)(n + 2 + offset), file, fmt, arg);
    free(file);
}

static int is(const parser *ps, const char *text)
{
    if (ps->at >= ps->count)
        return 0;
    const token *t = &ps->tokens[ps->at];
    return t->length == strlen(text) && !memcmp(ps->text + t->offset, text, t->length);
}

static size_t here(const parser *ps) { return ps->at < ps->count ? ps->tokens[ps->at].offset : strlen(ps->text); }

static void expect(parser *ps, const char *text, size_t opened_at)
{
    if (is(ps, text)) {
        ps->at++;
        return;
    }
    if (ps->at >= ps->count)
        report(ps, opened_at, "this bracket is never closed: the expression needs a '%s'", text);
    else
        report(ps, here(ps), "expected '%s' here", text);
}

/* Operators of more than one character, longest first. */
static const char *const long_operators[] = {"<<=", ">>=", "++", "--", "<<", ">>", "<=", ">=", "==", "!=", "&&",
                                             "||",  "^^",  "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", NULL};

/* GLSL's characters; a comment, a statement end, a block, a preprocessor line or a line
 * break has no place in one expression. 0 when the text is fine, else the offset + 1. */
static size_t bad_character(const char *text, const char **why)
{
    for (size_t i = 0; text[i]; i++) {
        unsigned char c = (unsigned char)text[i];
        *why = NULL;
        if (c == '/' && text[i + 1] == '/')
            *why = "a comment in the expression: '//' would comment out the rest of libhalo's line";
        else if (c == '/' && text[i + 1] == '*')
            *why =
                "a comment in the expression: '/*' hides what follows from the check and can span libhalo's "
                "lines; give the expression alone";
        else if (c == ';')
            *why = "';' ends a statement: give one expression, which libhalo passes as an argument";
        else if (c == '{' || c == '}')
            *why = "a block is not an expression: give one expression";
        else if (c == '#')
            *why = "a preprocessor directive has no place in an expression";
        else if (c == '\\')
            *why = "a line continuation has no place in an expression";
        else if (c == '\n' || c == '\r')
            *why = "the expression spans lines: give it on one line";
        else if (c != ' ' && c != '\t' && !isalnum(c) && !strchr("_.+-*/%<>[]()^|&~=!:?,", c))
            *why = "this character is not part of a GLSL expression";
        if (*why)
            return i + 1;
    }
    return 0;
}

/* halo_lex's tokens, with its one-character punctuation joined into GLSL's operators. */
static int tokenize(parser *ps)
{
    halo_token_list list;
    if (halo_lex(ps->text, &list))
        return -1;
    ps->tokens = calloc(list.count + 1, sizeof *ps->tokens);
    if (!ps->tokens) {
        halo_token_list_free(&list);
        return -1;
    }
    for (size_t i = 0; i < list.count; i++) {
        const halo_token *t = &list.items[i];
        token out = {t->offset, t->length, t->kind == HALO_TOK_IDENT, t->kind == HALO_TOK_NUMBER};
        if (t->kind == HALO_TOK_PUNCT)
            for (int k = 0; long_operators[k]; k++) {
                size_t n = strlen(long_operators[k]), joined = 1;
                while (joined < n && i + joined < list.count && list.items[i + joined].kind == HALO_TOK_PUNCT &&
                       list.items[i + joined].offset == t->offset + joined)
                    joined++;
                if (joined == n && !strncmp(ps->text + t->offset, long_operators[k], n)) {
                    out.length = n;
                    i += n - 1;
                    break;
                }
            }
        ps->tokens[ps->count++] = out;
    }
    halo_token_list_free(&list);
    return 0;
}

static result parse_expression(parser *ps);
static result parse_conditional(parser *ps);

/* float, vecN, int, bool, matrices, integer, boolean and double vectors (the constructors
 * whose type the expression names) */
static expr_type constructor_type(const char *s, size_t n)
{
    for (int t = TYPE_FLOAT; t < TYPE_COUNT; t++)
        if (strlen(type_names[t]) == n && !memcmp(type_names[t], s, n))
            return (expr_type)t;
    return TYPE_UNKNOWN;
}

/* Built-in functions whose result type their name fixes, or that of their first argument. */
static expr_type builtin_type(const char *s, size_t n, expr_type first)
{
    static const char *const floats[] = {"length", "distance", "dot", "determinant", NULL};
    static const char *const vec4s[] = {"texture",     "texelFetch",    "textureLod", "textureProj", "texture3D",
                                        "textureGrad", "textureOffset", "texture2D",  NULL};
    static const char *const same[] = {
        "abs",  "sign",       "floor",     "ceil",    "fract",       "mod",   "min",   "max",     "clamp", "mix",
        "step", "smoothstep", "normalize", "sqrt",    "inversesqrt", "pow",   "exp",   "exp2",    "log",   "log2",
        "sin",  "cos",        "tan",       "radians", "degrees",     "round", "trunc", "reflect", NULL};
    for (int k = 0; floats[k]; k++)
        if (strlen(floats[k]) == n && !memcmp(floats[k], s, n))
            return TYPE_FLOAT;
    for (int k = 0; vec4s[k]; k++)
        if (strlen(vec4s[k]) == n && !memcmp(vec4s[k], s, n))
            return TYPE_VEC4;
    if (n == 5 && !memcmp(s, "cross", 5))
        return TYPE_VEC3;
    for (int k = 0; same[k]; k++)
        if (strlen(same[k]) == n && !memcmp(same[k], s, n))
            return first == TYPE_INT && k >= 13 ? TYPE_UNKNOWN : first;
    return TYPE_UNKNOWN;
}

/* Words that no operand is: statements, qualifiers, declarations. */
static int statement_word(const char *s, size_t n)
{
    static const char *const words[] = {
        "uniform",   "const",  "in",       "out",       "inout",    "discard",   "return",  "if",      "else",
        "for",       "while",  "do",       "break",     "continue", "switch",    "case",    "default", "struct",
        "precision", "layout", "highp",    "mediump",   "lowp",     "attribute", "varying", "buffer",  "shared",
        "flat",      "smooth", "centroid", "invariant", "void",     NULL};
    for (int k = 0; words[k]; k++)
        if (strlen(words[k]) == n && !memcmp(words[k], s, n))
            return 1;
    return 0;
}

/* A swizzle's component count (".xyz": 3), or 0 when the field is no swizzle. */
static int swizzle_length(const char *s, size_t n)
{
    static const char *const sets[] = {"xyzw", "rgba", "stpq"};
    if (n < 1 || n > 4)
        return 0;
    for (int k = 0; k < 3; k++) {
        size_t i = 0;
        while (i < n && strchr(sets[k], s[i]))
            i++;
        if (i == n)
            return (int)n;
    }
    return 0;
}

/* A GLSL number literal: decimal, octal (a leading 0, digits 0-7) or hexadecimal integer
 * with an optional u; or a float, digits with a '.' or an exponent (e, sign, digits), with
 * an optional f or lf (lf: GLSL 4.00, which glslang checks for the target). */
static int valid_number(const char *s, size_t n)
{
    size_t i = 0;
    if (n > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
        for (i = 2; i < n && isxdigit((unsigned char)s[i]); i++)
            ;
        return i > 2 && (i == n || (i + 1 == n && (s[i] == 'u' || s[i] == 'U')));
    }
    size_t digits = 0;
    int dot = 0, exponent = 0;
    for (; i < n && isdigit((unsigned char)s[i]); i++)
        digits++;
    if (i < n && s[i] == '.') {
        dot = 1;
        for (i++; i < n && isdigit((unsigned char)s[i]); i++)
            digits++;
    }
    if (!digits)
        return 0;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        exponent = 1;
        i += i + 1 < n && (s[i + 1] == '+' || s[i + 1] == '-') ? 2 : 1;
        size_t first = i;
        for (; i < n && isdigit((unsigned char)s[i]); i++)
            ;
        if (i == first)
            return 0;
    }
    if (!dot && !exponent && s[0] == '0') /* octal */
        for (size_t k = 1; k < i; k++)
            if (s[k] > '7')
                return 0;
    if (i == n)
        return 1;
    if (!dot && !exponent)
        return i + 1 == n && (s[i] == 'u' || s[i] == 'U');
    return (i + 1 == n && (s[i] == 'f' || s[i] == 'F')) ||
           (i + 2 == n && ((s[i] == 'l' && s[i + 1] == 'f') || (s[i] == 'L' && s[i + 1] == 'F')));
}

static result parse_primary(parser *ps)
{
    result r = {TYPE_UNKNOWN, 0};
    if (ps->at >= ps->count) {
        report(ps, here(ps), "the expression ends where an operand is expected%s", "");
        return r;
    }
    const token *t = &ps->tokens[ps->at];
    const char *s = ps->text + t->offset;
    if (t->number) {
        if (!valid_number(s, t->length)) {
            report(ps, t->offset, "not a GLSL number: digits with an optional '.', exponent and suffix%s", "");
            return r;
        }
        ps->at++;
        int real = memchr(s, '.', t->length) || ((memchr(s, 'e', t->length) || memchr(s, 'E', t->length)) &&
                                                 !(t->length > 1 && (s[1] == 'x' || s[1] == 'X')));
        r.type = real || s[t->length - 1] == 'f' || s[t->length - 1] == 'F' ? TYPE_FLOAT : TYPE_INT;
        return r;
    }
    if (is(ps, "(")) {
        size_t open = here(ps);
        ps->at++;
        r = parse_expression(ps);
        expect(ps, ")", open);
        return r; /* a bracketed designator stays one: (x) = ... is GLSL */
    }
    if (!t->ident) {
        report(ps, t->offset,
               is(ps, ")") || is(ps, "]") ? "this bracket closes one that was never opened%s"
                                          : "expected an operand here%s",
               "");
        return r;
    }
    if (statement_word(s, t->length)) {
        report(ps, t->offset, "a keyword of a statement or declaration: give one expression%s", "");
        return r;
    }
    ps->at++;
    if ((t->length == 4 && !memcmp(s, "true", 4)) || (t->length == 5 && !memcmp(s, "false", 5))) {
        r.type = TYPE_BOOL;
        return r;
    }
    if (is(ps, "(")) { /* a call or a constructor */
        size_t open = here(ps);
        ps->at++;
        expr_type first = TYPE_UNKNOWN;
        for (int k = 0; !ps->failed && !is(ps, ")") && ps->at < ps->count; k++) {
            if (k)
                expect(ps, ",", open);
            result a = parse_conditional(ps);
            if (!k)
                first = a.type;
        }
        expect(ps, ")", open);
        expr_type ctor = constructor_type(s, t->length);
        r.type = ctor ? ctor : builtin_type(s, t->length, first);
        return r;
    }
    if (t->length == 12 && !memcmp(s, "gl_FragCoord", 12))
        r.type = TYPE_VEC4;
    r.designator = 1;
    return r;
}

static result parse_postfix(parser *ps)
{
    result r = parse_primary(ps);
    while (!ps->failed && ps->at < ps->count) {
        if (is(ps, "[")) {
            size_t open = here(ps);
            ps->at++;
            parse_expression(ps);
            expect(ps, "]", open);
            r.type = r.type >= TYPE_VEC2 && r.type <= TYPE_VEC4 ? TYPE_FLOAT : TYPE_UNKNOWN;
        } else if (is(ps, ".")) {
            ps->at++;
            if (ps->at >= ps->count || !ps->tokens[ps->at].ident) {
                report(ps, here(ps), "expected a field or swizzle after '.'%s", "");
                break;
            }
            const token *f = &ps->tokens[ps->at++];
            int n = swizzle_length(ps->text + f->offset, f->length);
            r.type = n ? (expr_type)(TYPE_FLOAT + n - 1) : TYPE_UNKNOWN;
        } else if (is(ps, "++") || is(ps, "--")) {
            report(ps, here(ps), "'%s' changes the engine's state: libhalo evaluates the expression more than once",
                   is(ps, "++") ? "++" : "--");
        } else {
            break;
        }
    }
    return r;
}

static result parse_unary(parser *ps)
{
    if (is(ps, "++") || is(ps, "--")) {
        report(ps, here(ps), "'%s' changes the engine's state: libhalo evaluates the expression more than once",
               is(ps, "++") ? "++" : "--");
        return (result){TYPE_UNKNOWN, 0};
    }
    if (is(ps, "-") || is(ps, "+") || is(ps, "!") || is(ps, "~")) {
        int not = is(ps, "!");
        ps->at++;
        result r = parse_unary(ps);
        r.designator = 0;
        if (not )
            r.type = TYPE_BOOL;
        return r;
    }
    return parse_postfix(ps);
}

/* Binary operators by precedence, loosest first. */
static const char *const levels[][6] = {
    {"||"},       {"^^"},     {"&&"},          {"|"}, {"^"}, {"&"}, {"==", "!="}, {"<", ">", "<=", ">="},
    {"<<", ">>"}, {"+", "-"}, {"*", "/", "%"},
};
#define LEVEL_COUNT (sizeof levels / sizeof levels[0])

static int at_level(const parser *ps, size_t level)
{
    for (int k = 0; k < 6 && levels[level][k]; k++)
        if (is(ps, levels[level][k]))
            return 1;
    return 0;
}

/* The type of a op b, as far as it is known: a comparison is a bool; arithmetic with a
 * vector is that vector (or an error the compiler reports). */
static expr_type combine(size_t level, expr_type a, expr_type b)
{
    if (level <= 2 || level == 6 || level == 7)
        return TYPE_BOOL;
    if (level < 9)
        return a == b ? a : TYPE_UNKNOWN;
    if (a >= TYPE_VEC2 && a <= TYPE_VEC4)
        return a;
    if (b >= TYPE_VEC2 && b <= TYPE_VEC4)
        return b;
    return a == b ? a : TYPE_UNKNOWN;
}

static result parse_binary(parser *ps, size_t level)
{
    if (level == LEVEL_COUNT)
        return parse_unary(ps);
    result r = parse_binary(ps, level + 1);
    while (!ps->failed && at_level(ps, level)) {
        ps->at++;
        result b = parse_binary(ps, level + 1);
        r.type = combine(level, r.type, b.type);
        r.designator = 0;
    }
    return r;
}

static int assignment(const parser *ps)
{
    static const char *const ops[] = {"=", "+=", "-=", "*=", "/=", "%=", "<<=", ">>=", "&=", "|=", "^=", NULL};
    for (int k = 0; ops[k]; k++)
        if (is(ps, ops[k]))
            return 1;
    return 0;
}

static result parse_conditional(parser *ps)
{
    result r = parse_binary(ps, 0);
    if (!ps->failed && is(ps, "?")) {
        size_t q = here(ps);
        ps->at++;
        result a = parse_expression(ps);
        expect(ps, ":", q);
        result b = parse_conditional(ps);
        r.type = a.type == b.type ? a.type : TYPE_UNKNOWN;
        r.designator = 0;
    }
    if (!ps->failed && assignment(ps))
        report(ps, here(ps), "an assignment changes the engine's state: give a value (libhalo %s)",
               "evaluates the expression more than once, and writes the colour itself");
    return r;
}

/* In brackets, a comma is GLSL's sequence operator; at the top level it would split
 * libhalo's argument in two (parse_top refuses it). */
static result parse_expression(parser *ps)
{
    result r = parse_conditional(ps);
    while (!ps->failed && is(ps, ",")) {
        ps->at++;
        r = parse_conditional(ps);
        r.designator = 0; /* (a, b) is no lvalue */
    }
    return r;
}

static result parse_top(parser *ps)
{
    result r = parse_conditional(ps);
    if (!ps->failed && is(ps, ","))
        report(ps, here(ps), "a comma at the top level would pass libhalo's call two arguments: give one %s",
               "expression");
    else if (!ps->failed && ps->at < ps->count)
        report(ps, here(ps),
               is(ps, ")") || is(ps, "]") ? "this bracket closes one that was never opened%s"
                                          : "the expression ends before this: give one expression%s",
               "");
    return r;
}

/* One field's expression: 0 when it is fine, 1 after its error. */
static int check_one(const char *name, const char *text, field_kind kind, expr_type expected, int es,
                     halo_diagnostics *diag)
{
    parser ps = {.text = text, .name = name, .diag = diag, .es = es};
    const char *why = NULL;
    size_t bad = bad_character(text, &why);
    if (bad) {
        report(&ps, bad - 1, "%s", why);
        return 1;
    }
    if (tokenize(&ps)) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return 1;
    }
    if (!ps.count)
        report(&ps, 0, "the expression is empty%s", "");
    result r = ps.failed ? (result){0, 0} : parse_top(&ps);
    if (!ps.failed && kind == FIELD_LVALUE && !r.designator)
        report(&ps, 0,
               "libhalo writes the colour back to %s: give a variable, an array element or a field "
               "(a vec4 lvalue, e.g. g_srcColor)",
               name);
    if (!ps.failed && kind == FIELD_SAMPLER && !r.designator)
        report(&ps, 0,
               "%s names a sampler3D the engine declares: give its name, an array element or a field "
               "(e.g. in_volume[0])",
               name);
    int converts = !es && r.type == TYPE_INT && expected == TYPE_FLOAT;
    if (!ps.failed && expected && r.type && r.type != expected && !converts) {
        char what[160];
        const char *type = type_names[r.type];
        snprintf(what, sizeof what, "the expression is a%s %s, but %s is a %s", type[0] == 'i' ? "n" : "", type, name,
                 type_names[expected]);
        report(&ps, 0, "%s", what);
    }
    free(ps.tokens);
    return ps.failed;
}

int halo_pieces_check_expressions(const halo_pieces_desc *d, halo_target target, halo_diagnostics *diag)
{
    const struct {
        const char *name, *text;
        field_kind kind;
        expr_type type;
    } fields[] = {
        {"position", d->position, FIELD_VALUE, TYPE_VEC3},
        {"value", d->value, FIELD_VALUE, TYPE_FLOAT},
        {"gradient", d->gradient, FIELD_VALUE, TYPE_VEC3},
        {"view", d->view, FIELD_VALUE, TYPE_VEC3},
        {"depth", d->depth, FIELD_VALUE, TYPE_FLOAT},
        {"fragcoord", d->fragcoord, FIELD_VALUE, TYPE_VEC2},
        {"color", d->color, FIELD_LVALUE, TYPE_VEC4},
        {"volume", d->volume, FIELD_SAMPLER, TYPE_UNKNOWN},
        {"gradient_texture", d->gradient_texture, FIELD_SAMPLER, TYPE_UNKNOWN},
    };
    int errors = 0;
    for (size_t i = 0; i < sizeof fields / sizeof fields[0]; i++)
        if (fields[i].text)
            errors += check_one(fields[i].name, fields[i].text, fields[i].kind, fields[i].type,
                                target == HALO_TARGET_ES300, diag);
    return errors;
}
