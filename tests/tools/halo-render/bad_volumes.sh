#!/bin/sh
# Bad volumes and bad options: the documented exit status (1 bad contents, 2 usage or
# I/O) and a diagnostic naming the file; never a crash or an allocation failure.
. "$srcdir/tests/tools/halo-render/common.sh"

# rejects STATUS PATTERN ARGS...: halo-render ARGS (writing x.png) exits STATUS with a
# diagnostic matching PATTERN on stderr.
rejects() {
    expected=$1
    pattern=$2
    shift 2
    run "$expected" "$HALO_RENDER" "$@" -o "$tmp/x.png"
    expect_stderr "$pattern"
}

# Truncated NIfTI: uncompressed (checked against the file size before reading) and
# gzip-compressed (found while decompressing).
head -c 1000 "$volumes/sphere.nii" >"$tmp/cut.nii"
rejects 2 "cut\.nii: truncated" --volume "$tmp/cut.nii"
gzip -dc "$volumes/sphere.nii.gz" | head -c 2000 | gzip -c >"$tmp/cut.nii.gz"
rejects 2 "cut\.nii\.gz: truncated" --volume "$tmp/cut.nii.gz"
head -c 200 "$volumes/sphere.nii.gz" >"$tmp/cut-gzip.nii.gz"
rejects 2 "cut-gzip\.nii\.gz: " --volume "$tmp/cut-gzip.nii.gz"
# Only a part of the header.
head -c 100 "$volumes/sphere.nii" >"$tmp/header.nii"
rejects 1 "header\.nii: not a NIfTI file" --volume "$tmp/header.nii"
# Not NIfTI at all, and a file that does not exist.
echo "not a volume" >"$tmp/text.nii"
rejects 1 "text\.nii: not a NIfTI file" --volume "$tmp/text.nii"
rejects 2 "missing\.nii\.gz: No such file" --volume "$tmp/missing.nii.gz"

# Raw: truncated, too long, absurd dimensions (also those whose product overflows 64 bits).
head -c 1000 "$volumes/sphere.nii" >"$tmp/cut.raw"
rejects 2 "cut\.raw: truncated: 1000 bytes, .* need 4096" --volume "$tmp/cut.raw" --raw-dims 16x16x16 --raw-type uint8
rejects 1 "sphere\.nii: 4448 bytes, more than the 4096" --volume "$volumes/sphere.nii" --raw-dims 16x16x16 --raw-type uint8
rejects 1 "cut\.raw: dimension x is 100000" --volume "$tmp/cut.raw" --raw-dims 100000x100000x100000 --raw-type float32
rejects 1 "cut\.raw: 8192x8192x8192 is [0-9]+ voxels, more than" --volume "$tmp/cut.raw" --raw-dims 8192x8192x8192 --raw-type uint16
rejects 1 "cut\.raw: dimension x" --volume "$tmp/cut.raw" --raw-dims 3037000500x3037000500x3037000500 --raw-type uint8
rejects 2 "--raw-dims" --volume "$tmp/cut.raw" --raw-dims 0x16x16 --raw-type uint8
rejects 2 "--raw-dims" --volume "$tmp/cut.raw" --raw-dims 16x16 --raw-type uint8
rejects 2 "--raw-type" --volume "$tmp/cut.raw" --raw-dims 16x16x16
rejects 2 "--raw-type: unknown type 'int64'" --volume "$tmp/cut.raw" --raw-dims 16x16x16 --raw-type int64
rejects 2 "--raw-endian" --volume "$tmp/cut.raw" --raw-dims 16x16x16 --raw-type uint8 --raw-endian middle

# NaN and infinite option values, an empty window, an unknown host.
for option in --zoom --azimuth --elevation; do
    rejects 2 "$option: 'nan' is not a finite number" $option nan
done
rejects 2 "--window: 'nan' is not a finite number" --window nan:1
rejects 2 "--window: 'inf' is not a finite number" --window 0:inf
rejects 2 "--window: HIGH 1 is not above LOW 5" --window 5:1
rejects 2 "--host: unknown host 'gpu'" --host gpu
rejects 2 "--size" --size 0x10
run 2 "$HALO_RENDER" --size 64x64 -o "$tmp/no/such/dir/x.png"
expect_stderr "x\.png"
finish
