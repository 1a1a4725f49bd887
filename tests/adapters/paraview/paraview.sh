#!/bin/sh
# libhalo in ParaView across MPI ranks (adapters/paraview, docs/distributed.md): pvbatch
# renders the built-in volume (halo-vtk --export) with the HaloVolume plugin on 1 and 2
# ranks, each rank drawing its own brick and IceT compositing them. Skipped (77) without
# the plugin, halo-vtk, pvbatch, mpirun or xvfb-run. Checks, 2 ranks against 1 (mean abs
# and the share of pixels over 1/255):
#  - per-sample stages (boundary and silhouette, tone shading, distance colour blending)
#    within the tolerance below, and each changes the image by at least 4x its error;
#  - a control that must fail it: the distance cue with each rank in its own brick's
#    space (HALO_PARAVIEW_LOCAL=1, what a per-rank install without the whole extent does);
#  - volumetric halos with the seeds combined over the ranks within the halo tolerance,
#    and the naive halos (each rank's own seeds, HaloExchange 0) outside it; the same with
#    the representation's shading on (the stages on VTK's own gradient);
#  - outlines across ranks are refused with a diagnostic (they need the composited image),
#    and a scene with an error gets its diagnostic; both make pvbatch exit non-zero.
. "${srcdir:-.}/tests/harness.sh"
harness_need srcdir HALO_IMAGE_COMPARE HALO_PVBATCH_SCRIPT
if test -z "${HALO_PARAVIEW_PLUGIN:-}" || test ! -f "$HALO_PARAVIEW_PLUGIN"; then
    echo "SKIP: the ParaView plugin is not built (configure found no ParaView, or this is a sanitizer build: pvbatch is not instrumented)"
    exit 77
fi
if test -z "${HALO_VTK:-}" || test ! -x "$HALO_VTK"; then
    echo "SKIP: halo-vtk is not built (it exports the volume)"
    exit 77
fi
for tool in pvbatch mpirun xvfb-run; do
    command -v $tool >/dev/null 2>&1 || { echo "SKIP: $tool not found (install paraview, openmpi-bin, xvfb)"; exit 77; }
done
if test -z "${HALO_PARAVIEW_UNDER_X:-}"; then
    harness_tmp halo-paraview-test
    . "$srcdir/tests/xrun.sh"
    HALO_PARAVIEW_UNDER_X=1 xrun sh "$0"
    exit $?
fi

scenes="$srcdir/examples/scenes"
harness_tmp halo-paraview-test
# OpenMPI refuses root unless told (CI runs as root)
OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_ALLOW_RUN_AS_ROOT OMPI_ALLOW_RUN_AS_ROOT_CONFIRM
"$HALO_VTK" --quiet --scene "$scenes/default.json" --volume-size 64 --size 96x96 --export "$tmp/volume" ||
    { echo "FAIL: halo-vtk --export exited $?"; exit 1; }

