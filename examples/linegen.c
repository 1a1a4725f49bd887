/* Line data (see linegen.h). */
#include "linegen.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "halo.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Upper bound on points, far beyond what an example renders; keeps sizes from overflowing. */
#define MAX_POINTS ((size_t)1 << 28)

void halo_polylines_free(halo_polylines *lines)
{
    if (!lines)
        return;
    free(lines->first);
    free(lines->points);
    memset(lines, 0, sizeof *lines);
}

/* ---- Building ---------------------------------------------------------------------- */

typedef struct builder {
    halo_polylines lines;
    size_t line_cap, point_cap;
    int failed;
} builder;

static int builder_begin_line(builder *b)
{
    if (b->failed)
        return 0;
    if (b->lines.line_count + 2 > b->line_cap) {
        size_t cap = b->line_cap ? b->line_cap * 2 : 64;
        size_t *first = realloc(b->lines.first, cap * sizeof *first);
        if (!first)
            return !(b->failed = 1);
        b->lines.first = first;
        b->line_cap = cap;
    }
    if (b->lines.line_count == 0)
        b->lines.first[0] = 0;
    b->lines.line_count++;
    b->lines.first[b->lines.line_count] = b->lines.point_count;
    return 1;
}

static int builder_point(builder *b, double x, double y, double z)
{
    if (b->failed)
        return 0;
    if (b->lines.point_count >= MAX_POINTS)
        return !(b->failed = 1);
    if (b->lines.point_count + 1 > b->point_cap) {
        size_t cap = b->point_cap ? b->point_cap * 2 : 1024;
        double *points = realloc(b->lines.points, cap * 3 * sizeof *points);
        if (!points)
            return !(b->failed = 1);
        b->lines.points = points;
        b->point_cap = cap;
    }
    double *p = &b->lines.points[3 * b->lines.point_count++];
    p[0] = x, p[1] = y, p[2] = z;
    b->lines.first[b->lines.line_count] = b->lines.point_count;
    return 1;
}

/* Drops the last line (e.g. a streamline too short to draw). */
static void builder_drop_line(builder *b)
{
    if (b->lines.line_count == 0)
        return;
    b->lines.line_count--;
    b->lines.point_count = b->lines.first[b->lines.line_count];
}

static halo_status builder_finish(builder *b, halo_polylines *out, halo_diagnostics *diag)
{
    if (b->failed) {
        halo_polylines_free(&b->lines);
        HALO_REPORT_ERROR(diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0,
                          "out of memory building polylines (at most %zu points)", (size_t)MAX_POINTS);
        return HALO_ERROR_IO;
    }
    *out = b->lines;
    return HALO_OK;
}

/* ---- The text format ---------------------------------------------------------------- */

static char *line_copy(const char *start, size_t length)
{
    char *copy = malloc(length + 1);
    if (copy) {
        memcpy(copy, start, length);
        copy[length] = '\0';
    }
    return copy;
}

typedef struct parser {
    builder b;
    const char *file;
    halo_diagnostics *diag;
    int errors, header, line_number, open_line;
    int bad_points; /* of the open polyline: reported where they are, counted as points */
    const char *source_line;
} parser;

static void parse_error(parser *ps, halo_message_id id, int column, const char *fmt, const char *arg)
{
    halo_diagnostics_report(ps->diag, HALO_SEVERITY_ERROR, id, ps->file, ps->line_number, column, ps->source_line, fmt,
                            arg);
    ps->errors++;
}

/* Reports the open polyline when it has fewer than two points (at its 'line' keyword).
 * A malformed point counts: it has its own error, and one problem is one message. */
static void close_line(parser *ps)
{
    const halo_polylines *l = &ps->b.lines;
    if (l->line_count == 0)
        return;
    size_t n = l->first[l->line_count] - l->first[l->line_count - 1];
    if (n + (size_t)ps->bad_points < 2) {
        halo_diagnostics_report(ps->diag, HALO_SEVERITY_ERROR, HALO_MSG_SCENE_VALUE_COUNT, ps->file, ps->open_line, 1,
                                NULL, "line %zu has %zu point%s; a polyline needs at least 2", l->line_count, n,
                                n == 1 ? "" : "s");
        ps->errors++;
    }
}

static int same_letters(const char *word, const char *lower)
{
    for (; *word && *lower; ++word, ++lower)
        if (tolower((unsigned char)*word) != *lower)
            return 0;
    return *word == *lower;
}

/* A word starting with a letter, other than what strtod reads as a non-finite number
 * (reported as such). */
static int is_keyword_like(const char *word)
{
    return isalpha((unsigned char)word[0]) && !same_letters(word, "nan") && !same_letters(word, "inf") &&
           !same_letters(word, "infinity");
}

