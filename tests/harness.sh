# The shell tests' shared helpers, sourced by each folder's common.sh (tests/validate,
# tests/tools/halo-render, tests/tools/halo-view, tests/tools/halo-outline, tests/tools/halo-lines) and tests/adapters/vtk/vtk.sh.
#
# harness_need VAR...: each variable is set (the harness sets them), else exit 99.
# harness_program PATH: PATH is built and runnable, else exit 99.
# harness_tmp NAME: $tmp, a scratch directory removed at exit; failures=0.
# fail, run, expect_stderr, expect_stdout, expect_no_stdout, is_png, expect_png, finish.

harness_need() {
    for harness_var in "$@"; do
        eval "harness_value=\${$harness_var:-}"
        if test -z "$harness_value"; then
            echo "broken setup: run through 'make check' ($* must be set; $harness_var is not)" >&2
            exit 99
        fi
    done
}

harness_program() {
    if test ! -x "$1"; then
        echo "broken setup: $1 is not built" >&2
        exit 99
    fi
}

harness_tmp() {
    tmp=$(mktemp -d "${TMPDIR:-/tmp}/$1.XXXXXX") || exit 99
    trap 'rm -rf "$tmp"' EXIT
    failures=0
}

fail() {
    echo "FAIL: $*" >&2
    failures=$((failures + 1))
}

# run STATUS COMMAND [ARG]...: runs the command with stdout in $tmp/out and stderr in
# $tmp/err (both shown in the log), and checks that it exits with exactly STATUS (a
# crash is >= 128).
run() {
    expected=$1
    shift
    echo "+ $* (expect exit $expected)"
    "$@" >"$tmp/out" 2>"$tmp/err"
    status=$?
    sed 's/^/    stdout: /' "$tmp/out"
    sed 's/^/    stderr: /' "$tmp/err"
    if test "$status" -ge 128; then
        fail "'$*' crashed (exit $status)"
    elif test "$status" -ne "$expected"; then
        fail "'$*' exited $status, expected $expected"
    fi
}

# expect_stderr REGEX, expect_stdout REGEX: the last command's output matches the extended regex.
expect_stderr() {
    if ! grep -E -q -e "$1" "$tmp/err"; then
        fail "stderr does not match /$1/"
        sed 's/^/    stderr: /' "$tmp/err" >&2
    fi
}

expect_stdout() {
    if ! grep -E -q -e "$1" "$tmp/out"; then
        fail "stdout does not match /$1/"
        sed 's/^/    stdout: /' "$tmp/out" >&2
    fi
}

# expect_no_stdout: the last command printed nothing on stdout.
expect_no_stdout() {
    if test -s "$tmp/out"; then
        fail "unexpected output on stdout"
        head -5 "$tmp/out" | sed 's/^/    /' >&2
    fi
}

# must_render NAME COMMAND [ARG]...: runs a render with its output in $tmp/NAME.out;
# skips the test (77) when the command does (no headless OpenGL context), and fails it
# at once (exit 1, the output shown) when the command fails.
must_render() {
    must_name=$1
    shift
    "$@" >"$tmp/$must_name.out" 2>&1
    must_status=$?
    if test $must_status -eq 77; then
        cat "$tmp/$must_name.out" >&2
        exit 77
    fi
    if test $must_status -ne 0; then
        echo "FAIL: $(basename "$1") $must_name exited $must_status:" >&2
        cat "$tmp/$must_name.out" >&2
        exit 1
    fi
}

# is_png FILE: FILE exists and starts with the PNG signature; expect_png FILE fails otherwise.
is_png() {
    test -s "$1" && test "$(od -An -tx1 -N8 "$1" | tr -d ' \n')" = "89504e470d0a1a0a"
}

expect_png() {
    is_png "$1" || fail "$1 was not written as a PNG"
}

finish() {
    if test "$failures" -ne 0; then
        echo "$failures check(s) failed" >&2
        exit 1
    fi
    exit 0
}
