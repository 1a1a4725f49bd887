# Shared by tests/lines/*.sh: finds halo-lines and a scratch directory.
HALO_LINES=${HALO_LINES:-${top_builddir:-.}/tools/halo-lines}
if test ! -x "$HALO_LINES"; then
    echo "broken setup: $HALO_LINES missing" >&2
    exit 99
fi
tmp=$(mktemp -d "${TMPDIR:-/tmp}/halo-lines.XXXXXX") || exit 99
trap 'rm -rf "$tmp"' EXIT
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}

# run_lines ARGS...: runs halo-lines, stdout+stderr in $tmp/out; skips (77) without GL.
run_lines() {
    "$HALO_LINES" "$@" >"$tmp/out" 2>&1
    status=$?
    if grep -q "no OpenGL context" "$tmp/out"; then
        cat "$tmp/out" >&2
        exit 77
    fi
    return $status
}

# is_png FILE
is_png() {
    test -s "$1" && test "$(od -An -tx1 -N8 "$1" | tr -d ' \n')" = "89504e470d0a1a0a"
}