/* One line of words (comments already removed). Returns 0 when memory ran out. */
static int parse_words(parser *ps, char **words, const int *columns, int count)
{
    if (count == 0)
        return 1;
    if (!ps->header) {
        ps->header = 1; /* after a bad header, go on checking the rest */
        if (strcmp(words[0], "halo-polylines") == 0) {
            if (count != 2 || strcmp(words[1], "1") != 0)
                parse_error(ps, HALO_MSG_SCENE_VERSION, columns[count > 1 ? 1 : 0],
                            "unsupported polyline format version%s (this reader knows 'halo-polylines 1')", "");
            return 1;
        }
        parse_error(ps, HALO_MSG_SCENE_VERSION, columns[0], "a polyline file starts with the line 'halo-polylines 1'%s",
                    "");
    }
    if (strcmp(words[0], "line") == 0) {
        close_line(ps);
        if (count > 1)
            parse_error(ps, HALO_MSG_SCENE_VALUE_COUNT, columns[1], "'line' takes no values%s", "");
        ps->open_line = ps->line_number;
        ps->bad_points = 0;
        return builder_begin_line(&ps->b);
    }
    if (is_keyword_like(words[0])) {
        parse_error(ps, HALO_MSG_SCENE_KEY_UNKNOWN, columns[0], "unknown keyword '%s' (expected 'line' or x y z)",
                    words[0]);
        return 1;
    }
    if (ps->b.lines.line_count == 0) {
        parse_error(ps, HALO_MSG_SCENE_KEY_UNKNOWN, columns[0], "a point before the first 'line'%s", "");
        return 1;
    }
    double xyz[3] = {0.0, 0.0, 0.0};
    int ok = 1;
    if (count != 3) {
        char n[32];
        snprintf(n, sizeof n, "%s%d", count > 8 ? "more than " : "", count > 8 ? 8 : count);
        parse_error(ps, HALO_MSG_SCENE_VALUE_COUNT, columns[count > 3 ? 3 : 0], "a point has 3 coordinates, not %s", n);
        ok = 0;
    }
    for (int i = 0; ok && i < 3; ++i) { /* a point of the wrong size is one error, not more */
        char *stop = NULL;
        errno = 0;
        double x = strtod(words[i], &stop);
        if (stop == words[i] || *stop != '\0') {
            parse_error(ps, HALO_MSG_SCENE_TYPE, columns[i], "'%s' is not a number", words[i]);
            ok = 0;
        } else if (!isfinite(x) || fabs(x) > 1e30) {
            parse_error(ps, HALO_MSG_SCENE_VALUE_NONFINITE, columns[i], "coordinate '%s' is not finite (|x| <= 1e30)",
                        words[i]);
            ok = 0;
        } else {
            xyz[i] = x;
        }
    }
    ps->bad_points += !ok;
    return !ok || builder_point(&ps->b, xyz[0], xyz[1], xyz[2]);
}

halo_status halo_polylines_parse(const char *text, const char *file, halo_polylines *out, halo_diagnostics *diag)
{
    memset(out, 0, sizeof *out);
    if (!text) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, file ? file : "", 0, 0, "no polyline text");
        return HALO_ERROR_INPUT;
    }
    parser ps = {.file = file ? file : "polylines", .diag = diag};
    const char *cursor = text;
    if (!strncmp(cursor, "\xEF\xBB\xBF", 3)) /* a UTF-8 byte-order mark (editors write it) */
        cursor += 3;
    while (*cursor && !ps.b.failed) {
        const char *end = strchr(cursor, '\n');
        size_t length = end ? (size_t)(end - cursor) : strlen(cursor);
        /* where the next line starts: length may lose a trailing '\r' below */
        const char *next = end ? end + 1 : cursor + length;
        ps.line_number++;
        char *row = line_copy(cursor, length), *source_line = line_copy(cursor, length);
        if (!row || !source_line) {
            free(row);
            free(source_line);
            ps.b.failed = 1;
            break;
        }
        if (length && row[length - 1] == '\r') {
            --length;
            row[length] = source_line[length] = '\0';
        }
        char *hash = strchr(row, '#');
        if (hash)
            *hash = '\0';
        char *words[9];
        int columns[9], count = 0;
        for (char *scan = row; *scan;) {
            while (*scan && isspace((unsigned char)*scan))
                ++scan;
            if (!*scan)
                break;
            if (count < 9) {
                words[count] = scan;
                columns[count] = (int)(scan - row) + 1;
            }
            count++;
            while (*scan && !isspace((unsigned char)*scan))
                ++scan;
            if (*scan)
                *scan++ = '\0';
        }
        ps.source_line = source_line;
        if (!parse_words(&ps, words, columns, count > 9 ? 9 : count))
            ps.b.failed = 1;
        ps.source_line = NULL;
        free(source_line);
        free(row);
        cursor = next;
    }
    if (ps.b.failed)
        return builder_finish(&ps.b, out, diag);
    if (!ps.header) {
        halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_SCENE_VERSION, ps.file, 1, 1, NULL,
                                "empty file: a polyline file starts with the line 'halo-polylines 1'");
        ps.errors++;
    } else {
        close_line(&ps);
        if (ps.b.lines.line_count == 0 && ps.errors == 0) {
            halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_SCENE_VALUE_COUNT, ps.file, ps.line_number, 1,
                                    NULL, "the file has no 'line'");
            ps.errors++;
        }
    }
    if (ps.errors) {
        halo_polylines_free(&ps.b.lines);
        return HALO_ERROR_INPUT;
    }
    return builder_finish(&ps.b, out, diag);
}

