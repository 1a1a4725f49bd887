# Helpers for the command-line tests, sourced by each tests/cli/*.sh.
# The harness sets srcdir (the top source directory), HALO_VALIDATE and HALO_RENDER.

if test -z "${srcdir:-}" || test -z "${HALO_VALIDATE:-}"; then
    echo "broken setup: run through 'make check' (srcdir and HALO_VALIDATE unset)" >&2
    exit 99
fi
if test ! -x "$HALO_VALIDATE"; then
    echo "broken setup: $HALO_VALIDATE is not built" >&2
    exit 99
fi
data="$srcdir/tests/data"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/halo-test.XXXXXX") || exit 99
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
        sed 's/^/    /' "$tmp/err" >&2
    elif test "$status" -ne "$expected"; then
        fail "'$*' exited $status, expected $expected"
        sed 's/^/    /' "$tmp/err" >&2
    fi
}

# expect_stderr REGEX: the last command's stderr matches the extended regex.
expect_stderr() {
    if ! grep -E -q -e "$1" "$tmp/err"; then
        fail "stderr does not match /$1/"
        echo "    stderr was:" >&2
        sed 's/^/    /' "$tmp/err" >&2
    fi
}

# expect_no_stdout: the last command printed nothing on stdout.
expect_no_stdout() {
    if test -s "$tmp/out"; then
        fail "unexpected output on stdout"
        head -5 "$tmp/out" | sed 's/^/    /' >&2
    fi
}

# A regex fragment matching a path ending in NAME (with . escaped).
re_file() {
    printf '%s' "$1" | sed 's/[.[\*^$]/\\&/g'
}

finish() {
    if test "$failures" -ne 0; then
        echo "$failures check(s) failed" >&2
        exit 1
    fi
    exit 0
}