# pvrun NAME RANKS ARG...: one pvbatch run of halo_pvbatch.py, its output in $tmp/NAME.log;
# returns its exit status. A new X connection is sometimes refused ("bad X server
# connection"; seen right after the server starts and now and then later), and a rank
# without one can leave the others waiting: the run is stopped as soon as its output
# says so, and tried again (at most 6 times, each at most 5 minutes, waiting 1, 2, ... 5 s
# between: on a loaded machine the refusals came four times in a row once, session 25).
pvrun() {
    p_name=$1 p_ranks=$2 p_try=1
    shift 2
    while :; do
        timeout 300 mpirun --oversubscribe -np "$p_ranks" pvbatch "$HALO_PVBATCH_SCRIPT" \
            --plugin "$HALO_PARAVIEW_PLUGIN" --view "$tmp/volume" "$@" >"$tmp/$p_name.log" 2>&1 &
        p_pid=$!
        # a refused connection is known at once: the run stops then, not at the timeout
        while kill -0 "$p_pid" 2>/dev/null; do
            if grep -E -q "bad X server connection|remote rendering which" "$tmp/$p_name.log"; then
                kill "$p_pid" 2>/dev/null
                break
            fi
            sleep 1
        done
        wait "$p_pid"
        p_status=$?
        if test $p_try -lt 6 &&
            { test $p_status -eq 124 || grep -E -q "bad X server connection|remote rendering which" "$tmp/$p_name.log"; }; then
            echo "    (pvbatch on $p_ranks ranks: no X connection on a rank; trying again)"
            sleep $p_try
            p_try=$((p_try + 1))
            continue
        fi
        return $p_status
    done
}
# pv NAME RANKS JOBS [ARG...]: renders the jobs (OUTPUT SCENE|- [EXCHANGE [SETTINGS]] a
# line) in one pvbatch run (ARGs to halo_pvbatch.py); any error, the plugin's included,
# fails the test.
pv() {
    printf '%s\n' "$3" >"$tmp/$1.jobs"
    p_pv_name=$1 p_pv_ranks=$2
    shift 3
    if pvrun "$p_pv_name" "$p_pv_ranks" --jobs "$tmp/$p_pv_name.jobs" "$@" && ! grep -q "HaloVolume" "$tmp/$p_pv_name.log"; then
        return 0
    fi
    fail "pvbatch on $p_pv_ranks rank(s) ($p_pv_name) failed or the plugin reported errors"
    grep -v "No plugin loaded yet" "$tmp/$p_pv_name.log" | sed 's/^/    /' | head -20 >&2
    return 1
}
# metrics A B: "MEAN SHARE" (mean abs; percent of pixels over 1/255)
metrics() {
    "$HALO_IMAGE_COMPARE" "$tmp/$1.png" "$tmp/$2.png" --max-abs 1 --max-share 1 --threshold 0.00393 |
        sed -n 's/.*mean abs \([^,]*\), [0-9]* pixels (\([^ ]*\) %).*/\1 \2/p'
}
# within MEAN SHARE MAX_MEAN MAX_SHARE: true when both are within
within() {
    awk -v m="$1" -v s="$2" -v mm="$3" -v ms="$4" 'BEGIN { exit !(m <= mm && s <= ms) }'
}
# halo_ranks ONE TWO WHAT: the halos of image TWO (2 ranks) against ONE (1 rank) within
# the halos' tolerance (halo_mean, halo_share below), said and checked
halo_ranks() {
    h_what=$3
    set -- $(metrics "$1" "$2")
    echo "halos $h_what: 2 ranks against 1: mean abs $1, $2 % over 1/255"
    test $# -eq 2 && within "$1" "$2" $halo_mean $halo_share ||
        fail "halos $h_what: 2 ranks differ from 1 by mean abs $1, $2 % over 1/255 (tolerance $halo_mean, $halo_share %)"
}

# tolerances (docs/distributed.md): per-sample stages, and halos
sample_mean=2.5e-3 sample_share=10
halo_mean=2.0e-3 halo_share=10
# the distance cue towards red and linear in depth: a clear depth ramp across the bricks
distance="$scenes/distance.json 1 distance_blend.background=1,0,0;distance_blend.k_de=1"
pv one 1 "$tmp/plain-1.png -
$tmp/boundary-silhouette-1.png $scenes/boundary-silhouette.json
$tmp/tone-1.png $scenes/tone.json
$tmp/distance-1.png $distance
$tmp/default-1.png $scenes/default.json"
pv two 2 "$tmp/boundary-silhouette-2.png $scenes/boundary-silhouette.json
$tmp/tone-2.png $scenes/tone.json
$tmp/distance-2.png $distance
$tmp/default-2.png $scenes/default.json 1
$tmp/default-naive-2.png $scenes/default.json 0"
HALO_PARAVIEW_LOCAL=1 pv local 2 "$tmp/distance-local-2.png $distance"

for scene in boundary-silhouette tone distance; do
    set -- $(metrics "$scene-1" "$scene-2")
    test $# -eq 2 || { fail "$scene: no comparison"; continue; }
    effect=$(metrics plain-1 "$scene-1" | cut -d' ' -f1)
    echo "$scene: 2 ranks against 1: mean abs $1, $2 % of pixels over 1/255; the stages change the image by $effect"
    within "$1" "$2" $sample_mean $sample_share ||
        fail "$scene: 2 ranks differ from 1 by mean abs $1, $2 % over 1/255 (tolerance $sample_mean, $sample_share %)"
    awk -v e="$effect" -v m="$1" 'BEGIN { exit !(e >= 4 * m) }' ||
        fail "$scene: the stages change the image by $effect, less than 4x the 2-rank error $1"
done
set -- $(metrics distance-1 distance-local-2)
echo "control, the distance cue in each brick's own space: mean abs $1, $2 % over 1/255"
test $# -eq 2 && within "$1" "$2" $sample_mean $sample_share && fail "control: the brick-space distance cue passed"

halo_ranks default-1 default-2 "(the seeds combined over the ranks)"
set -- $(metrics default-1 default-naive-2)
echo "control, each rank's own seeds: mean abs $1, $2 % over 1/255"
test $# -eq 2 && within "$1" "$2" $halo_mean $halo_share && fail "control: the naive halos passed the halo tolerance"

