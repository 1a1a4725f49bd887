/* Inputs that amplify (issue 26): a file that never ends or is far larger than any
 * module or scene, and a long line echoed by every diagnostic on it. Each is bounded:
 * the readers stop at HALO_MAX_FILE_BYTES with INPUT_TOO_LARGE naming the file, and a
 * diagnostic's source line is kept and printed as a window around its column. Message
 * ids, never wording. No GL, no glslang. */
#define _DEFAULT_SOURCE /* mkstemp, ftruncate */
#include "check.h"

#include <signal.h>
#include <unistd.h>

static halo_library *library;
static halo_diagnostics *diags;

/* Before the bound a read of /dev/zero never ended: fail, not hang, if it does again. */
static void on_alarm(int sig)
{
    (void)sig;
    static const char message[] = "test_amplify: a file read did not end within 60 s\n";
    if (write(2, message, sizeof message - 1) < 0)
        _exit(1);
    _exit(1);
}

/* A sparse regular file of `size` bytes (nothing written: no disk, no time). */
static int sparse_file(char *path, off_t size)
{
    int fd = mkstemp(path);
    if (fd < 0)
        return -1;
    int r = ftruncate(fd, size);
    close(fd);
    return r;
}

static int test_stream_without_end(void)
{
    if (access("/dev/zero", R_OK))
        return 0;
    halo_diagnostics_clear(diags);
    CHECK(halo_scene_load("/dev/zero", NULL, library, diags) == NULL);
    CHECK_DIAG(diags, HALO_MSG_INPUT_TOO_LARGE);
    const halo_diagnostic *g = check_find_diag(diags, HALO_MSG_INPUT_TOO_LARGE, 0);
    CHECK_STR_EQ(g->file, "/dev/zero");
    CHECK_STR_CONTAINS(g->text, "HALO_MAX_FILE_BYTES");
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_library_add(library, "/dev/zero", NULL, HALO_ADD_NEW, diags), HALO_ERROR_IO);
    CHECK_DIAG(diags, HALO_MSG_INPUT_TOO_LARGE);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_library_add(library, "/dev/zero", NULL, HALO_ADD_REPLACE, diags), HALO_ERROR_IO);
    CHECK_DIAG(diags, HALO_MSG_INPUT_TOO_LARGE);
    return 0;
}

/* A regular file past the maximum is refused by its size, before a byte is read. */
static int test_regular_file_too_large(void)
{
    char path[] = "/tmp/halo-amplify-XXXXXX";
    SETUP(sparse_file(path, (off_t)HALO_MAX_FILE_BYTES + 1) == 0);
    halo_diagnostics_clear(diags);
    halo_scene *s = halo_scene_load(path, NULL, library, diags);
    halo_status st = halo_library_add(library, path, NULL, HALO_ADD_NEW, diags);
    unlink(path);
    CHECK(s == NULL);
    CHECK_INT_EQ(st, HALO_ERROR_IO);
    CHECK_INT_EQ(check_count_diag(diags, HALO_MSG_INPUT_TOO_LARGE), 2);
    return 0;
}

/* A one-line scene of 20 000 unknown stages (about 300 KB): the default cap keeps 100
 * errors, and each keeps and prints a window of the line, the caret under the same
 * character as in the whole line. Before, every error echoed the whole line: 30 MB. */
static int test_long_line_echo(void)
{
    enum { STAGES = 20000 };
    size_t cap = (size_t)STAGES * 24 + 64, len = 0;
    char *text = malloc(cap);
    SETUP(text != NULL);
    len += (size_t)snprintf(text + len, cap - len, "{\"halo_scene\": 1, \"stages\": [");
    for (int i = 0; i < STAGES; i++)
        len += (size_t)snprintf(text + len, cap - len, "%s\"nosuch%d\"", i ? ", " : "", i);
    len += (size_t)snprintf(text + len, cap - len, "]}");
    halo_diagnostics_clear(diags);
    CHECK(halo_scene_load("long.json", text, library, diags) == NULL);
    CHECK_INT_EQ(halo_diagnostics_describe(diags).count, HALO_DIAGNOSTICS_DEFAULT_LIMIT);
    for (size_t i = 0; i < halo_diagnostics_describe(diags).count; i++) {
        const halo_diagnostic *g = halo_diagnostics_get(diags, i);
        CHECK(g->source_line != NULL);
        CHECK_INT_EQ(g->line, 1);
        CHECK(strlen(g->source_line) <= HALO_DIAGNOSTIC_SOURCE_MAX + 6);
        CHECK(g->source_column > 0 && (size_t)g->source_column <= strlen(g->source_line));
        /* the caret's character is the column's */
        CHECK_INT_EQ(g->source_line[g->source_column - 1], text[g->column - 1]);
        if (g->column > HALO_DIAGNOSTIC_SOURCE_MAX)
            CHECK(!strncmp(g->source_line, "...", 3));
        CHECK_STR_CONTAINS(g->source_line + strlen(g->source_line) - 3, "...");
    }
    FILE *out = tmpfile();
    SETUP(out != NULL);
    halo_diagnostics_print(diags, out);
    long bytes = ftell(out);
    fclose(out);
    free(text);
    if (bytes > 64 * 1024)
        CHECK_FAIL_AT("100 errors printed %ld bytes (the line is %zu bytes)", bytes, len);
    return 0;
}

/* A short line is kept whole, its caret where the column says. */
static int test_short_line_echo(void)
{
    halo_diagnostics_clear(diags);
    CHECK(halo_scene_load("short.json", "{\"halo_scene\": 1, \"stages\": [\"nosuch\"]}", library, diags) == NULL);
    const halo_diagnostic *g = check_find_diag(diags, HALO_MSG_SCENE_STAGE_UNKNOWN, 1);
    CHECK(g != NULL);
    CHECK_STR_EQ(g->source_line, "{\"halo_scene\": 1, \"stages\": [\"nosuch\"]}");
    CHECK_INT_EQ(g->source_column, g->column);
    return 0;
}

int main(void)
{
    signal(SIGALRM, on_alarm);
    alarm(60);
    static const check_test tests[] = {
        CHECK_TEST(test_stream_without_end),
        CHECK_TEST(test_regular_file_too_large),
        CHECK_TEST(test_long_line_echo),
        CHECK_TEST(test_short_line_echo),
    };
    return check_main_with_library(&library, &diags, tests, sizeof tests / sizeof tests[0]);
}
