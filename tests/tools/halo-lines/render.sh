#!/bin/sh
# halo-lines renders streamlines and knots (with and without halos, and as an
# anaglyph) to PNG, and reads back the data it writes in the polyline format.
. "${srcdir:-.}/tests/tools/halo-lines/common.sh"
for builtin in streamlines knots; do
    run_lines --builtin "$builtin" --size 96x64 -o "$tmp/$builtin.png" --write-lines "$tmp/$builtin.txt" ||
        { cat "$tmp/out" >&2; echo "FAIL: --builtin $builtin exited $status" >&2; exit 1; }
    is_png "$tmp/$builtin.png" || { echo "FAIL: $builtin.png is not a PNG" >&2; exit 1; }
done
run_lines --builtin knots --size 64x64 --no-halos -o "$tmp/plain.png" && is_png "$tmp/plain.png" ||
    { cat "$tmp/out" >&2; echo "FAIL: --no-halos" >&2; exit 1; }
run_lines --builtin knots --size 64x64 --stereo anaglyph -o "$tmp/stereo.png" && is_png "$tmp/stereo.png" ||
    { cat "$tmp/out" >&2; echo "FAIL: --stereo anaglyph" >&2; exit 1; }
run_lines --lines "$tmp/knots.txt" --scene "${srcdir:-.}/examples/scenes/lines-knots.json" --size 64x64 \
    -o "$tmp/again.png" && is_png "$tmp/again.png" ||
    { cat "$tmp/out" >&2; echo "FAIL: the written polylines do not load back" >&2; exit 1; }
exit 0
