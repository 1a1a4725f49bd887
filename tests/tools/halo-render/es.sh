#!/bin/sh
# The GL runtime on OpenGL ES (docs/host-contract.md, "OpenGL ES"): halo-render's raycast
# host through an ES 3.0 context (the WebGL 2 feature set: no per-draw-buffer blending;
# Mesa is made to report 3.0) and an ES 3.2 one, the shaders linked for GLSL ES 3.00.
# - host contract 3 (--one-draw: libhalo's march writes the seeds with one blend for all
#   its buffers) on ES 3.0 and 3.2, and host contract 2 (segments: the host's own seed
#   output blends per buffer) on ES 3.2: each within LIMIT of the same render on desktop
#   OpenGL (EGL); the halos must change the image far more than that (the control);
# - feature halos (the halo buffer splatted by libhalo: GLSL ES 3.00, points sized by the
#   shader) on ES 3.0 and 3.2, within LIMIT of desktop; with GL_EXT_float_blend taken away
#   the buffer is R16F, with a note, within HALF_LIMIT (any pixel may differ: half floats); the feature halos must change the
#   image far more than either (the control);
# - outlines (the host's extra outputs and the passes after its draw), alone and with halos,
#   the ray caster drawn once on ES 3.0 (one blend for all buffers: the outputs written
#   unblended, each pixel once) and 3.2, within LIMIT of desktop; the outlines must change
#   the image far more (the control);
# - contract 2 on ES 3.0 is refused with the way out, and so are outlines without one_draw; the slice host on ES is a usage error.
# Skipped (77) without EGL or an ES context.
. "$srcdir/tests/tools/halo-render/common.sh"
test -x "${HALO_IMAGE_COMPARE:-}" || { echo "image_compare not built"; exit 99; }
if test "${HALO_HAVE_EGL:-}" != yes; then
    echo "this build has no EGL backend: skipping"
    exit 77
fi
# Mesa 22.3's EGL leaks a little at eglTerminate (tests/validate/conform_backend.sh)
ASAN_OPTIONS="detect_leaks=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export ASAN_OPTIONS
LIMIT=1e-4
HALF_LIMIT=1e-2
render() { # BACKEND OUT [ARG]...
    backend=$1 out=$2
    shift 2
    run 0 "$HALO_RENDER" --backend "$backend" --host raycast --size 48x48 --volume-size 24 --quiet \
        -o "$tmp/$out.exr" "$@"
}
"$HALO_RENDER" --backend egl-es3.0 --host raycast --no-halos --size 8x8 --volume-size 8 --quiet \
    -o "$tmp/probe.png" 2>"$tmp/probe" ||
    { cat "$tmp/probe"; grep -q "no headless OpenGL context" "$tmp/probe" && exit 77; }

render egl one-draw --one-draw
render egl segments
render egl plain --no-halos
render egl-es3.0 one-draw-es30 --one-draw
render egl-es3.2 one-draw-es32 --one-draw
render egl-es3.2 segments-es32
compare() { # A B LIMIT [SHARE: of the pixels that may differ at all; default 0]
    echo "+ image_compare $1 $2 --max-abs $3"
    "$HALO_IMAGE_COMPARE" "$tmp/$1.exr" "$tmp/$2.exr" --max-abs "$3" --max-share "${4:-0}" ||
        fail "$1 and $2 differ by more than $3"
}
compare one-draw one-draw-es30 $LIMIT
compare one-draw one-draw-es32 $LIMIT
compare segments segments-es32 $LIMIT
# the control: the halos are visible, far above the limit
if "$HALO_IMAGE_COMPARE" "$tmp/one-draw.exr" "$tmp/plain.exr" --max-abs 0.05 --max-share 0 >/dev/null; then
    fail "the halos change the one-draw image by less than 0.05: the comparison above would not see them"
fi

