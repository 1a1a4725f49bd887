#!/bin/sh
# The good inputs that the bad-input tests start from link, validate and reflect:
# a failure elsewhere is then the input's fault, not the setup's.
. "$srcdir/tests/validate/common.sh"

for target in 330 450 es300; do
    run 0 "$HALO_VALIDATE" link --scene "$data/scenes/good.json" --host "$data/hosts/minimal.frag" \
        --target "$target" -o "$tmp/linked.frag"
    test -s "$tmp/linked.frag" || fail "link -o wrote nothing for target $target"
done
grep -q '^#version 300 es' "$tmp/linked.frag" || fail "es300 output has no '#version 300 es'"
run 0 "$HALO_VALIDATE" link --scene "$data/scenes/good.json" --host "$data/hosts/minimal.frag" --reflect
grep -q '"halo_boundary_k_gc"' "$tmp/out" || fail "--reflect does not list the live uniform halo_boundary_k_gc"
run 0 "$HALO_VALIDATE" link --scene "$data/scenes/good.json" --host "$data/hosts/minimal.frag"
grep -q 'halo_apply' "$tmp/out" || fail "link without -o prints no linked source"
# An image no sample stage reads (halo_map's occlusion without occlusive halos: its
# read_when=mode is off) is read as zero without a fetch; with occlusive halos it is fetched.
scenes="$srcdir/examples/scenes"
run 0 "$HALO_VALIDATE" link --scene "$scenes/halo-emissive.json" --host "$srcdir/examples/hosts/raycast.frag"
grep -q 'halo_read_occlusion(vec2 fragcoord) { return halo_channels(0.0); }' "$tmp/out" ||
    fail "an emissive halo scene still fetches its occlusion image"
run 0 "$HALO_VALIDATE" link --scene "$scenes/halo-occlusive.json" --host "$srcdir/examples/hosts/raycast.frag"
grep -q 'texelFetch(halo_image_occlusion' "$tmp/out" || fail "an occlusive halo scene does not read its occlusion image"
# The good modules pass check alone; together with their cycle only a scene fails.
run 0 "$HALO_VALIDATE" check "$data/modules/cycle_a.glsl" "$data/modules/cycle_b.glsl"
run 0 "$HALO_VALIDATE" list
grep -q '^boundary' "$tmp/out" || fail "list does not show boundary"
run 0 "$HALO_VALIDATE" --help
run 0 "$HALO_VALIDATE" --version
finish
