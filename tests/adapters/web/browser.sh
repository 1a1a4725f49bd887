#!/bin/sh
# The web package in headless Chromium (tests/adapters/web/browser.mjs): examples/hosts/raycast.frag
# with a scene's per-sample stages, linked in the page by the WebAssembly linker and drawn
# in WebGL 2, and the package's three.js ray caster with the stages put in by installHalo
# (adapters/web/three.mjs), against halo-render --host raycast with the same inputs
# (--export-host); and the default scene's volumetric halos drawn once (host contract 3: the
# field computed by libhalo's GL runtime in WebAssembly on the page's context) against
# halo-render --one-draw; NiiVue and vtk.js with the MRI head's stages and halos through the
# package's adapters (adapters/web/niivue.mjs, vtkjs.mjs), against the viewer alone, vtk.js
# against halo-render, NiiVue against libhalo's C runtime drawing a host in its style with the
# inputs the page exports (tests/adapters/web/niivue_reference). Skipped
# (77) without the web package, Chromium, puppeteer-core or three (setup.sh installs them:
# Debian's chromium, npm ci in tests/adapters/web from its lock file).
. "$srcdir/tests/tools/halo-render/common.sh"
if test "${HALO_HAVE_WEB:-}" != yes; then
    echo "the web package is not built (configure --with-web): skipping"
    exit 77
fi
HALO_CHROMIUM=${HALO_CHROMIUM:-$(command -v chromium || true)}
if test -z "$HALO_CHROMIUM"; then
    echo "no chromium (the Debian package chromium): skipping"
    exit 77
fi
HALO_WEB_MODULES=${HALO_WEB_MODULES:-$srcdir/tests/adapters/web/node_modules}
for module in puppeteer-core three; do
    if test ! -d "$HALO_WEB_MODULES/$module"; then
        echo "no $module in $HALO_WEB_MODULES (setup.sh: npm ci --prefix tests/adapters/web): skipping"
        exit 77
    fi
done
export HALO_CHROMIUM HALO_WEB_MODULES srcdir HALO_WEB_PACKAGE
set --
for scene in boundary-silhouette.json distance.json orientation.json feature-halos.json; do
    mkdir -p "$tmp/$scene"
    run 0 "$HALO_RENDER" --host raycast --scene "$srcdir/examples/scenes/$scene" --size 64x64 --volume-size 32 \
        --quiet --export-host "$tmp/$scene" -o "$tmp/$scene/reference.png"
    set -- "$@" "$tmp/$scene" "$scene"
done
# host contract 3 in the page: the halo field by libhalo's C runtime in WebAssembly
mkdir -p "$tmp/one-draw"
run 0 "$HALO_RENDER" --host raycast --one-draw --scene "$srcdir/examples/scenes/default.json" --size 64x64 \
    --volume-size 32 --quiet --export-host "$tmp/one-draw" -o "$tmp/one-draw/reference.png"
set -- "$@" "$tmp/one-draw" one-draw:default.json
# outlines in the page: the ray caster's extra outputs (unblended on WebGL 2) and the passes
# after its draw, with halos drawn once (the scene: default.json with outline-depth.json's
# outline stages)
mkdir -p "$tmp/outline"
sed -e 's|"stages": \[|&{"outline_feature": {"value_min": 0.55, "value_max": 1}}, {"outlines": {"sigma": 6, "lambda": 4}},|' \
    "$srcdir/examples/scenes/default.json" >"$tmp/outline/halo-outline.json"
run 0 "$HALO_RENDER" --host raycast --one-draw --scene "$tmp/outline/halo-outline.json" --size 64x64 \
    --volume-size 32 --quiet --export-host "$tmp/outline" -o "$tmp/outline/reference.png"
set -- "$@" "$tmp/outline" one-draw:/in/halo-outline.json
# NiiVue and vtk.js: the MRI head at 96^3, as halo-render resamples it (browser.mjs writes it
# as NIfTI); without a viewer or the MRI the others still run, and the log says what was left out
mri=/usr/share/mricron/templates/ch2better.nii.gz
HALO_WEB_ENGINES=
if test ! -d "$HALO_WEB_MODULES/@niivue/niivue"; then
    echo "NOT TESTED: NiiVue and the demo page: no @niivue/niivue in $HALO_WEB_MODULES (setup.sh: npm ci)"
