#include "diag.h"
#include "strbuf.h"

#include <errno.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

struct halo_diagnostics {
    halo_diagnostic *items;
    size_t count, cap;
    size_t limit;                       /* kept per kind (errors; warnings and notes); 0: no cap */
    int limit_set;                      /* limit was given (else the default) */
    size_t kept_errors;                 /* errors among items */
    size_t dropped[3];                  /* left out by the cap, per severity */
    unsigned char seen[HALO_MSG_COUNT]; /* ids added, kept or not */
    /* Runs (halo_diagnostics_set_run): their names, the current one, each item's runs as
     * bits, and a hash of the items (indices + 1, 0 empty) that finds an earlier run's. */
    char *run_names[HALO_DIAGNOSTICS_MAX_RUNS];
    int run_count, run;  /* run: index + 1 of the current run, 0 none */
    uint32_t *item_runs; /* per item, parallel to items */
    size_t *hash;
    size_t hash_cap;
};

static const char *const message_names[] = {
#define HALO_X_NAME(id, text) #id,
    HALO_MESSAGES(HALO_X_NAME)
#undef HALO_X_NAME
};

/* The setup logger is per thread (halo.h, "Threads"): a thread's halo_setup installs
 * it for the calls that thread makes, so one thread's diagnostics never reach another
 * thread's logger; it goes with that thread's last halo_shutdown. */
static _Thread_local struct {
    void (*logger)(const halo_diagnostic *, void *);
    void *user_data;
    long setups; /* this thread's halo_setup calls not yet paired with halo_shutdown */
} thread_logger;

void halo_diag_thread_setup(const halo_setup_desc *desc)
{
    thread_logger.setups++;
    if (desc) {
        thread_logger.logger = desc->logger;
        thread_logger.user_data = desc->user_data;
    }
}

void halo_diag_thread_shutdown(void)
{
    if (thread_logger.setups > 0 && --thread_logger.setups == 0) {
        thread_logger.logger = NULL;
        thread_logger.user_data = NULL;
    }
}

const char *halo_message_name(halo_message_id id)
{
    return (unsigned)id < HALO_MSG_COUNT ? message_names[id] : "UNKNOWN";
}

halo_diagnostics *halo_diagnostics_create(void) { return calloc(1, sizeof(halo_diagnostics)); }

static void free_item(halo_diagnostic *d)
{
    free((char *)d->file);
    free((char *)d->text);
    free((char *)d->source_line);
}

void halo_diagnostics_clear(halo_diagnostics *d)
{
    if (!d)
        return;
    for (size_t i = 0; i < d->count; i++)
        free_item(&d->items[i]);
    for (int r = 0; r < d->run_count; r++)
        free(d->run_names[r]);
    d->run_count = d->run = 0;
    if (d->hash)
        memset(d->hash, 0, d->hash_cap * sizeof *d->hash);
    d->count = 0;
    d->kept_errors = 0;
    memset(d->dropped, 0, sizeof d->dropped);
    memset(d->seen, 0, sizeof d->seen);
}

void halo_diagnostics_destroy(halo_diagnostics *d)
{
    if (!d)
        return;
    halo_diagnostics_clear(d);
    free(d->items);
    free(d->item_runs);
    free(d->hash);
    free(d);
}

const halo_diagnostic *halo_diagnostics_get(const halo_diagnostics *d, size_t i)
{
    return d && i < d->count ? &d->items[i] : NULL;
}

static size_t diag_limit(const halo_diagnostics *d)
{
    return d && d->limit_set ? d->limit : HALO_DIAGNOSTICS_DEFAULT_LIMIT;
}

halo_diagnostics_info halo_diagnostics_describe(const halo_diagnostics *d)
{
    halo_diagnostics_info info = {0};
    info.limit = diag_limit(d);
    if (!d)
        return info;
    info.count = d->count;
    info.errors = d->kept_errors + d->dropped[HALO_SEVERITY_ERROR];
    info.dropped = d->dropped[0] + d->dropped[1] + d->dropped[2];
    return info;
}

int halo_diagnostics_has(const halo_diagnostics *d, halo_message_id id)
{
    return d && (unsigned)id < HALO_MSG_COUNT && d->seen[id];
}

