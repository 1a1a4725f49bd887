#!/bin/sh
# The MRI template of Debian's mricron-data renders with halos (skipped without it).
. "$srcdir/tests/tools/halo-render/common.sh"

head=/usr/share/mricron/templates/ch2better.nii.gz
if test ! -r "$head"; then
    echo "SKIP: $head is absent (Debian package mricron-data)"
    exit 77
fi
run 0 "$HALO_RENDER" --volume "$head" --scene "$scenes/mri-head.json" --size 96x96 --volume-size 64 -o "$tmp/head.png"
expect_png "$tmp/head.png"
expect_stdout "halo_seed, halo_generate, halo_map"
expect_stderr "ch2better\.nii\.gz: NIfTI-1, .*301x370x316"
run 0 "$HALO_RENDER" --quiet --volume "$head" --scene "$scenes/mri-head.json" --size 96x96 --volume-size 64 \
    --no-halos -o "$tmp/plain.png"
if cmp -s "$tmp/head.png" "$tmp/plain.png"; then
    fail "the MRI head renders the same with and without halos"
fi
finish
