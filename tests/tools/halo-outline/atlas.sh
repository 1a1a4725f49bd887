#!/bin/sh
# The atlas example (docs/outlines.md, "Atlas"): AAL regions as label features of
# outline_feature over the T1 they were drawn on (mricron-data), through halo-render
# --labels. The labels must reach the shader: regions that exist draw outlines (the
# image differs from lambda 0), label ids that no voxel has draw none (the image equals
# lambda 0's byte for byte). A segmentation on another grid is refused.
. "${srcdir:-.}/tests/harness.sh"
HALO_RENDER=${HALO_RENDER:-${top_builddir:-.}/tools/halo-render}
templates=${HALO_MRICRON_TEMPLATES:-/usr/share/mricron/templates}
if test ! -r "$templates/ch2bet.nii.gz" || test ! -r "$templates/aal.nii.gz"; then
    echo "SKIP: $templates/ch2bet.nii.gz and aal.nii.gz (Debian: mricron-data) are not installed" >&2
    exit 77
fi
scenes="${srcdir:-.}/examples/scenes"
harness_tmp halo-atlas
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}

cp "$scenes/atlas-aal.json" "$tmp/regions.json"
sed 's/"lambda": \[[0-9, ]*\]/"lambda": [0, 0, 0, 0]/' "$scenes/atlas-aal.json" >"$tmp/lambda0.json"
sed 's/"label": \[[0-9, ]*\]/"label": [200, 201, 202, 203]/' "$scenes/atlas-aal.json" >"$tmp/absent.json"
for name in lambda0 absent; do
    if cmp -s "$tmp/$name.json" "$tmp/regions.json"; then
        echo "broken test: the $name variant of atlas-aal.json is the scene itself" >&2
        exit 99
    fi
done
for name in regions lambda0 absent; do
    must_render "$name" "$HALO_RENDER" --quiet --volume "$templates/ch2bet.nii.gz" --labels "$templates/aal.nii.gz" \
        --scene "$tmp/$name.json" --size 64x64 --volume-size 48 -o "$tmp/$name.png"
done
if cmp -s "$tmp/regions.png" "$tmp/lambda0.png"; then
    echo "FAIL: the AAL regions draw no outline (are the labels bound?)" >&2
    exit 1
fi
if ! cmp -s "$tmp/absent.png" "$tmp/lambda0.png"; then
    echo "FAIL: label ids that no voxel has still draw something" >&2
    exit 1
fi
# a segmentation on another grid: a diagnostic and exit 1, no image
"$HALO_RENDER" --quiet --volume "$templates/ch2bet.nii.gz" --labels "$templates/ch2better.nii.gz" \
    --scene "$tmp/regions.json" --size 16x16 --volume-size 16 -o "$tmp/grid.png" >"$tmp/grid.out" 2>&1
status=$?
if test $status -ne 1 || ! grep -q "is not on the grid" "$tmp/grid.out" || test -e "$tmp/grid.png"; then
    echo "FAIL: labels on another grid: exit $status, expected 1 and 'is not on the grid':" >&2
    cat "$tmp/grid.out" >&2
    exit 1
fi
# --labels needs --volume
"$HALO_RENDER" --quiet --labels "$templates/aal.nii.gz" -o "$tmp/none.png" >"$tmp/none.out" 2>&1
status=$?
if test $status -ne 2 || ! grep -q "needs --volume" "$tmp/none.out"; then
    echo "FAIL: --labels without --volume: exit $status, expected 2:" >&2
    cat "$tmp/none.out" >&2
    exit 1
fi
exit 0
