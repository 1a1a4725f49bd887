# Shared by tests/tools/halo-outline/*.sh (tests/harness.sh): finds halo-outline, the scenes and a
# scratch directory.
. "${srcdir:-.}/tests/harness.sh"
HALO_OUTLINE=${HALO_OUTLINE:-${top_builddir:-.}/tools/halo-outline}
harness_program "$HALO_OUTLINE"
scenes="${srcdir:-.}/examples/scenes"
harness_tmp halo-outline
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}

# outline NAME ARGS...: renders scene NAME small into $tmp/NAME.png (output in
# $tmp/NAME.out); skips the test (77) without a headless OpenGL context.
outline() {
    name=$1
    shift
    must_render "$name" "$HALO_OUTLINE" --scene "$scenes/$name.json" --size 48 --volume-size 32 -o "$tmp/$name.png" "$@"
    if ! is_png "$tmp/$name.png"; then
        echo "FAIL: $name.png is not a PNG" >&2
        exit 1
    fi
}
