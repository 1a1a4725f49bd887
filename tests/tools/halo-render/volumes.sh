#!/bin/sh
# Volumes from files: NIfTI (.nii, .nii.gz), raw of each type and byte order, NaN voxels.
. "$srcdir/tests/tools/halo-render/common.sh"

for file in sphere.nii sphere.nii.gz; do
    run 0 "$HALO_RENDER" --volume "$volumes/$file" --size 48x48 -o "$tmp/$file.png"
    expect_png "$tmp/$file.png"
    expect_stderr "$file: NIfTI-1, .*16x16x16 voxels of 1\.5x1\.5x1\.5"
done
if ! cmp -s "$tmp/sphere.nii.png" "$tmp/sphere.nii.gz.png"; then
    fail ".nii and .nii.gz of the same volume render differently"
fi

# The raw voxels of sphere.nii (after its 352-byte header), as uint8 and with an offset.
run 0 "$HALO_RENDER" --volume "$volumes/sphere.nii" --raw-dims 16x16x16 --raw-type uint8 --raw-offset 352 \
    --window 0:200 --size 48x48 -o "$tmp/raw.png"
expect_png "$tmp/raw.png"
expect_stderr "window 0:200 \(--window\)"

# 2x2x2 float32, little- and big-endian, one NaN voxel: a warning, then a render.
printf '\000\000\200\077\000\000\000\100\000\000\100\100\000\000\200\100\000\000\240\100\000\000\300\100\000\000\340\100\000\000\300\177' >"$tmp/le.raw"
run 0 "$HALO_RENDER" --volume "$tmp/le.raw" --raw-dims 2x2x2 --raw-type float32 --size 32x32 -o "$tmp/le.png"
expect_png "$tmp/le.png"
expect_stderr "le\.raw: 1 voxel is NaN or infinite"
printf '\077\200\000\000\100\000\000\000\100\100\000\000\100\200\000\000\100\240\000\000\100\300\000\000\100\340\000\000\177\300\000\000' >"$tmp/be.raw"
run 0 "$HALO_RENDER" --volume "$tmp/be.raw" --raw-dims 2x2x2 --raw-type float32 --raw-endian big --size 32x32 \
    -o "$tmp/be.png"
if ! cmp -s "$tmp/le.png" "$tmp/be.png"; then
    fail "the same float32 volume renders differently little- and big-endian"
fi
# int16 and uint16: 8 voxels, 16 bytes.
printf '\001\000\002\000\003\000\004\000\005\000\006\000\007\000\010\000' >"$tmp/v16.raw"
for type in int16 uint16; do
    run 0 "$HALO_RENDER" --quiet --volume "$tmp/v16.raw" --raw-dims 2x2x2 --raw-type $type --size 32x32 \
        -o "$tmp/$type.png"
    expect_png "$tmp/$type.png"
done
finish
