#!/bin/sh
# NIfTI header fields that libnifti repairs silently or trusts: vox_offset (negative,
# NaN, huge, inside the header, beyond the file), dim[0] against dim[1..3], pixdim
# (zero, negative, NaN), magic, bitpix against datatype, scl_slope/scl_inter NaN or inf. Each is refused with exit 1 and a message naming the field,
# before any voxel is read; libnifti's own messages never reach the terminal. The
# header is sphere.nii's (NIfTI-1, little-endian, 16^3 uint8, vox_offset 352).
. "$srcdir/tests/tools/halo-render/common.sh"

# patched NAME OFFSET BYTES: a copy of sphere.nii with BYTES (printf octal escapes)
# written at OFFSET, in $tmp/NAME.nii
patched() {
    cp "$volumes/sphere.nii" "$tmp/$1.nii"
    printf "$3" | dd of="$tmp/$1.nii" bs=1 seek="$2" conv=notrunc 2>/dev/null
}

# refused NAME FIELD: halo-render refuses $tmp/NAME.nii naming the header field
refused() {
    rm -f "$tmp/x.png"
    run 1 "$HALO_RENDER" --volume "$tmp/$1.nii" --size 16x16 -o "$tmp/x.png"
    expect_stderr "$1\.nii: header field $2 is"
    if grep -q -i -e "nifti_\|\*\* ERROR\|^\*\*" "$tmp/err"; then fail "$1: libnifti's own messages reached stderr"; fi
    test ! -e "$tmp/x.png" || fail "$1: an image was written"
}

patched offset-negative 108 '\000\000\240\300'   # -5.0f
refused offset-negative vox_offset
patched offset-nan 108 '\000\000\300\177'        # NaN
refused offset-nan vox_offset
patched offset-huge 108 '\312\362\111\161'       # 1e30f
refused offset-huge vox_offset
patched offset-beyond 108 '\000\044\164\111'     # 1e6f, the file is 4448 bytes
refused offset-beyond vox_offset
patched offset-header 108 '\000\000\110\103'     # 200.0f: inside the 348-byte header
refused offset-header vox_offset
patched offset-fraction 108 '\000\040\260\103'   # 352.25f
refused offset-fraction vox_offset
patched dim3-zero 46 '\000\000'                  # dim[0] = 3, dim[3] = 0
refused dim3-zero "dim\\[3\\]"
patched dim2-negative 44 '\377\377'              # dim[2] = -1
refused dim2-negative "dim\\[2\\]"
patched two-d 40 '\002\000'                      # a valid 2-D image: dim[0] = 2
refused two-d "dim\\[0\\]"
patched pixdim-zero 84 '\000\000\000\000'        # pixdim[2] = 0
refused pixdim-zero "pixdim\\[2\\]"
patched pixdim-negative 88 '\000\000\200\277'    # pixdim[3] = -1
refused pixdim-negative "pixdim\\[3\\]"
patched pixdim-nan 76 '\000\000\300\177'         # pixdim[0] (qfac) may be anything...
patched pixdim-nan 80 '\000\000\300\177'         # ...pixdim[1] may not be NaN
refused pixdim-nan "pixdim\\[1\\]"
# magic, bitpix against datatype, a non-finite scale (libnifti read a bad magic as
# NIfTI-1, trusted bitpix and replaced NaN/inf scl_slope and scl_inter silently)
patched magic-bad 344 'XYZ\000'
refused magic-bad magic
patched bitpix-16 72 '\020\000'                  # uint8 (datatype 2) with bitpix 16
refused bitpix-16 bitpix
patched slope-nan 112 '\000\000\300\177'
refused slope-nan scl_slope
patched slope-inf 112 '\000\000\200\177'
refused slope-inf scl_slope
patched inter-inf 116 '\000\000\200\377'        # -inf
refused inter-inf scl_inter
# gzip-compressed: the same checks
patched gz-offset 108 '\000\000\240\300'
gzip -c "$tmp/gz-offset.nii" >"$tmp/gz-offset.nii.gz"
run 1 "$HALO_RENDER" --volume "$tmp/gz-offset.nii.gz" --size 16x16 -o "$tmp/x.png"
expect_stderr "gz-offset\.nii\.gz: header field vox_offset is -5"

# the untouched file and its gzip copy still render
run 0 "$HALO_RENDER" --quiet --volume "$volumes/sphere.nii" --size 16x16 -o "$tmp/ok.png"
run 0 "$HALO_RENDER" --quiet --volume "$volumes/sphere.nii.gz" --size 16x16 -o "$tmp/ok.png"
finish
