#include "strbuf.h"

#include "halo.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static int reserve(halo_strbuf *b, size_t extra)
{
    if (b->failed)
        return 0;
    if (b->len + extra + 1 <= b->cap)
        return 1;
    size_t cap = b->cap ? b->cap : 256;
    while (cap < b->len + extra + 1) {
        if (cap > ((size_t)-1) / 2) {
            b->failed = 1;
            return 0;
        }
        cap *= 2;
    }
    char *p = realloc(b->data, cap);
    if (!p) {
        b->failed = 1;
        return 0;
    }
    b->data = p;
    b->cap = cap;
    return 1;
}

void halo_strbuf_append_n(halo_strbuf *b, const char *s, size_t n)
{
    if (!reserve(b, n))
        return;
    memcpy(b->data + b->len, s, n);
    b->len += n;
    b->data[b->len] = '\0';
}

void halo_strbuf_append(halo_strbuf *b, const char *s) { halo_strbuf_append_n(b, s, strlen(s)); }

void halo_strbuf_vprintf(halo_strbuf *b, const char *fmt, va_list ap)
{
    va_list ap2;
    va_copy(ap2, ap);
    int n = vsnprintf(NULL, 0, fmt, ap2);
    va_end(ap2);
    if (n < 0) {
        b->failed = 1;
        return;
    }
    if (!reserve(b, (size_t)n))
        return;
    vsnprintf(b->data + b->len, (size_t)n + 1, fmt, ap);
    b->len += (size_t)n;
}

void halo_strbuf_printf(halo_strbuf *b, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    halo_strbuf_vprintf(b, fmt, ap);
    va_end(ap);
}

char *halo_strbuf_take(halo_strbuf *b)
{
    if (b->failed) {
        halo_strbuf_free(b);
        return NULL;
    }
    if (!b->data) {
        reserve(b, 0);
        if (b->failed)
            return NULL;
        b->data[0] = '\0';
    }
    char *s = b->data;
    b->data = NULL;
    b->len = b->cap = 0;
    return s;
}

void halo_strbuf_free(halo_strbuf *b)
{
    free(b->data);
    b->data = NULL;
    b->len = b->cap = 0;
    b->failed = 0;
}

char *halo_strdup(const char *s)
{
    if (!s)
        return NULL;
    size_t n = strlen(s) + 1;
    char *p = malloc(n);
    if (p)
        memcpy(p, s, n);
    return p;
}

char *halo_strndup(const char *s, size_t n)
{
    char *p = malloc(n + 1);
    if (p) {
        memcpy(p, s, n);
        p[n] = '\0';
    }
    return p;
}

void halo_strbuf_set_n(halo_strbuf *b, const char *s, size_t n)
{
    b->len = 0;
    halo_strbuf_append_n(b, s, n);
}

char *halo_read_file(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode) && (unsigned long long)st.st_size > HALO_MAX_FILE_BYTES) {
        fclose(f);
        errno = EFBIG;
        return NULL;
    }
    halo_strbuf b = {0};
    char chunk[65536];
    size_t n, want = sizeof chunk;
    /* one byte past the maximum tells a file at the maximum from a longer one */
    while (!b.failed && b.len <= HALO_MAX_FILE_BYTES && (n = fread(chunk, 1, want, f)) > 0) {
        halo_strbuf_append_n(&b, chunk, n);
        if (HALO_MAX_FILE_BYTES + 1 - b.len < want)
            want = HALO_MAX_FILE_BYTES + 1 - b.len;
    }
    int err = b.failed ? ENOMEM : b.len > HALO_MAX_FILE_BYTES ? EFBIG : ferror(f) ? errno : 0;
    fclose(f);
    /* keep the reason: EISDIR ("Is a directory") for a folder, not a bare EIO */
    if (err) {
        halo_strbuf_free(&b);
        errno = err == EISDIR || err == ENOMEM || err == EFBIG ? err : EIO;
        return NULL;
    }
    size_t l = b.len;
    char *s = halo_strbuf_take(&b);
    if (!s) {
        errno = ENOMEM;
        return NULL;
    }
    if (len)
        *len = l;
    return s;
}

const char *halo_skip_bom(const char *s) { return s && !strncmp(s, "\xEF\xBB\xBF", 3) ? s + 3 : s; }

int halo_find_nul(const char *text, size_t len, int *line, int *column)
{
    const char *nul = memchr(text, '\0', len);
    if (!nul)
        return 0;
    const char *start = len >= 3 && !memcmp(text, "\xEF\xBB\xBF", 3) && nul >= text + 3 ? text + 3 : text;
    *line = 1;
    *column = 1;
    for (const char *p = start; p < nul; p++) {
        if (*p == '\n') {
            ++*line;
            *column = 1;
        } else {
            ++*column;
        }
    }
    return 1;
}

/* Splits text in place at its newlines (a \r before one is dropped); *out gets the
 * line starts. Returns the line count, or -1 when memory runs out. */
int halo_split_lines(char *text, char ***out)
{
    int count = 0, cap = 64;
    char **lines = malloc((size_t)cap * sizeof *lines);
    if (!lines)
        return -1;
    for (char *p = text;;) {
        if (count == cap) {
            cap *= 2;
            char **l = realloc(lines, (size_t)cap * sizeof *l);
            if (!l) {
                free(lines);
                return -1;
            }
            lines = l;
        }
        lines[count++] = p;
        char *nl = strchr(p, '\n');
        if (!nl)
            break;
        *nl = '\0';
        if (nl > p && nl[-1] == '\r')
            nl[-1] = '\0';
        p = nl + 1;
    }
    *out = lines;
    return count;
}
