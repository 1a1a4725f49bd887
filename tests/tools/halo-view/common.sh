# Helpers for the halo-view tests, sourced by each tests/tools/halo-view/*.sh. The harness sets
# srcdir, HALO_RENDER, HALO_IMAGE_COMPARE and, when halo-view was built (GLFW found),
# HALO_VIEW. The viewer needs an X display: each test runs it under xvfb-run -a (a
# private Xvfb server), and is skipped (77) without halo-view or xvfb-run.

. "${srcdir:-.}/tests/harness.sh"
harness_need srcdir HALO_RENDER HALO_IMAGE_COMPARE
if test -z "${HALO_VIEW:-}" || test ! -x "$HALO_VIEW"; then
    echo "SKIP: halo-view is not built (configure found no GLFW 3: install libglfw3-dev)"
    exit 77
fi
if ! command -v xvfb-run >/dev/null 2>&1; then
    echo "SKIP: xvfb-run not found (install the Debian packages xvfb and xauth)"
    exit 77
fi
# Under clang's AddressSanitizer (its runtime linked into the program: __asan_init
# defined in it), Mesa's GLX driver leaks a few blocks from modules that glfwTerminate
# unloads before the leak check, so that no suppression can name them (GCC's shared
# runtime does not report them): leaks are not checked there, memory errors are.
if nm "$HALO_VIEW" 2>/dev/null | grep -q ' T __asan_init$'; then
    ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
    export ASAN_OPTIONS
fi
scenes="$srcdir/examples/scenes"
harness_tmp halo-view-test

. "$srcdir/tests/xrun.sh"

# Whether this machine can open a GLFW window with OpenGL at all (Xvfb without GLX,
# a broken Mesa): if not, the tests are skipped rather than failed.
probe_display() {
    xrun "$HALO_VIEW" --scene "$scenes/plain.json" --size 8x8 --volume-size 8 --frames 1 --quit \
        >"$tmp/probe.out" 2>"$tmp/probe.err"
    probe_status=$?
    if test "$probe_status" -ne 0 && grep -E -q "cannot (initialize GLFW|open a .* window)" "$tmp/probe.err"; then
        sed 's/^/    probe: /' "$tmp/probe.err"
        echo "SKIP: no X display with OpenGL 3.3 core under xvfb-run"
        exit 77
    fi
}

# same A B [image_compare limits]: A and B match within the limits (default: exactly).
same() {
    a=$1
    b=$2
    shift 2
    "$HALO_IMAGE_COMPARE" "$a" "$b" "$@" || fail "$a and $b differ beyond the limits ($*)"
}

# different A B: A and B are not the same image.
different() {
    "$HALO_IMAGE_COMPARE" "$1" "$2" --differ || fail "$1 and $2 are the same image"
}