halo_status halo_polylines_load(const char *path, halo_polylines *out, halo_diagnostics *diag)
{
    memset(out, 0, sizeof *out);
    size_t len = 0;
    if (!path) {
        HALO_REPORT_ERROR(diag, HALO_MSG_IO_READ, "", 0, 0, "cannot open polyline file: no path");
        return HALO_ERROR_IO;
    }
    char *text = halo_read_text_file(path, "polyline file", &len, diag);
    if (!text)
        return HALO_ERROR_IO;
    if (memchr(text, '\0', len)) {
        free(text);
        HALO_REPORT_ERROR(diag, HALO_MSG_SCENE_TYPE, path, 0, 0, "'%s' is not a text file (it holds NUL bytes)", path);
        return HALO_ERROR_INPUT;
    }
    halo_status status = halo_polylines_parse(text, path, out, diag);
    free(text);
    return status;
}

int halo_polylines_write(const char *path, const halo_polylines *lines)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    fprintf(f, "halo-polylines 1\n# %zu lines, %zu points\n", lines->line_count, lines->point_count);
    for (size_t i = 0; i < lines->line_count; ++i) {
        fputs("line\n", f);
        for (size_t k = lines->first[i]; k < lines->first[i + 1]; ++k)
            fprintf(f, "%.9g %.9g %.9g\n", lines->points[3 * k], lines->points[3 * k + 1], lines->points[3 * k + 2]);
    }
    return fclose(f) == 0 ? 0 : -1;
}

/* ---- Streamlines of the ABC flow ---------------------------------------------------- */

static uint64_t splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

static double uniform01(uint64_t *state) { return (double)(splitmix64(state) >> 11) * 0x1.0p-53; }

/* The ABC flow at p (box coordinates, shifted by -pi). */
static void abc_flow(const double p[3], double out[3])
{
    const double a = sqrt(3.0), b = sqrt(2.0), c = 1.0;
    double x = p[0] + M_PI, y = p[1] + M_PI, z = p[2] + M_PI;
    out[0] = a * sin(z) + c * cos(y);
    out[1] = b * sin(x) + a * cos(z);
    out[2] = c * sin(y) + b * cos(x);
}

static void rk4_step(double p[3], double h)
{
    double k1[3], k2[3], k3[3], k4[3], q[3];
    abc_flow(p, k1);
    for (int i = 0; i < 3; ++i)
        q[i] = p[i] + 0.5 * h * k1[i];
    abc_flow(q, k2);
    for (int i = 0; i < 3; ++i)
        q[i] = p[i] + 0.5 * h * k2[i];
    abc_flow(q, k3);
    for (int i = 0; i < 3; ++i)
        q[i] = p[i] + h * k3[i];
    abc_flow(q, k4);
    for (int i = 0; i < 3; ++i)
        p[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
}

halo_status halo_linegen_streamlines(size_t target_points, int max_points, unsigned long long seed, halo_polylines *out,
                                     halo_diagnostics *diag)
{
    memset(out, 0, sizeof *out);
    if (target_points < 2 || target_points > MAX_POINTS || max_points < 2) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0, "streamlines: 2..%zu points and at least 2 per line",
                          (size_t)MAX_POINTS);
        return HALO_ERROR_INPUT;
    }
    builder b = {0};
    uint64_t state = seed;
    const double h = 0.01;
    while (b.lines.point_count < target_points && !b.failed) {
        double p[3];
        for (int i = 0; i < 3; ++i)
            p[i] = (2.0 * uniform01(&state) - 1.0) * M_PI;
        if (!builder_begin_line(&b))
            break;
        size_t want = target_points - b.lines.point_count;
        int limit = want < (size_t)max_points ? (int)want : max_points;
        if (limit < 2)
            limit = 2;
        for (int k = 0; k < limit; ++k) {
            if (fabs(p[0]) > M_PI || fabs(p[1]) > M_PI || fabs(p[2]) > M_PI)
                break;
            builder_point(&b, p[0], p[1], p[2]);
            rk4_step(p, h);
        }
        size_t n = b.lines.first[b.lines.line_count] - b.lines.first[b.lines.line_count - 1];
        if (n < 8) /* a seed right at the box's edge: too short to see */
            builder_drop_line(&b);
    }
    return builder_finish(&b, out, diag);
}