void halo_diagnostics_set_limit(halo_diagnostics *d, size_t limit)
{
    if (!d)
        return;
    d->limit = limit;
    d->limit_set = 1;
}

int halo_diag_kept(const halo_diagnostics *d, halo_severity severity)
{
    size_t limit = diag_limit(d);
    size_t kept = !d ? 0 : severity == HALO_SEVERITY_ERROR ? d->kept_errors : d->count - d->kept_errors;
    return !d || !limit || kept < limit;
}

/* Whether the cap leaves a diagnostic of this severity out (then it is counted). */
static int over_limit(halo_diagnostics *d, halo_severity severity)
{
    if (halo_diag_kept(d, severity))
        return 0;
    d->dropped[(unsigned)severity < 3 ? severity : HALO_SEVERITY_NOTE]++;
    return 1;
}

/* ---- Runs: one input checked several times (for each target) ---- */

static size_t hash_text(size_t h, const char *s)
{
    for (; s && *s; s++)
        h = (h ^ (unsigned char)*s) * 1099511628211u;
    return h * 1099511628211u;
}

static size_t hash_item(const halo_diagnostic *g)
{
    size_t h = 14695981039346656037u ^ (size_t)g->severity;
    h = (h ^ (size_t)g->id) * 1099511628211u;
    h = (h ^ (size_t)(unsigned)g->line) * 1099511628211u;
    h = (h ^ (size_t)(unsigned)g->column) * 1099511628211u;
    return hash_text(hash_text(h, g->file), g->text);
}

static int same_item(const halo_diagnostic *a, const halo_diagnostic *b)
{
    return a->severity == b->severity && a->id == b->id && a->line == b->line && a->column == b->column &&
           !strcmp(a->file, b->file) && !strcmp(a->text, b->text);
}

/* The slot of g in the hash: where it is, or the empty slot where it would go. */
static size_t *hash_slot(const halo_diagnostics *d, const halo_diagnostic *g)
{
    size_t mask = d->hash_cap - 1;
    for (size_t i = hash_item(g) & mask;; i = (i + 1) & mask)
        if (!d->hash[i] || same_item(&d->items[d->hash[i] - 1], g))
            return &d->hash[i];
}

/* Keeps the hash at most half full; 0 when memory ran out. */
static int hash_reserve(halo_diagnostics *d, size_t items)
{
    if (items * 2 < d->hash_cap)
        return 1;
    size_t cap = d->hash_cap ? d->hash_cap * 2 : 64;
    while (items * 2 >= cap)
        cap *= 2;
    size_t *hash = calloc(cap, sizeof *hash);
    if (!hash)
        return 0;
    free(d->hash);
    d->hash = hash;
    d->hash_cap = cap;
    for (size_t i = 0; i < d->count; i++)
        *hash_slot(d, &d->items[i]) = i + 1;
    return 1;
}

void halo_diagnostics_set_run(halo_diagnostics *d, const char *name)
{
    if (!d)
        return;
    d->run = 0;
    if (!name)
        return;
    for (int r = 0; r < d->run_count; r++)
        if (!strcmp(d->run_names[r], name)) {
            d->run = r + 1;
            return;
        }
    if (d->run_count == HALO_DIAGNOSTICS_MAX_RUNS)
        return; /* past the last: untagged, kept apart */
    char *copy = halo_strdup(name);
    if (!copy)
        return;
    d->run_names[d->run_count++] = copy;
    d->run = d->run_count;
}

/* An item equal to g from an earlier run takes the current run too: 1 (g is not added). */
static int merge_into_earlier_run(halo_diagnostics *d, const halo_diagnostic *g)
{
    if (!d->run || !hash_reserve(d, d->count + 1))
        return 0;
    size_t at = *hash_slot(d, g);
    if (!at)
        return 0;
    d->item_runs[at - 1] |= UINT32_C(1) << (d->run - 1);
    return 1;
}

/* The line at source_line (up to its end of line), or a window of it of at most
 * HALO_DIAGNOSTIC_SOURCE_MAX bytes around column with "..." at each cut, the cuts moved
 * off UTF-8 continuation bytes; *caret gets column's place in the result. */
