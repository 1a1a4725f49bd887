#!/bin/sh
# halo-view's screenshot of a scene is halo-render's image of the same view: same size,
# camera, scene, volume, host (slice for a halo scene, the ray caster otherwise) and the
# same GL implementation (Mesa llvmpipe: GLX under Xvfb for the viewer, OSMesa for
# halo-render) running the same linked shaders, so the images are expected to be
# identical; measured: max abs 0, 0 % of pixels differ (EXR floats and 8-bit PNG).
# Tolerance allowed (docs/halo-view.md): max abs 2^-10 (a quarter of an 8-bit step)
# and at most 0.5 % of the pixels differing at all, so that a rounding difference
# between two GL front ends would not fail the test while any real one (camera, scene,
# volume window, host) would.
. "$srcdir/tests/tools/halo-view/common.sh"
probe_display
limits="--max-abs 0.0009765625 --max-share 0.005"

# name SCENE [halo-view/halo-render options]...
compare_view() {
    name=$1
    scene=$2
    shift 2
    for ext in exr png; do
        run 0 xrun "$HALO_VIEW" --scene "$scene" "$@" --frames 2 --screenshot "$tmp/$name-view.$ext" --quit
        grep -q "wrote $tmp/$name-view.$ext" "$tmp/out" || fail "$name: halo-view did not report $name-view.$ext"
        run 0 "$HALO_RENDER" --quiet --scene "$scene" "$@" -o "$tmp/$name-render.$ext"
        same "$tmp/$name-view.$ext" "$tmp/$name-render.$ext" $limits
    done
}

# a halo scene (slice host), a scene without halos (ray caster), a NIfTI volume file
compare_view default "$scenes/default.json" --size 128x96 --volume-size 48
compare_view plain "$scenes/plain.json" --size 96x128 --volume-size 40
compare_view nifti "$scenes/boundary-silhouette.json" --size 80x80 --volume "$srcdir/tests/data/volumes/sphere.nii.gz"

# the hosts halo-view picked, as it reports them
run 0 xrun "$HALO_VIEW" --scene "$scenes/halo-occlusive.json" --size 32x32 --volume-size 24 --quit
grep -q "slice host" "$tmp/out" || fail "a halo scene did not get the slice host"
run 0 xrun "$HALO_VIEW" --scene "$scenes/tone.json" --size 32x32 --volume-size 24 --quit
grep -q "raycast host" "$tmp/out" || fail "a scene without halos did not get the ray caster"

# bad options and a broken scene at start: no window needed to fail
run 2 "$HALO_VIEW" --size 0x10
run 2 "$HALO_VIEW" --keys "1 nosuchkey"
run 0 "$HALO_VIEW" --help
printf '{"halo_scene": 1, "stages": [' >"$tmp/broken.json"
run 1 xrun "$HALO_VIEW" --scene "$tmp/broken.json" --size 32x32 --quit
grep -q "broken.json:.*error" "$tmp/err" || fail "no diagnostic for a broken scene at start"
finish
