# Shared by tests/outline/*.sh: finds halo-outline, the scenes and a scratch directory.
HALO_OUTLINE=${HALO_OUTLINE:-${top_builddir:-.}/tools/halo-outline}
if test ! -x "$HALO_OUTLINE"; then
    echo "broken setup: $HALO_OUTLINE missing" >&2
    exit 99
fi
scenes="${srcdir:-.}/examples/scenes"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/halo-outline.XXXXXX") || exit 99
trap 'rm -rf "$tmp"' EXIT
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}

# outline NAME ARGS...: renders scene NAME small into $tmp/NAME.png (output in
# $tmp/NAME.out); skips the test (77) without a headless OpenGL context.
outline() {
    name=$1
    shift
    "$HALO_OUTLINE" --scene "$scenes/$name.json" --size 48 --volume-size 32 -o "$tmp/$name.png" "$@" \
        >"$tmp/$name.out" 2>&1
    status=$?
    if test $status -eq 77; then
        cat "$tmp/$name.out" >&2
        exit 77
    fi
    if test $status -ne 0; then
        echo "FAIL: halo-outline $name exited $status:" >&2
        cat "$tmp/$name.out" >&2
        exit 1
    fi
    if test "$(od -An -tx1 -N8 "$tmp/$name.png" | tr -d ' \n')" != "89504e470d0a1a0a"; then
        echo "FAIL: $name.png is not a PNG" >&2
        exit 1
    fi
}