static char *source_window(const char *source_line, int column, int *caret)
{
    const size_t max = HALO_DIAGNOSTIC_SOURCE_MAX;
    size_t n = strcspn(source_line, "\r\n"), start = 0, end = n;
    size_t at = column > 0 ? (size_t)column - 1 : 0;
    if (n > max) {
        start = at > max / 2 ? at - max / 2 : 0;
        if (start > n - max)
            start = n - max;
        end = start + max;
        while (start > 0 && ((unsigned char)source_line[start] & 0xC0) == 0x80)
            start--;
        while (end < n && ((unsigned char)source_line[end] & 0xC0) == 0x80)
            end++;
    }
    halo_strbuf b = {0};
    if (start > 0)
        halo_strbuf_append(&b, "...");
    halo_strbuf_append_n(&b, source_line + start, end - start);
    if (end < n)
        halo_strbuf_append(&b, "...");
    *caret = column > 0 ? (int)(at - start + (start > 0 ? 3 : 0)) + 1 : 0;
    return halo_strbuf_take(&b);
}

void halo_diagnostics_report(halo_diagnostics *d, halo_severity severity, halo_message_id id, const char *file,
                             int line, int column, const char *source_line, const char *fmt, ...)
{
    if ((unsigned)id >= HALO_MSG_COUNT)
        id = HALO_MSG_USAGE; /* a caller's id out of range */
    if (!fmt)
        fmt = "";
    if (d)
        d->seen[id] = 1;
    halo_strbuf text = {0};
    va_list ap;
    va_start(ap, fmt);
    if (d && d->run)
        halo_strbuf_vprintf(&text, fmt, ap); /* to compare with the earlier runs' */
    va_end(ap);
    if (d && d->run) {
        halo_diagnostic probe = {.severity = severity,
                                 .id = id,
                                 .file = file ? file : "",
                                 .line = line,
                                 .column = column,
                                 .text = text.data ? text.data : ""};
        if (merge_into_earlier_run(d, &probe)) {
            halo_strbuf_free(&text);
            return;
        }
    }
    if (d && over_limit(d, severity)) { /* nothing formatted or stored: a runaway input stays cheap */
        halo_strbuf_free(&text);
        return;
    }
    if (!text.data) {
        va_start(ap, fmt);
        halo_strbuf_vprintf(&text, fmt, ap);
        va_end(ap);
    }
    halo_diagnostic item = {
        .severity = severity,
        .id = id,
        .file = halo_strdup(file ? file : ""),
        .line = line,
        .column = column,
        .text = halo_strbuf_take(&text),
        .source_line = NULL,
    };
    if (source_line)
        item.source_line = source_window(source_line, column, &item.source_column);
    if (!item.text)
        item.text = halo_strdup(halo_message_name(id));
    if (thread_logger.logger)
        thread_logger.logger(&item, thread_logger.user_data);
    if (!d || !item.file || !item.text) {
        free_item(&item);
        return;
    }
    if (d->count == d->cap) {
        size_t cap = d->cap ? d->cap * 2 : 16;
        halo_diagnostic *p = realloc(d->items, cap * sizeof *p);
        if (!p) {
            free_item(&item);
            return;
        }
        d->items = p;
        uint32_t *r = realloc(d->item_runs, cap * sizeof *r);
        if (!r) {
            free_item(&item);
            return;
        }
        d->item_runs = r;
        d->cap = cap;
    }
    d->item_runs[d->count] = d->run ? UINT32_C(1) << (d->run - 1) : 0;
    d->items[d->count++] = item;
    if (d->hash_cap && hash_reserve(d, d->count))
        *hash_slot(d, &item) = d->count;
    d->kept_errors += severity == HALO_SEVERITY_ERROR;
}

void halo_diag_null(halo_diagnostics *d, const char *function, const char *argument)
{
    halo_diag_error(d, USAGE, "", 0, 0, "%s: %s is NULL", function, argument);
}

/* " [330, 450]": the runs an item occurred in, when there were several. */
static void print_runs(const halo_diagnostics *d, size_t i, FILE *out)
{
    if (d->run_count < 2 || !d->item_runs[i])
        return;
    const char *sep = " [";
    for (int r = 0; r < d->run_count; r++)
        if (d->item_runs[i] & (UINT32_C(1) << r)) {
            fprintf(out, "%s%s", sep, d->run_names[r]);
            sep = ", ";
        }
    fputs("]", out);
}

