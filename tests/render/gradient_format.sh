#!/bin/sh
# The slice and slab hosts' gradient texture (docs/performance.md, "Memory: the gradient
# texture"): halo-render uses the hosts' default, half (RGB16F), when no option says
# otherwise, and --gradient-format float|half|snorm8|packed16|packed32 takes the others; an unknown value
# is a usage error (exit 2) that names the valid ones, in halo-render and in
# halo-validate conform.
. "$srcdir/tests/render/common.sh"
HALO_VALIDATE=${HALO_VALIDATE:-${top_builddir:-.}/validate/halo-validate}
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}

run 0 "$HALO_RENDER" --volume-size 16 --size 16x16 -o "$tmp/default.png"
expect_stderr "gradient texture: half$"
for format in float half snorm8 packed16 packed32; do
    run 0 "$HALO_RENDER" --volume-size 16 --size 16x16 --host slab --gradient-format "$format" -o "$tmp/$format.png"
    expect_stderr "gradient texture: $format$"
done
# no stage reads the gradient: no texture, nothing to say
run 0 "$HALO_RENDER" --volume-size 16 --size 16x16 --scene "$scenes/plain.json" --host slice -o "$tmp/plain.png"
if grep -q "gradient texture" "$tmp/err"; then
    fail "a gradient texture was built for a scene that reads no gradient"
fi

run 2 "$HALO_RENDER" --gradient-format snorm16 -o "$tmp/bad.png"
expect_stderr "error: --gradient-format: 'snorm16' is not float, half, snorm8, packed16 or packed32"
test ! -e "$tmp/bad.png" || fail "an image was written after a usage error"
run 2 "$HALO_RENDER" --gradient-format half --max-error 0.1 -o "$tmp/bad.png"
expect_stderr "not with --gradient-format"
# the raycast host has no gradient texture: asked for, or the scene's choice, an error
run 2 "$HALO_RENDER" --gradient-format float --host raycast -o "$tmp/bad.png"
expect_stderr "error: --gradient-format: the raycast host has no gradient texture"
run 2 "$HALO_RENDER" --gradient-format float --scene "$scenes/plain.json" -o "$tmp/bad.png"
expect_stderr "error: --gradient-format: the raycast host \(this scene's"
test ! -e "$tmp/bad.png" || fail "an image was written after a usage error"
run 2 "$HALO_VALIDATE" conform --stage slice --gradient-format ""
expect_stderr "conform: --gradient-format: '' is not float, half, snorm8, packed16 or packed32"
finish
