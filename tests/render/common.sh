# Helpers for the halo-render tests, sourced by each tests/render/*.sh.
# The harness sets srcdir (the top source directory) and HALO_RENDER.

if test -z "${srcdir:-}" || test -z "${HALO_RENDER:-}"; then
    echo "broken setup: run through 'make check' (srcdir and HALO_RENDER unset)" >&2
    exit 99
fi
if test ! -x "$HALO_RENDER"; then
    echo "broken setup: $HALO_RENDER is not built" >&2
    exit 99
fi
scenes="$srcdir/examples/scenes"
volumes="$srcdir/tests/data/volumes"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/halo-render-test.XXXXXX") || exit 99
trap 'rm -rf "$tmp"' EXIT
failures=0

fail() {
    echo "FAIL: $*" >&2
    failures=$((failures + 1))
}

# run STATUS COMMAND [ARG]...: runs the command with stdout in $tmp/out and stderr in
# $tmp/err, and checks that it exits with exactly STATUS (a crash is >= 128).
run() {
    expected=$1
    shift
    echo "+ $* (expect exit $expected)"
    "$@" >"$tmp/out" 2>"$tmp/err"
    status=$?
    sed 's/^/    stderr: /' "$tmp/err"
    if test "$status" -ge 128; then
        fail "'$*' crashed (exit $status)"
    elif test "$status" -ne "$expected"; then
        fail "'$*' exited $status, expected $expected"
    fi
}

# expect_stderr REGEX: the last command's stderr matches the extended regex.
expect_stderr() {
    if ! grep -E -q -e "$1" "$tmp/err"; then
        fail "stderr does not match /$1/"
    fi
}

# expect_stdout REGEX
expect_stdout() {
    if ! grep -E -q -e "$1" "$tmp/out"; then
        fail "stdout does not match /$1/"
        sed 's/^/    stdout: /' "$tmp/out" >&2
    fi
}

# expect_png FILE: FILE exists and starts with the PNG signature.
expect_png() {
    if test ! -s "$1"; then
        fail "$1 was not written"
        return
    fi
    magic=$(od -An -tx1 -N8 "$1" | tr -d ' \n')
    if test "$magic" != "89504e470d0a1a0a"; then
        fail "$1 is not a PNG (starts with $magic)"
    fi
}

finish() {
    if test "$failures" -ne 0; then
        echo "$failures failure(s)" >&2
        exit 1
    fi
    exit 0
}