# halo images and libhalo's march at 1/2 (HaloImageScale 2): 2 ranks against 1 at 1/2, the
# same tolerance; and the property takes effect (1/2 is not the full-size image)
pv half-one 1 "$tmp/default-half-1.png $scenes/default.json" --image-scale 2
pv half-two 2 "$tmp/default-half-2.png $scenes/default.json 1" --image-scale 2
halo_ranks default-half-1 default-half-2 "at 1/2 (HaloImageScale 2)"
set -- $(metrics default-1 default-half-1)
echo "halos at 1/2 against full size, 1 rank: mean abs $1, $2 % over 1/255"
test $# -eq 2 && awk -v m="$1" 'BEGIN { exit !(m > 0) }' || fail "HaloImageScale 2 changed nothing"

# the representation's shading on (VTK's lighting; the stages take VTK's gradient, kept
# from its lighting, on each piece): 2 ranks against 1 within the halos' tolerance, and
# the shading takes effect (measured at 96x96: 2 ranks against 1 1.2e-3, 7.7 %; on against
# off 2.2e-3)
pv shade-one 1 "$tmp/default-shade-1.png $scenes/default.json" --shade
HALO_VTK_DUMP="$tmp/shade-two.frag" # the shader VTK built on a rank (halo_vtk_check writes it)
export HALO_VTK_DUMP
pv shade-two 2 "$tmp/default-shade-2.png $scenes/default.json 1" --shade
unset HALO_VTK_DUMP
if ! test -s "$tmp/shade-two.frag"; then
    fail "halos with shading on 2 ranks: no shader written by halo_vtk_check (HALO_VTK_DUMP)"
elif grep -q "halo_vtk_shading_gradient = shading_gradient" "$tmp/shade-two.frag"; then
    echo "halos with shading on 2 ranks: the stages take VTK's gradient (kept from its lighting)"
elif grep -q "shading_gradient" "$tmp/shade-two.frag"; then
    fail "halos with shading on 2 ranks: VTK's shader computes shading_gradient, but does not keep it for the stages"
else
    echo "halos with shading on 2 ranks: this VTK's lighting has no shading_gradient: the adapter's texture"
fi
halo_ranks default-shade-1 default-shade-2 "with shading on"
set -- $(metrics default-1 default-shade-1)
echo "shading on against off, 1 rank: mean abs $1"
test $# -eq 2 && awk -v m="$1" 'BEGIN { exit !(m > 5e-4) }' || fail "--shade changed nothing (mean abs $1)"

# a screenshot above the view's size (the GUI's Save Screenshot; ParaView renders it in
# tiles): halos are refused with the reason and the script's exit status says so (before: an
# empty image, exit 0); per-sample stages are the same as a render at that size
pvrun tiled 1 --scene "$scenes/default.json" --screenshot-scale 2 -o "$tmp/tiled.png"
status=$?
test $status -ne 0 && grep -q "tiles" "$tmp/tiled.log" ||
    { fail "halos in a tiled screenshot: exit $status, expected non-zero with a message on the tiles"; sed 's/^/    /' "$tmp/tiled.log" | head -20 >&2; }
pv tiled-tone 1 "$tmp/tiled-tone.png $scenes/tone.json" --screenshot-scale 2
"$HALO_VTK" --quiet --scene "$scenes/default.json" --volume-size 64 --size 192x192 --export "$tmp/volume2" ||
    fail "halo-vtk --export at 192x192 exited $?"
pv direct-tone 1 "$tmp/direct-tone.png $scenes/tone.json" --view "$tmp/volume2"
set -- $(metrics tiled-tone direct-tone)
echo "tone in a 2x2-tiled screenshot against a render at that size: mean abs $1, $2 % over 1/255"
test $# -eq 2 && within "$1" "$2" $sample_mean $sample_share ||
    fail "tone, tiled: differs from a direct render by mean abs $1, $2 % over 1/255"

# outlines need the composited image: refused on 2 ranks, with the reason, and the script's
# exit status says so (HaloStatus)
pvrun outline 2 --scene "$scenes/outline-depth.json" -o "$tmp/outline.png"
status=$?
grep -q "finished image (outlines)" "$tmp/outline.log" ||
    { fail "outlines on 2 ranks: no diagnostic"; sed 's/^/    /' "$tmp/outline.log" | head -20 >&2; }
test $status -ne 0 || fail "outlines on 2 ranks: refused, but pvbatch exited 0"
# a scene with an error: the reason at its file:line:col, and a non-zero exit
printf '{"halo_scene": 1, "stages": [{"tone_shading": {"k_ta": "x"}}]}\n' >"$tmp/bad.json"
pvrun bad 1 --scene "$tmp/bad.json" -o "$tmp/bad.png"
status=$?
grep -q "bad.json:1:" "$tmp/bad.log" || { fail "a bad scene: no diagnostic at its file:line"; sed 's/^/    /' "$tmp/bad.log" | head -20 >&2; }
test $status -ne 0 || fail "a bad scene: pvbatch exited 0"
echo "refused and bad scenes: pvbatch exits non-zero ($status)"
finish
