#!/bin/sh
# Feature halos render (a small image of the side-by-side scenes) and the halo buffer
# is built and bound: the feature scene differs from the same scene without halos.
if test ! -x "${HALO_FEATURE:-}"; then
    echo "broken setup: HALO_FEATURE missing" >&2
    exit 99
fi
tmp=$(mktemp -d) || exit 99
trap 'rm -rf "$tmp"' EXIT
scenes="$srcdir/examples/scenes"
for name in halos volumetric; do
    "$HALO_FEATURE" render --scene "$scenes/feature-$name.json" --size 48 --volume-size 32 -o "$tmp/$name.png" \
        > "$tmp/$name.out"
    status=$?
    test $status -eq 77 && { echo "no headless OpenGL context: skipping" >&2; exit 77; }
    test $status -eq 0 || { echo "FAIL: render $name exited $status" >&2; exit 1; }
    test -s "$tmp/$name.png" || { echo "FAIL: $name.png missing" >&2; exit 1; }
done
grep -q "halo buffer: [1-9][0-9]* qualified" "$tmp/halos.out" || {
    echo "FAIL: no qualified voxels reported:" >&2; cat "$tmp/halos.out" >&2; exit 1; }
# bad splat size: a usage error
"$HALO_FEATURE" render --splat 4 -o "$tmp/bad.png" 2>/dev/null
test $? -eq 2 || { echo "FAIL: --splat 4 was accepted" >&2; exit 1; }
exit 0
