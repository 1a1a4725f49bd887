#!/bin/sh
# Resampling into the display cube is bounded by the input and a cap, and refused
# before anything is allocated (docs/halo-render.md, "Memory"):
#   - an 8 KB NIfTI with an extreme aspect ratio (2x2048x2), or a 16^3 one with an
#     extreme spacing, gets a cube of at most 64 times its voxels (80^3, 64^3), not
#     512^3 (4.4 GB resident before);
#   - asking for a cube whose resampling would need more than the cap (2 GiB, or 4
#     times the volume's float copy) is exit 1 with "would need N GiB; the cap is M";
#   - a raw 1x8192x8192 volume (its first pass alone 128 GiB) is refused the same way;
#   - a 2 MB gzip NIfTI of 800^3 zeros, rendered at --volume-size 16: read a slice at a
#     time and reduced while read (halo_volume_read_nifti_for), at most 1 GiB resident
#     (measured: 227 MB; 2.69 GB before, the file's bytes and the float copy at once),
#     the reduction named in halo-render's description of the volume.
. "$srcdir/tests/tools/halo-render/common.sh"

# nifti NAME DIMX DIMY DIMZ BYTES: sphere.nii's header with these dimensions, then
# BYTES zero bytes of uint8 voxels, in $tmp/NAME.nii
short_le() {
    printf "\\$(printf '%03o' $(($1 % 256)))\\$(printf '%03o' $(($1 / 256)))"
}
nifti() {
    head -c 352 "$volumes/sphere.nii" >"$tmp/$1.nii"
    { short_le "$2"; short_le "$3"; short_le "$4"; } | dd of="$tmp/$1.nii" bs=1 seek=42 conv=notrunc 2>/dev/null
    head -c "$5" /dev/zero >>"$tmp/$1.nii"
}

nifti thin 2 2048 2 8192   # file y runs anterior: display z, the deepest pass
run 0 "$HALO_RENDER" --volume "$tmp/thin.nii" --size 16x16 -o "$tmp/thin.png"
expect_stderr "thin\.nii: .*resampled to 80\^3"
run 1 "$HALO_RENDER" --volume "$tmp/thin.nii" --volume-size 512 --size 16x16 -o "$tmp/thin512.png"
expect_stderr "thin\.nii: .*would need 2\.[0-9] GiB; the cap is 2\.0 GiB"
test ! -e "$tmp/thin512.png" || fail "an image was written for a refused volume"

# pixdim[3] = 1000: a 16^3 volume 1000 times deeper than wide
cp "$volumes/sphere.nii" "$tmp/deep.nii"
printf '\000\000\172\104' | dd of="$tmp/deep.nii" bs=1 seek=88 conv=notrunc 2>/dev/null
run 0 "$HALO_RENDER" --volume "$tmp/deep.nii" --size 16x16 -o "$tmp/deep.png"
expect_stderr "deep\.nii: .*resampled to 64\^3"

head -c 67108864 /dev/zero >"$tmp/wide.raw"
run 1 "$HALO_RENDER" --volume "$tmp/wide.raw" --raw-dims 1x8192x8192 --raw-type uint8 --size 16x16 -o "$tmp/wide.png"
expect_stderr "wide\.raw: .*would need [0-9.]+ GiB; the cap is 2\.0 GiB"
test ! -e "$tmp/wide.png" || fail "an image was written for a refused volume"

# nifti_stream NAME DIMX DIMY DIMZ: the same header, its zero voxels streamed into gzip
nifti_stream() {
    nifti "$1" "$2" "$3" "$4" 0
    { cat "$tmp/$1.nii"; head -c $(($2 * $3 * $4)) /dev/zero; } | gzip -1 >"$tmp/$1.nii.gz"
    rm -f "$tmp/$1.nii"
}
if test -x /usr/bin/time; then
    nifti_stream big 800 800 800
    run 0 /usr/bin/time -f "peak %M KB" "$HALO_RENDER" --volume "$tmp/big.nii.gz" --volume-size 16 --size 16x16 \
        -o "$tmp/big.png"
    expect_stderr "big\.nii\.gz: .*800x800x800 .*read reduced by 25 to 32x32x32 \(block means\)"
    peak=$(sed -n 's/^peak \([0-9]*\) KB$/\1/p' "$tmp/err")
    test -n "$peak" && test "$peak" -le 1048576 ||
        fail "800^3 gzip NIfTI at --volume-size 16: peak resident ${peak:-?} KB, more than 1 GiB"
    rm -f "$tmp/big.nii.gz"
else
    echo "note: /usr/bin/time missing (Debian package time): the 800^3 peak memory check is not run"
fi

# an ordinary volume keeps its size
run 0 "$HALO_RENDER" --volume "$volumes/sphere.nii" --size 16x16 -o "$tmp/sphere.png"
expect_stderr "sphere\.nii: .*resampled to 16\^3"
finish
