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
static void on_alarm(int sig) {
    (void)sig;
    static const char message[] = "test_amplify: a file read did not end within 60 s\n";
    if (write(2, message, sizeof message - 1) < 0) _exit(1);
    _exit(1);
}

/* A sparse regular file of `size` bytes (nothing written: no disk, no time). */
static int sparse_file(char *path, off_t size) {
    int fd = mkstemp(path);
    if (fd < 0) return -1;
    int r = ftruncate(fd, size);
    close(fd);
    return r;
}

static int test_stream_without_end(void) {
    if (access("/dev/zero", R_OK)) return 0;
    halo_diagnostics_clear(diags);
    CHECK(halo_scene_load("/dev/zero", library, diags) == NULL);
    CHECK_DIAG(diags, HALO_MSG_INPUT_TOO_LARGE);
    const halo_diagnostic *g = check_find_diag(diags, HALO_MSG_INPUT_TOO_LARGE, 0);
    CHECK_STR_EQ(g->file, "/dev/zero");
    CHECK_STR_CONTAINS(g->text, "HALO_MAX_FILE_BYTES");
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_library_add_file(library, "/dev/zero", diags), HALO_ERROR_IO);
    CHECK_DIAG(diags, HALO_MSG_INPUT_TOO_LARGE);
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_library_override_file(library, "/dev/zero", diags), HALO_ERROR_IO);
    CHECK_DIAG(diags, HALO_MSG_INPUT_TOO_LARGE);
    return 0;
}

/* A regular file past the maximum is refused by its size, before a byte is read. */
static int test_regular_file_too_large(void) {
    char path[] = "/tmp/halo-amplify-XXXXXX";
    SETUP(sparse_file(path, (off_t)HALO_MAX_FILE_BYTES + 1) == 0);
    halo_diagnostics_clear(diags);
    halo_scene *s = halo_scene_load(path, library, diags);
    halo_status st = halo_library_add_file(library, path, diags);
    unlink(path);
    CHECK(s == NULL);
    CHECK_INT_EQ(st, HALO_ERROR_IO);
    CHECK_INT_EQ(check_count_diag(diags, HALO_MSG_INPUT_TOO_LARGE), 2);
    return 0;
}

int main(void) {
    signal(SIGALRM, on_alarm);
    alarm(60);
    static const check_test tests[] = {
        CHECK_TEST(test_stream_without_end),
        CHECK_TEST(test_regular_file_too_large),
    };
    return check_main_with_library(&library, &diags, tests, sizeof tests / sizeof tests[0]);
}