# feature halos: the halo buffer drawn by the ES context
features=$srcdir/examples/scenes/feature-halos.json
render egl features --scene "$features"
render egl features-plain --scene "$features" --no-halos
render egl-es3.0 features-es30 --scene "$features"
render egl-es3.2 features-es32 --scene "$features"
compare features features-es30 $LIMIT
compare features features-es32 $LIMIT
MESA_EXTENSION_OVERRIDE=-GL_EXT_float_blend
export MESA_EXTENSION_OVERRIDE
render egl-es3.0 features-half --scene "$features"
unset MESA_EXTENSION_OVERRIDE
expect_stderr "note: feature halos: the halo buffer is R16F"
compare features features-half $HALF_LIMIT 1
if "$HALO_IMAGE_COMPARE" "$tmp/features.exr" "$tmp/features-plain.exr" --max-abs 0.05 --max-share 0 >/dev/null; then
    fail "the feature halos change the image by less than 0.05: the comparisons above would not see them"
fi

# outlines: the ray caster's extra outputs, drawn once, and the passes after its draw; with
# halos too (the scene /tmp-made from default.json and outline-depth.json's outline stages)
outline=$srcdir/examples/scenes/outline-depth.json
sed -e 's|"stages": \[|&{"outline_feature": {"value_min": 0.55, "value_max": 1}}, {"outlines": {"sigma": 6, "lambda": 4}},|' \
    "$srcdir/examples/scenes/default.json" >"$tmp/halo-outline.json"
for scene in outline "$tmp/halo-outline.json"; do
    name=$(basename "$scene" .json)
    test "$scene" = outline && scene=$outline && name=outline
    render egl "$name" --one-draw --scene "$scene"
    render egl-es3.0 "$name-es30" --one-draw --scene "$scene"
    render egl-es3.2 "$name-es32" --one-draw --scene "$scene"
    compare "$name" "$name-es30" $LIMIT
    compare "$name" "$name-es32" $LIMIT
done
render egl outline-plain --one-draw --scene "$outline" --no-halos
if "$HALO_IMAGE_COMPARE" "$tmp/outline.exr" "$tmp/outline-plain.exr" --max-abs 0.05 --max-share 0 >/dev/null; then
    fail "the outlines change the image by less than 0.05: the comparisons above would not see them"
fi
if "$HALO_IMAGE_COMPARE" "$tmp/halo-outline.exr" "$tmp/one-draw.exr" --max-abs 0.05 --max-share 0 >/dev/null; then
    fail "the outlines change the halo image by less than 0.05: the comparison above would not see them"
fi

# contract 2 on ES 3.0: its seed output would need glBlendFunci
run 1 "$HALO_RENDER" --backend egl-es3.0 --host raycast --size 8x8 --volume-size 8 -o "$tmp/refused.png"
expect_stderr "per-draw-buffer blending .*OpenGL ES 3.0.*link a ray caster with host contract 3 \(halo_link_desc.one_draw\)"
# outlines on ES 3.0 without one_draw: the host has not said it draws each pixel once
run 1 "$HALO_RENDER" --backend egl-es3.0 --host raycast --scene "$outline" --size 8x8 --volume-size 8 -o "$tmp/refused.png"
expect_stderr "extra outputs \(feature_depth, ...\).*OpenGL ES 3.0.*halo_link_desc.one_draw"
test ! -e "$tmp/refused.png" || fail "an image was written for a refused program"
# without --host a halo scene takes the raycast host drawn once on ES
run 0 "$HALO_RENDER" --backend egl-es3.0 --size 8x8 --volume-size 8 -o "$tmp/auto.png"
expect_stderr "note: OpenGL ES: the raycast host, drawn once"
run 2 "$HALO_RENDER" --backend egl-es3.2 --host slice --size 8x8 -o "$tmp/slice.png"
expect_stderr "error: an OpenGL ES context .* draws the raycast host"
run 2 "$HALO_RENDER" --backend gles -o "$tmp/bad.png"
expect_stderr "'gles' is not egl, osmesa, auto, egl-es3.0 or egl-es3.2"
finish
