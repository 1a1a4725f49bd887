#!/bin/sh
# Unknown commands and options, and missing arguments: exit 2, a message on stderr.
. "$srcdir/tests/validate/common.sh"

run 2 "$HALO_VALIDATE"
run 2 "$HALO_VALIDATE" frobnicate
expect_stderr "frobnicate"
run 2 "$HALO_VALIDATE" --frobnicate
run 2 "$HALO_VALIDATE" check
run 2 "$HALO_VALIDATE" check --bogus "$srcdir/glsl/sample/boundary.glsl"
expect_stderr "bogus"
run 2 "$HALO_VALIDATE" check --target 999 "$srcdir/glsl/sample/boundary.glsl"
run 2 "$HALO_VALIDATE" check "$data/scenes/good.json"
expect_error_in good.json
# conform --stage: a name that is no row, family or stage; an image-pass stage's name
# points at its rows
run 2 "$HALO_VALIDATE" conform --stage no_such_stage
expect_stderr "no per-sample stage 'no_such_stage'"
run 2 "$HALO_VALIDATE" conform --stage halo_generate
expect_stderr "'halo_generate' is an image-pass stage: its rows are"
run 2 "$HALO_VALIDATE" link --bogus
expect_stderr "bogus"
run 2 "$HALO_VALIDATE" link --scene "$data/scenes/good.json"
run 2 "$HALO_VALIDATE" link --scene
run 2 "$HALO_VALIDATE" link --scene "$data/scenes/good.json" --host "$data/hosts/minimal.frag" --target es310
expect_stderr "es310"
# the headless backend (--backend, HALO_HEADLESS): checked before anything renders
run 2 "$HALO_VALIDATE" conform --backend vulkan --stage empty
expect_stderr "--backend: 'vulkan' is not egl, osmesa, auto, egl-es3.0 or egl-es3.2"
# OpenGL ES: halo-render's raycast host (tests/tools/halo-render/es.sh) and conform (tests/validate/conform_es.sh) only
run 2 "$HALO_VALIDATE" bench --backend egl-es3.0 --size 16
expect_stderr "'egl-es3.0': this tool draws with desktop OpenGL only \\(on OpenGL ES: halo-render, halo-validate conform\\)"
run 2 "$HALO_VALIDATE" bench --backend
expect_stderr "--backend needs a value"
run 2 "$HALO_VALIDATE" check --backend egl "$srcdir/glsl/sample/boundary.glsl"
expect_stderr "unknown option '--backend'"
run 2 env HALO_HEADLESS=vulkan "$HALO_VALIDATE" conform --stage empty
expect_stderr "no headless OpenGL context: HALO_HEADLESS: 'vulkan' is not egl, osmesa, auto, egl-es3.0 or egl-es3.2"
# An option the user gave that cannot apply is a usage error, never ignored (issue 26):
# the composer-piece options with a host shader, an empty or malformed --kernels list.
for opt in "--segmented" "--sample value=v" "--first-output-location 2"; do
    run 2 "$HALO_VALIDATE" link --host "$data/hosts/minimal.frag" $opt
    expect_stderr "${opt%% *} applies to --pieces only"
done
for kernels in "" "5," "5,,7" "x" "3,5,7,9,11,13,15,17,19"; do
    run 2 "$HALO_VALIDATE" blur --kernels "$kernels"
    expect_stderr "blur: --kernels takes 1 to 8 odd sizes"
done
if test -n "${HALO_RENDER:-}" && test -x "$HALO_RENDER"; then
    run 2 "$HALO_RENDER" --backend=software
    expect_stderr "halo-render: error: --backend: 'software'"
    run 2 "$HALO_RENDER" --bogus
    run 2 "$HALO_RENDER" --size 0x0
    run 2 "$HALO_RENDER" --size
    # host contract 3 draws the ray caster or the slice host once: not the slab host
    run 2 "$HALO_RENDER" --export-host "$tmp" --host slab
    expect_stderr "export-host writes the raycast host's inputs: it needs --host raycast"
    run 2 "$HALO_RENDER" --export-host "$tmp/no/such/folder" --host raycast --size 8x8 --volume-size 8 -o "$tmp/e.png"
    expect_stderr "export-host: cannot write .*no/such/folder/host.json"
    run 2 "$HALO_RENDER" --one-draw --host slab
    expect_stderr "one-draw draws the host once over the halo field .host contract 3.: it needs --host raycast or slice"
    run 2 "$HALO_RENDER" --one-draw
    run 2 "$HALO_RENDER" --one-draw --host slice --gradient-format packed32
    expect_stderr "one-draw: libhalo's march reads the slice host's R32F volume, which the packed gradient formats free"
fi
finish
