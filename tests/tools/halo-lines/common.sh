# Shared by tests/tools/halo-lines/*.sh (tests/harness.sh): finds halo-lines and a scratch directory.
. "${srcdir:-.}/tests/harness.sh"
HALO_LINES=${HALO_LINES:-${top_builddir:-.}/tools/halo-lines}
harness_program "$HALO_LINES"
harness_tmp halo-lines
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

