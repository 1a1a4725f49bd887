/* Internal: a growable string buffer (never fixed arrays with strcat). */
#ifndef HALO_STRBUF_H
#define HALO_STRBUF_H

#include <stdarg.h>
#include <stddef.h>

typedef struct halo_strbuf {
    char *data; /* always NUL-terminated once anything was appended */
    size_t len, cap;
    int failed; /* an allocation failed: contents are incomplete */
} halo_strbuf;

void halo_strbuf_append(halo_strbuf *b, const char *s);
void halo_strbuf_append_n(halo_strbuf *b, const char *s, size_t n);
void halo_strbuf_printf(halo_strbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void halo_strbuf_vprintf(halo_strbuf *b, const char *fmt, va_list ap);
/* Returns the string (caller frees) and resets b; NULL if an allocation failed. */
char *halo_strbuf_take(halo_strbuf *b);
void halo_strbuf_free(halo_strbuf *b);

/* Reads a whole file of at most HALO_MAX_FILE_BYTES; NULL on failure with errno set:
 * EFBIG past the maximum (a regular file's size is checked first; a stream is read to
 * one byte past it), ENOMEM when memory ran out (reading stops then), EISDIR, EIO. */
char *halo_read_file(const char *path, size_t *len);
char *halo_strdup(const char *s);
/* The first n bytes of s as a string (caller frees); NULL when memory ran out. */
char *halo_strndup(const char *s, size_t n);
/* Makes b hold exactly the n bytes at s (b reused: no allocation once it is large enough). */
void halo_strbuf_set_n(halo_strbuf *b, const char *s, size_t n);

/* s past a UTF-8 byte-order mark, if it starts with one (editors write it; it is no
 * part of the text, and skipping it keeps line 1's columns right). */
const char *halo_skip_bom(const char *s);

/* Finds the first NUL byte among len bytes of text: returns 1 and its 1-based line
 * and column (a byte-order mark not counted), or 0 when there is none. */
int halo_find_nul(const char *text, size_t len, int *line, int *column);

/* Splits text into lines in place (text is modified); returns the count or -1. */
int halo_split_lines(char *text, char ***lines);

#endif