void halo_diagnostics_print(const halo_diagnostics *d, FILE *out)
{
    static const char *const sev[] = {"error", "warning", "note"};
    HALO_REFUSE_NULL_VOID(NULL, out, "out");
    for (size_t i = 0; d && i < d->count; i++) {
        const halo_diagnostic *g = &d->items[i];
        if (g->file[0] && g->line > 0 && g->column > 0)
            fprintf(out, "%s:%d:%d: ", g->file, g->line, g->column);
        else if (g->file[0] && g->line > 0)
            fprintf(out, "%s:%d: ", g->file, g->line);
        else if (g->file[0])
            fprintf(out, "%s: ", g->file);
        fprintf(out, "%s: %s", sev[g->severity], g->text);
        print_runs(d, i, out);
        fputc('\n', out);
        if (g->source_line) {
            /* the gutter as wide as the line number (at least 5 digits, as before) */
            int width = snprintf(NULL, 0, "%d", g->line);
            if (width < 5)
                width = 5;
            fprintf(out, " %*d | %s\n", width, g->line, g->source_line);
            if (g->source_column > 0) {
                fprintf(out, " %*s | ", width, "");
                size_t n = strlen(g->source_line);
                for (int c = 1; c < g->source_column; c++)
                    fputc((size_t)c <= n && g->source_line[c - 1] == '\t' ? '\t' : ' ', out);
                fputs("^\n", out);
            }
        }
    }
    static const char *const kinds[][2] = {{"error", "errors"}, {"warning", "warnings"}, {"note", "notes"}};
    for (int s = 0; d && s < 3; s++)
        if (d->dropped[s])
            fprintf(out, "%zu more %s not shown (the limit is %zu per kind)\n", d->dropped[s],
                    kinds[s][d->dropped[s] != 1], diag_limit(d));
}

void halo_diag_read_failed(halo_diagnostics *d, const char *path, const char *what)
{
    int e = errno;
    if (e == EFBIG)
        halo_diag_error(d, INPUT_TOO_LARGE, path, 0, 0,
                        "cannot read %s: the file is larger than the %zu MiB that libhalo reads (HALO_MAX_FILE_BYTES)",
                        what, HALO_MAX_FILE_BYTES >> 20);
    else if (e == ENOMEM)
        halo_diag_error(d, OUT_OF_MEMORY, path, 0, 0, "cannot read %s: out of memory", what);
    else
        halo_diag_error(d, IO_READ, path, 0, 0, "cannot read %s: %s", what, strerror(e));
}

char *halo_read_text_file(const char *path, const char *what, size_t *len, halo_diagnostics *d)
{
    HALO_REFUSE_NULL(d, path, "path", NULL);
    return halo_read_text(path, what, len, NULL, d);
}

char *halo_read_text(const char *path, const char *what, size_t *len, int *not_text, halo_diagnostics *d)
{
    if (not_text)
        *not_text = 0;
    size_t length = 0;
    char *text = halo_read_file(path, &length);
    if (!text) {
        halo_diag_read_failed(d, path, what ? what : "file");
        return NULL;
    }
    int line, column;
    if (halo_find_nul(text, length, &line, &column)) {
        /* the text up to the NUL is the line to show */
        const char *start = text;
        for (int l = 1; l < line; l++)
            start = strchr(start, '\n') + 1;
        halo_diagnostics_report(d, HALO_SEVERITY_ERROR, HALO_MSG_INPUT_NUL_BYTE, path, line, column,
                                halo_skip_bom(start), "the %s contains a NUL byte: not a text file",
                                what ? what : "file");
        free(text);
        if (not_text)
            *not_text = 1;
        return NULL;
    }
    if (len)
        *len = length;
    return text;
}

void *halo_diag_calloc(halo_diagnostics *d, size_t size, const char *what)
{
    void *p = calloc(1, size);
    if (!p)
        halo_diag_error(d, OUT_OF_MEMORY, "", 0, 0, "out of memory creating %s", what);
    return p;
}