/* ---- Knotted tubes ---------------------------------------------------------------- */

static void knot_point(int p, int q, double t, double out[3])
{
    double r = 2.0 + cos(q * t);
    out[0] = r * cos(p * t);
    out[1] = r * sin(p * t);
    out[2] = -sin(q * t);
}

static void normalize3(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 0.0)
        v[0] /= n, v[1] /= n, v[2] /= n;
}

/* The unit tangent at point k of n on the closed knot: the central difference over
 * half a step on either side. */
static void knot_tangent(int p, int q, int k, int n, double tangent[3])
{
    double before[3], after[3];
    knot_point(p, q, 2.0 * M_PI * (k - 0.5) / (n - 1), before);
    knot_point(p, q, 2.0 * M_PI * (k + 0.5) / (n - 1), after);
    for (int i = 0; i < 3; ++i)
        tangent[i] = after[i] - before[i];
    normalize3(tangent);
}

halo_status halo_linegen_knot(int p, int q, int tube_lines, int points_per_line, double tube_radius,
                              halo_polylines *out, halo_diagnostics *diag)
{
    memset(out, 0, sizeof *out);
    if (p < 1 || q < 1 || p > 64 || q > 64 || tube_lines < 1 || tube_lines > 4096 || points_per_line < 2 ||
        points_per_line > 1000000 || !(tube_radius >= 0.0 && tube_radius < 1.0)) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0,
                          "knot: p, q in 1..64, 1..4096 tube lines, 2..1000000 points each, radius in [0, 1)");
        return HALO_ERROR_INPUT;
    }
    int n = points_per_line;
    double *centre = malloc((size_t)n * 3 * sizeof *centre), *normal = malloc((size_t)n * 3 * sizeof *normal);
    builder b = {0};
    if (!centre || !normal) {
        b.failed = 1;
    } else {
        /* Centre line and a rotation-minimizing frame: each normal is the previous one
         * with its component along the new tangent removed. */
        for (int k = 0; k < n; ++k)
            knot_point(p, q, 2.0 * M_PI * k / (n - 1), &centre[3 * k]);
        for (int k = 0; k < n; ++k) {
            double tangent[3];
            knot_tangent(p, q, k, n, tangent);
            double *nk = &normal[3 * k];
            if (k == 0) {
                double z[3] = {0.0, 0.0, 1.0};
                memcpy(nk, z, sizeof z);
            } else {
                memcpy(nk, &normal[3 * (k - 1)], 3 * sizeof *nk);
            }
            double along = nk[0] * tangent[0] + nk[1] * tangent[1] + nk[2] * tangent[2];
            for (int i = 0; i < 3; ++i)
                nk[i] -= along * tangent[i];
            normalize3(nk);
            /* the binormal goes into the next slot's scratch: recomputed below */
        }
        /* The transported frame does not close on the closed curve: spread the twist
         * between the last and the first normal over the line, so that the tube's lines
         * meet themselves. */
        double t0[3];
        knot_tangent(p, q, 0, n, t0);
        const double *n0 = &normal[0], *nl = &normal[3 * (n - 1)];
        double b0[3] = {t0[1] * n0[2] - t0[2] * n0[1], t0[2] * n0[0] - t0[0] * n0[2], t0[0] * n0[1] - t0[1] * n0[0]};
        double twist =
            atan2(nl[0] * b0[0] + nl[1] * b0[1] + nl[2] * b0[2], nl[0] * n0[0] + nl[1] * n0[1] + nl[2] * n0[2]);
        for (int line = 0; line < tube_lines && builder_begin_line(&b); ++line) {
            double angle0 = 2.0 * M_PI * line / tube_lines;
            for (int k = 0; k < n; ++k) {
                double tangent[3];
                knot_tangent(p, q, k, n, tangent);
                const double *nk = &normal[3 * k];
                double binormal[3] = {tangent[1] * nk[2] - tangent[2] * nk[1], tangent[2] * nk[0] - tangent[0] * nk[2],
                                      tangent[0] * nk[1] - tangent[1] * nk[0]};
                double point[3], angle = angle0 - twist * k / (n - 1);
                for (int i = 0; i < 3; ++i)
                    point[i] = centre[3 * k + i] + tube_radius * (cos(angle) * nk[i] + sin(angle) * binormal[i]);
                builder_point(&b, point[0], point[1], point[2]);
            }
        }
    }
    free(centre);
    free(normal);
    return builder_finish(&b, out, diag);
}
