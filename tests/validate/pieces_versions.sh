#!/bin/sh
# Issue 26: a shader linked without a #version line (--version none, what a three.js
# ShaderMaterial takes; --version keep of a host that has none) is validated as the
# target it is linked for, not as GLSL ES 1.00 (which failed on valid hosts); under GLSL
# ES it gets its precision statements; and 'link --pieces -o FILE' writes FILE.
. "$srcdir/tests/validate/common.sh"

sed '/^#version/d' "$data/hosts/host.glsl" >"$tmp/no_version.frag"
for target in 330 450 es300; do
    run 0 "$HALO_VALIDATE" link --scene "$data/scenes/seed.json" --host "$data/hosts/host.glsl" \
        --target $target --version none -o "$tmp/none.frag"
    if grep -q '^#version' "$tmp/none.frag"; then fail "--version none wrote a #version line"; fi
    run 0 "$HALO_VALIDATE" link --scene "$data/scenes/seed.json" --host "$tmp/no_version.frag" \
        --target $target --version keep -o "$tmp/keep.frag"
    if grep -q '^#version' "$tmp/keep.frag"; then fail "--version keep added a #version line"; fi
done
grep -q '^precision highp float;' "$tmp/keep.frag" || fail "--version keep --target es300 has no precision"
# ... and an error in such a shader is still the host's, at its line
sed 's/fragment_color = color;/fragment_color = color.xyz;/' "$tmp/no_version.frag" >"$tmp/bad.frag"
run 1 "$HALO_VALIDATE" link --scene "$data/scenes/seed.json" --host "$tmp/bad.frag" --version keep -o "$tmp/bad_out.frag"
expect_stderr "bad\.frag:[0-9]+:[0-9]+: error:"

# --pieces -o FILE: the pieces, with their headers, in FILE (and nothing on stdout)
run 0 "$HALO_VALIDATE" link --pieces --scene "$data/scenes/good.json" --sample volume=in_volume -o "$tmp/pieces.glsl"
expect_no_stdout
for piece in declarations sample finish; do
    grep -q "^// ==== libhalo piece: $piece ====" "$tmp/pieces.glsl" || fail "-o FILE lacks the $piece piece"
done
finish
