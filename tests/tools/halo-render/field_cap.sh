#!/bin/sh
# Host contract 3's memory cap in halo-render (docs/host-contract.md, "Memory"): a frame
# drawn once whose halo field is over --field-max-mib is drawn with halo images at 1/2
# (else 1/4), with a warning naming what the field needed (with --quiet too): the image
# --halo-scale 2 gives.
# With --halo-scale given the scale is the user's: the field is refused (FIELD_MEMORY).
# --field-max-mib without --one-draw is a usage error.
. "$srcdir/tests/tools/halo-render/common.sh"

render() { # OUT EXIT [ARG]...
    out=$1 code=$2
    shift 2
    run "$code" "$HALO_RENDER" --host raycast --one-draw --size 128x128 --volume-size 32 -o "$tmp/$out.png" "$@"
}
# the default scene at 128^2: 27 layers of 64 KiB, 1.69 MiB; at 1/2 0.42 MiB
render capped 0 --quiet --field-max-mib 1
expect_png "$tmp/capped.png"
expect_stderr "warning: .*over field_max_bytes 1 MiB.*drawing with halo images at 1/2 \(--halo-scale 2\)"
render half 0 --quiet --halo-scale 2
if ! cmp -s "$tmp/capped.png" "$tmp/half.png"; then
    fail "the capped frame is not --halo-scale 2's image"
fi
render full 0 --quiet
if cmp -s "$tmp/capped.png" "$tmp/full.png"; then
    fail "the capped frame is the full-size image: the cap did nothing"
fi
# the user's scale is kept: refused, with the scale that fits
render refused 2 --quiet --halo-scale 1 --field-max-mib 1
expect_stderr "over field_max_bytes 1 MiB; halo_link_desc.image_scale 2 fits"
test ! -e "$tmp/refused.png" || fail "a refused frame wrote an image"
# 1/4 does not fit either: refused after the two tries
render tiny 2 --field-max-mib 0.05
expect_stderr "drawing with halo images at 1/4"
expect_stderr "error: .*over field_max_bytes"
run 2 "$HALO_RENDER" --host raycast --size 32x32 --field-max-mib 1 -o "$tmp/x.png"
expect_stderr "field-max-mib .*needs --one-draw"
finish