else
    HALO_WEB_ENGINES=niivue
fi
if test ! -d "$HALO_WEB_MODULES/vtk.js"; then
    echo "NOT TESTED: vtk.js: no vtk.js in $HALO_WEB_MODULES (setup.sh: npm ci)"
else
    HALO_WEB_ENGINES="$HALO_WEB_ENGINES vtkjs"
fi
# NiiVue's frames drawn again by libhalo's C runtime (a host in NiiVue's style, with the
# inputs the page exports), which browser.mjs compares NiiVue's with
if test -n "${HALO_WEB_NIIVUE_REFERENCE:-}"; then
    harness_program "$HALO_WEB_NIIVUE_REFERENCE"
    export HALO_WEB_NIIVUE_REFERENCE
fi
if test -n "$HALO_WEB_ENGINES" && test ! -f "$mri"; then
    echo "NOT TESTED: $HALO_WEB_ENGINES: no $mri (the Debian package mricron-data, which setup.sh installs)"
elif test -n "$HALO_WEB_ENGINES"; then
    # the scene drawn once with its halos, and without its halo_* stages (vtk.js, set up as
    # raycast.frag samples, is compared with both at the page's 128^2)
    mkdir -p "$tmp/mri"
    run 0 "$HALO_RENDER" --host raycast --one-draw --scene "$srcdir/examples/scenes/mri-head.json" --volume "$mri" \
        --size 128x128 --volume-size 96 --quiet --export-host "$tmp/mri" -o "$tmp/mri/reference.png"
    # a variant of the MRI scene (JS changes `scene`; halos() drops its halo_* stages) and
    # halo-render's image of it: mri_case NAME WHAT JS [HALO_RENDER ARGS]...
    mri_case() {
        name=$1 what=$2 change=$3
        shift 3
        mkdir -p "$tmp/$name"
        "$NODE" -e 'const fs = require("fs"), scene = JSON.parse(fs.readFileSync(process.argv[1]));
            const halos = () => { scene.stages = scene.stages.filter((s) => !Object.keys(s).some((k) => k.startsWith("halo_"))); };
            eval(process.argv[3]);
            fs.writeFileSync(process.argv[2], JSON.stringify(scene));' \
            "$srcdir/examples/scenes/mri-head.json" "$tmp/$name/scene.json" "$change" || fail "writing the scene $what"
        run 0 "$HALO_RENDER" --host raycast --scene "$tmp/$name/scene.json" --volume "$mri" --size 128x128 \
            --volume-size 96 --quiet --export-host "$tmp/$name" -o "$tmp/$name/reference.png" "$@"
    }
    mri_case mri-stages "without its halo stages" 'halos()'
    # its stages without halo_* and with feature halos instead (vtk.js, set up as raycast.frag)
    mri_case mri-features "with feature halos" 'halos(); scene.stages.push({ feature_halo: { opacity_gain: 2,
        darkening: 4, threshold: 0.02, gradient_weighted: true } })'
    # its stages and halos with outlines (vtk.js, set up as raycast.frag, drawn once)
    mri_case mri-outlines "with outlines" 'scene.stages.push({ outline_feature: { value_min: 0.4, value_max: 1 } },
        { outlines: { sigma: 4, lambda: 6 } })' --one-draw
    HALO_WEB_MRI_OUTLINES=$tmp/mri-outlines
    HALO_WEB_MRI=$tmp/mri
    HALO_WEB_MRI_STAGES=$tmp/mri-stages
    HALO_WEB_MRI_FEATURES=$tmp/mri-features
    # the same three in raycast.frag and the three.js caster (a scene path from / is the page's
    # /in/, the case's folder)
    set -- "$@" "$tmp/mri-stages" /in/scene.json "$tmp/mri" one-draw:mri-head.json "$tmp/mri-features" /in/scene.json
    export HALO_WEB_MRI HALO_WEB_MRI_STAGES HALO_WEB_MRI_FEATURES HALO_WEB_MRI_OUTLINES HALO_WEB_ENGINES
fi
echo "+ node browser.mjs $*"
"$NODE" "$srcdir/tests/adapters/web/browser.mjs" "$@" || fail "the pages' images (above)"
finish
