#!/bin/sh
# Bad volumes and bad options: the documented exit status (1 bad contents, 2 usage or
# I/O) and a diagnostic naming the file; never a crash or an allocation failure.
. "$srcdir/tests/render/common.sh"

# Truncated NIfTI: uncompressed (checked against the file size before reading) and
# gzip-compressed (found while decompressing).
head -c 1000 "$volumes/sphere.nii" >"$tmp/cut.nii"
run 2 "$HALO_RENDER" --volume "$tmp/cut.nii" -o "$tmp/x.png"
expect_stderr "cut\.nii: truncated"
gzip -dc "$volumes/sphere.nii.gz" | head -c 2000 | gzip -c >"$tmp/cut.nii.gz"
run 2 "$HALO_RENDER" --volume "$tmp/cut.nii.gz" -o "$tmp/x.png"
expect_stderr "cut\.nii\.gz: truncated"
head -c 200 "$volumes/sphere.nii.gz" >"$tmp/cut-gzip.nii.gz"
run 2 "$HALO_RENDER" --volume "$tmp/cut-gzip.nii.gz" -o "$tmp/x.png"
expect_stderr "cut-gzip\.nii\.gz: "
# Only a part of the header.
head -c 100 "$volumes/sphere.nii" >"$tmp/header.nii"
run 1 "$HALO_RENDER" --volume "$tmp/header.nii" -o "$tmp/x.png"
expect_stderr "header\.nii: not a NIfTI file"
# Not NIfTI at all, and a file that does not exist.
echo "not a volume" >"$tmp/text.nii"
run 1 "$HALO_RENDER" --volume "$tmp/text.nii" -o "$tmp/x.png"
expect_stderr "text\.nii: not a NIfTI file"
run 2 "$HALO_RENDER" --volume "$tmp/missing.nii.gz" -o "$tmp/x.png"
expect_stderr "missing\.nii\.gz: No such file"

# Raw: truncated, too long, absurd dimensions (also those whose product overflows 64 bits).
head -c 1000 "$volumes/sphere.nii" >"$tmp/cut.raw"
run 2 "$HALO_RENDER" --volume "$tmp/cut.raw" --raw-dims 16x16x16 --raw-type uint8 -o "$tmp/x.png"
expect_stderr "cut\.raw: truncated: 1000 bytes, .* need 4096"
run 1 "$HALO_RENDER" --volume "$volumes/sphere.nii" --raw-dims 16x16x16 --raw-type uint8 -o "$tmp/x.png"
expect_stderr "sphere\.nii: 4448 bytes, more than the 4096"
run 1 "$HALO_RENDER" --volume "$tmp/cut.raw" --raw-dims 100000x100000x100000 --raw-type float32 -o "$tmp/x.png"
expect_stderr "cut\.raw: dimension x is 100000"
run 1 "$HALO_RENDER" --volume "$tmp/cut.raw" --raw-dims 8192x8192x8192 --raw-type uint16 -o "$tmp/x.png"
expect_stderr "cut\.raw: 8192x8192x8192 is [0-9]+ voxels, more than"
run 1 "$HALO_RENDER" --volume "$tmp/cut.raw" --raw-dims 3037000500x3037000500x3037000500 --raw-type uint8 -o "$tmp/x.png"
expect_stderr "cut\.raw: dimension x"
run 2 "$HALO_RENDER" --volume "$tmp/cut.raw" --raw-dims 0x16x16 --raw-type uint8 -o "$tmp/x.png"
expect_stderr "--raw-dims"
run 2 "$HALO_RENDER" --volume "$tmp/cut.raw" --raw-dims 16x16 --raw-type uint8 -o "$tmp/x.png"
expect_stderr "--raw-dims"
run 2 "$HALO_RENDER" --volume "$tmp/cut.raw" --raw-dims 16x16x16 -o "$tmp/x.png"
expect_stderr "--raw-type"
run 2 "$HALO_RENDER" --volume "$tmp/cut.raw" --raw-dims 16x16x16 --raw-type int64 -o "$tmp/x.png"
expect_stderr "--raw-type: unknown type 'int64'"
run 2 "$HALO_RENDER" --volume "$tmp/cut.raw" --raw-dims 16x16x16 --raw-type uint8 --raw-endian middle -o "$tmp/x.png"
expect_stderr "--raw-endian"

# NaN and infinite option values, an empty window, an unknown host.
for option in --zoom --azimuth --elevation; do
    run 2 "$HALO_RENDER" $option nan -o "$tmp/x.png"
    expect_stderr "$option: 'nan' is not a finite number"
done
run 2 "$HALO_RENDER" --window nan:1 -o "$tmp/x.png"
expect_stderr "--window: 'nan' is not a finite number"
run 2 "$HALO_RENDER" --window 0:inf -o "$tmp/x.png"
expect_stderr "--window: 'inf' is not a finite number"
run 2 "$HALO_RENDER" --window 5:1 -o "$tmp/x.png"
expect_stderr "--window: HIGH 1 is not above LOW 5"
run 2 "$HALO_RENDER" --host gpu -o "$tmp/x.png"
expect_stderr "--host: unknown host 'gpu'"
run 2 "$HALO_RENDER" --size 0x10 -o "$tmp/x.png"
expect_stderr "--size"
run 2 "$HALO_RENDER" --size 64x64 -o "$tmp/no/such/dir/x.png"
expect_stderr "x\.png"
finish
