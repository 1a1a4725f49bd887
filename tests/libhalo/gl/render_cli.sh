#!/bin/sh
# halo-render --host raycast (host contract 2): volumetric halos, outlines and feature
# halos through the segmented ray caster. Each must change the image far more (mean abs
# difference, 5 times) than the ray caster and the slab host differ with the same scene:
# a stage that silently did nothing in the ray caster fails. The images must be finite
# (image_compare refuses NaN: its largest difference would be NaN, never <= a limit).
. "$srcdir/tests/validate/common.sh"

test -x "${HALO_IMAGE_COMPARE:-}" || { echo "image_compare not built"; exit 99; }
render() { # SCENE HOST OUT [ARG]...
    scene=$1 host=$2 out=$3
    shift 3
    run 0 "$HALO_RENDER" --scene "$srcdir/examples/scenes/$scene.json" --host "$host" --size 64x64 --quiet \
        -o "$tmp/$out.exr" "$@"
}
mean_abs() { # A B: the mean absolute difference image_compare prints
    "$HALO_IMAGE_COMPARE" "$tmp/$1.exr" "$tmp/$2.exr" --max-abs 1e9 --max-share 1 |
        sed -n 's/.*mean abs \([^,]*\),.*/\1/p'
}
for scene in default outline-depth feature-halos; do
    render $scene raycast ray
    render $scene raycast plain --no-halos
    render $scene slab slab
    effect=$(mean_abs ray plain)
    hosts=$(mean_abs ray slab)
    echo "$scene: the stages change the ray caster's image by $effect (mean abs); ray caster against slab host $hosts"
    awk -v e="$effect" -v h="$hosts" 'BEGIN { exit !(e != "" && h != "" && e + 0 > 5 * h) }' ||
        fail "$scene: in the ray caster the stages change the image by $effect, not 5 times $hosts"
done
finish
