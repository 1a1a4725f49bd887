#!/bin/sh
# halo-render checks its output before it renders (issue 15): an output it cannot
# write (a missing folder, a folder, a read-only folder) or an image format it does
# not know is refused with exit 2, a message that names the output, and no render:
# nothing of the render (the host's notes, progress) comes before the message, and
# a broken scene is not even read.
. "$srcdir/tests/validate/common.sh"
# expect_no_render: the last command never got to rendering.
expect_no_render() {
    if grep -E -q "gradient texture|rendering|rendered|feature halo buffer|broken\.json" "$tmp/err"; then
        fail "halo-render rendered (or read the scene) before it refused its output"
    fi
}
printf '{ broken' > "$tmp/broken.json"
run 2 "$HALO_RENDER" --size 8x8 --volume-size 8 -o "$tmp/missing/x.png"
expect_stderr "-o: .*missing/x\.png: cannot write"
expect_no_render
run 2 "$HALO_RENDER" --scene "$tmp/broken.json" --size 8x8 --volume-size 8 -o "$tmp/missing/x.png"
expect_stderr "-o: .*missing/x\.png: cannot write"
expect_no_render
mkdir "$tmp/folder.png"
run 2 "$HALO_RENDER" --size 8x8 --volume-size 8 -o "$tmp/folder.png"
expect_stderr "-o: .*folder\.png: cannot write: Is a directory"
expect_no_render
run 2 "$HALO_RENDER" --size 8x8 --volume-size 8 -o "$tmp/x.unknownformat"
expect_stderr "-o: .*x\.unknownformat: unknown image format"
expect_no_render
test -e "$tmp/x.unknownformat" && fail "an output in an unknown format was written"
if test "$(id -u)" != 0; then # root writes anywhere
    mkdir "$tmp/readonly" && chmod a-w "$tmp/readonly"
    run 2 "$HALO_RENDER" --size 8x8 --volume-size 8 -o "$tmp/readonly/x.png"
    expect_stderr "-o: .*readonly/x\.png: cannot write"
    expect_no_render
fi
# a good output still renders, and a PNG or EXR in any case of its extension
run 0 "$HALO_RENDER" --size 8x8 --volume-size 8 --quiet -o "$tmp/x.EXR"
test -s "$tmp/x.EXR" || fail "x.EXR was not written"
finish
