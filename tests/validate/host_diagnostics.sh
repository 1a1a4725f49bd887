#!/bin/sh
# Hosts that used to link with exit 0 and render wrong (issue 13): each is now an error
# at the host's own file:line, through 'halo-validate link' and 'check'.
. "$srcdir/tests/validate/common.sh"

scene="$data/scenes/good.json"
# The marker commented out: said so at its line, not "no marker".
run 1 "$HALO_VALIDATE" link --scene "$scene" --host "$data/hosts/marker_commented.frag"
expect_stderr "marker_commented\.frag:3:1: error: .*commented out"
expect_no_stdout
# The marker in a branch taken only for GLSL ES: an error for 330, fine for es300.
run 1 "$HALO_VALIDATE" link --scene "$scene" --host "$data/hosts/marker_es_only.frag" --target 330
expect_stderr "marker_es_only\.frag:4:1: error: .*branch not taken for target 330 .*marker_es_only\.frag:3"
run 0 "$HALO_VALIDATE" link --scene "$scene" --host "$data/hosts/marker_es_only.frag" --target es300 -o "$tmp/es.frag"
# The only halo_apply call commented out, with per-sample stages in the scene.
run 1 "$HALO_VALIDATE" link --scene "$scene" --host "$data/hosts/no_apply.frag"
expect_stderr "no_apply\.frag:11:8: error: .*halo_apply.*commented out.*boundary"
# A GLSL error after '#line 200' is at line 202 of the host, not in a module.
run 1 "$HALO_VALIDATE" link --scene "$scene" --host "$data/hosts/line_directive.frag"
expect_stderr "line_directive\.frag:202:[0-9]+: error:"
if grep -q '^glsl/' "$tmp/err"; then fail "an error of the host is blamed on a module"; fi
# A host macro that rewrites a halo_sample field, at its #define.
run 1 "$HALO_VALIDATE" link --scene "$scene" --host "$data/hosts/macro_clash.frag"
expect_stderr "macro_clash\.frag:3:9: error: .*'opacity'.*#undef"
# An output without a location beside libhalo's extra outputs.
run 1 "$HALO_VALIDATE" link --scene "$data/scenes/seed.json" --host "$data/hosts/no_location.frag"
expect_stderr "no_location\.frag:4:1: error: .*layout\(location = 0\)"
run 0 "$HALO_VALIDATE" link --scene "$data/scenes/seed.json" --host "$data/hosts/host.glsl" -o "$tmp/seed.frag"
# check: a host is a host by its marker, whatever the extension.
run 0 "$HALO_VALIDATE" check "$data/hosts/host.glsl"
grep -q 'host\.glsl: ok' "$tmp/out" || fail "check does not pass the host host.glsl"
cp "$data/hosts/marker_commented.frag" "$tmp/commented.glsl"
run 1 "$HALO_VALIDATE" check --target 330 "$tmp/commented.glsl"
expect_stderr "commented\.glsl:3:1: error: .*commented out"
if grep -q "module" "$tmp/err"; then fail "check takes a host named .glsl for a module"; fi
# ... and a module is a module by its annotation, whatever the extension.
cp "$data/modules/cycle_a.glsl" "$tmp/cycle_a.frag"
run 0 "$HALO_VALIDATE" check "$tmp/cycle_a.frag"
finish
