# Sourced by tests/validate/conform.sh (OSMesa) and tests/validate/conform_egl.sh (EGL):
# conform_backend NAME BUILT runs the conformance suite at a small size (25, the least
# conform accepts: its hard cases need 25x25 pixels) through the headless backend NAME
# (halo-validate conform --backend NAME) and exits with the test's status: 0 when
# every row passes on that backend; 77 (skip) when the build has no such backend
# (BUILT is not yes) or it cannot create a context here; 1 when a row fails or the
# rows ran on another backend.
conform_backend() {
    backend=$1
    if test ! -x "${HALO_VALIDATE:-}"; then
        echo "broken setup: HALO_VALIDATE missing" >&2
        exit 99
    fi
    if test "$2" != yes; then
        echo "this build has no $backend backend: skipping" >&2
        exit 77
    fi
    log=$(mktemp) || exit 99
    # Mesa 22.3's EGL leaks a little at eglTerminate, after which it unloads the driver:
    # LeakSanitizer cannot name (suppress) it. Leaks in libhalo are caught by the OSMesa run
    # of the same code (--enable-sanitizers); memory errors are still checked here.
    if test "$backend" = egl; then
        ASAN_OPTIONS="detect_leaks=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
        export ASAN_OPTIONS
    fi
    "$HALO_VALIDATE" conform --backend "$backend" --size 25 -v 2>"$log"
    status=$?
    cat "$log" >&2
    if test $status -eq 2 && grep -q "no headless OpenGL context" "$log"; then
        rm -f "$log"
        echo "no $backend context here: skipping" >&2
        exit 77
    fi
    if test $status -ne 0; then
        rm -f "$log"
        echo "FAIL: halo-validate conform --backend $backend --size 25 exited $status" >&2
        exit 1
    fi
    # -v names the context's backend: the rows ran on the one asked for
    if ! grep -q "^conform: $backend context" "$log"; then
        rm -f "$log"
        echo "FAIL: halo-validate conform --backend $backend ran on another backend" >&2
        exit 1
    fi
    rm -f "$log"
    exit 0
}
