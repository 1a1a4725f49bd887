#!/bin/sh
# A UTF-8 byte-order mark (editors write it) at the start of a module, host, scene or
# polyline file is skipped: the file is read as without it, and the columns of line 1
# are counted from the first character after it.
. "$srcdir/tests/validate/common.sh"

bom=$(printf '\357\273\277')
{ printf '%s' "$bom"; cat "$data/hosts/minimal.frag"; } >"$tmp/host.frag"
{ printf '%s' "$bom"; cat "$data/scenes/good.json"; } >"$tmp/scene.json"
printf '%s#pragma halo module bom_module\n#pragma halo hook sample\nvoid apply(inout halo_sample s) {}\n' "$bom" \
    >"$tmp/module.glsl"
printf '%s{"halo_scene": 1, "stages": [}\n' "$bom" >"$tmp/broken.json"
printf '%s#pragma halo module bom_bad\n#pragma halo hook sample\n#pragma halo nonsense\n' "$bom" >"$tmp/bad.glsl"
printf '%shalo-polylines 1\nline\n0 0 0\n1 1 1\n' "$bom" >"$tmp/lines.txt"

run 0 "$HALO_VALIDATE" check --target 330 "$tmp/host.frag" "$tmp/module.glsl"
run 0 "$HALO_VALIDATE" link --scene "$tmp/scene.json" --host "$tmp/host.frag" --module "$tmp/module.glsl"
grep -q "HALO_LINKED" "$tmp/out" || fail "no linked shader on stdout"
# the linked shader has no byte-order mark in its middle
if grep -q "$bom" "$tmp/out"; then fail "the byte-order mark reached the linked shader"; fi
# columns on line 1 after the mark: as if it were not there
run 1 "$HALO_VALIDATE" link --scene "$tmp/broken.json" --host "$tmp/host.frag"
expect_stderr "broken\.json:1:30: error:"
run 1 "$HALO_VALIDATE" check --target 330 "$tmp/bad.glsl"
expect_stderr "bad\.glsl:3:[0-9]+: error:"
if grep -q "bad\.glsl:1:" "$tmp/err"; then fail "an error on line 1 for the byte-order mark"; fi

# the renderers' own reads of the scene, and the polyline reader
HALO_LINES=${HALO_LINES:-${top_builddir:-.}/tools/halo-lines}
run 0 "$HALO_RENDER" --quiet --scene "$tmp/scene.json" --size 16x16 --volume-size 16 -o "$tmp/scene.png"
if test -x "$HALO_LINES"; then
    "$HALO_LINES" --lines "$tmp/lines.txt" --size 16x16 -o "$tmp/lines.png" >"$tmp/out" 2>&1
    status=$?
    if ! grep -q "no OpenGL context" "$tmp/out" && test "$status" -ne 0; then
        fail "halo-lines refused a polyline file with a byte-order mark (exit $status)"
        sed 's/^/    /' "$tmp/out" >&2
    fi
fi
finish
