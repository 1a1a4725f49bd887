#!/bin/sh
# Every outline and depth-enhancement scene renders small through halo-outline (slice
# host, feature buffers, the at=post passes), and the GPU's post passes match their
# emulation on the same inputs (--check).
. "$srcdir/tests/tools/halo-outline/common.sh"
count=0
for scene in "$scenes"/outline-*.json "$scenes"/depth-*.json; do
    name=$(basename "$scene" .json)
    outline "$name" --check
    count=$((count + 1))
done
if test "$count" -lt 10; then
    echo "FAIL: only $count outline/depth scenes in $scenes" >&2
    exit 1
fi
# a feature image (grey levels) and an unknown one
outline outline-depth --image importance
if "$HALO_OUTLINE" --scene "$scenes/outline-depth.json" --size 16 --volume-size 16 --image nosuch \
    -o "$tmp/nosuch.png" >/dev/null 2>&1; then
    echo "FAIL: --image nosuch was accepted" >&2
    exit 1
fi
exit 0
