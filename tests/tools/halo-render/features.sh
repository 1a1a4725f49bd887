#!/bin/sh
# Feature halos (the halo buffer of feature_halo, built for the view and bound by
# halo-render), the outline scenes' post passes, and progress per slice.
. "$srcdir/tests/tools/halo-render/common.sh"

# feature-halos.json: the ray caster by default, the buffer built (qualified voxels).
run 0 "$HALO_RENDER" --scene "$scenes/feature-halos.json" --size 48x48 --volume-size 32 -o "$tmp/feature.png"
expect_png "$tmp/feature.png"
expect_stdout "raycast host, .*feature_halo"
expect_stderr "feature halo buffer: [1-9][0-9]* qualified voxels"
# --no-halos switches feature_halo off: no buffer, another image, the same host.
run 0 "$HALO_RENDER" --scene "$scenes/feature-halos.json" --size 48x48 --volume-size 32 --no-halos \
    -o "$tmp/feature-plain.png"
expect_stdout "raycast host"
if grep -q "feature_halo" "$tmp/out"; then
    fail "--no-halos still links feature_halo: $(cat "$tmp/out")"
fi
if grep -q "feature halo buffer" "$tmp/err"; then
    fail "--no-halos still builds the feature halo buffer"
fi
if cmp -s "$tmp/feature.png" "$tmp/feature-plain.png"; then
    fail "feature halos: --no-halos gives the same image"
fi
# The slice host binds the buffer too.
run 0 "$HALO_RENDER" --quiet --scene "$scenes/feature-halos.json" --host slice --size 48x48 --volume-size 32 \
    -o "$tmp/feature-slice.png"
expect_stdout "slice host, .*feature_halo"
run 0 "$HALO_RENDER" --quiet --scene "$scenes/feature-halos.json" --host slice --no-halos --size 48x48 \
    --volume-size 32 -o "$tmp/feature-slice-plain.png"
if cmp -s "$tmp/feature-slice.png" "$tmp/feature-slice-plain.png"; then
    fail "feature halos on the slice host: no effect"
fi
# Its volumetric counterpart renders with the slice host.
run 0 "$HALO_RENDER" --quiet --scene "$scenes/feature-volumetric.json" --size 48x48 --volume-size 32 \
    -o "$tmp/volumetric.png"
expect_stdout "slice host, .*halo_seed, halo_generate, halo_map"

# An outline scene: the post passes run on the host's image; the image is "final".
run 0 "$HALO_RENDER" --quiet --scene "$scenes/outline-depth.json" --size 48x48 --volume-size 32 -o "$tmp/outline.png"
expect_png "$tmp/outline.png"
expect_stdout "slice host, .*outlines; image final of the post passes"
run 0 "$HALO_RENDER" --quiet --scene "$scenes/outline-depth.json" --no-halos --size 48x48 --volume-size 32 \
    -o "$tmp/outline-plain.png"
if grep -q "post passes" "$tmp/out"; then
    fail "--no-halos still runs the post passes"
fi
if cmp -s "$tmp/outline.png" "$tmp/outline-plain.png"; then
    fail "the outline post passes changed nothing"
fi

# Progress: a render of more than a second reports "slice k of n" on stderr (checked when
# it took 1.5 s or more, so that a fast machine does not fail it).
run 0 "$HALO_RENDER" --size 160x160 --volume-size 64 -o "$tmp/progress.png"
seconds=$(sed -n 's/.*rendered [0-9]* slices and [0-9]* image passes in \([0-9.]*\) s.*/\1/p' "$tmp/err")
if test -n "$seconds" && awk -v s="$seconds" 'BEGIN { exit !(s >= 1.5) }'; then
    expect_stderr "rendering 160x160 with the slice host: slice [0-9]+ of [0-9]+ \([0-9]+ s\)"
fi
finish
