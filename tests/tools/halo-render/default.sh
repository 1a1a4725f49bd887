#!/bin/sh
# halo-render with no input (the built-in volume and scene) renders a PNG.
if test ! -x "${HALO_RENDER:-}"; then
    echo "broken setup: HALO_RENDER missing" >&2
    exit 99
fi
tmp=$(mktemp -d "${TMPDIR:-/tmp}/halo-render.XXXXXX") || exit 99
trap 'rm -rf "$tmp"' EXIT
(cd "$tmp" && "$HALO_RENDER" --size 64x64)
status=$?
if test "$status" -ne 0; then
    echo "FAIL: halo-render --size 64x64 exited $status" >&2
    exit 1
fi
png="$tmp/halo-render.png"
if test ! -s "$png"; then
    echo "FAIL: halo-render wrote no halo-render.png" >&2
    ls -l "$tmp" >&2
    exit 1
fi
# The PNG signature: \211 P N G \r \n \032 \n
magic=$(od -An -tx1 -N8 "$png" | tr -d ' \n')
if test "$magic" != "89504e470d0a1a0a"; then
    echo "FAIL: halo-render.png is not a PNG (starts with $magic)" >&2
    exit 1
fi
exit 0
