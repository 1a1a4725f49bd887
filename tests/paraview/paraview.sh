#!/bin/sh
# libhalo in ParaView across MPI ranks (adapters/paraview, docs/distributed.md): pvbatch
# renders the built-in volume (halo-vtk --export) with the HaloVolume plugin on 1 and 2
# ranks, each rank drawing its own brick, IceT compositing them. Skipped (77) without the
# plugin, halo-vtk, pvbatch, mpirun or xvfb-run. Checks, 2 ranks against 1 (mean abs
# and the share of pixels over 1/255):
#  - per-sample stages (boundary and silhouette, tone shading, distance colour blending)
#    within the tolerance below, and each changes the image by at least 4x its error;
#  - a control that must fail it: the distance cue with each rank in its own brick's
#    space (HALO_PARAVIEW_LOCAL=1, what a per-rank install without the whole extent does);
#  - volumetric halos with the seeds combined over the ranks within the halo tolerance,
#    and the naive halos (each rank's own seeds, HaloExchange 0) outside it;
#  - outlines across ranks are refused with a diagnostic (they need the composited image).
if test -z "${HALO_IMAGE_COMPARE:-}" || test -z "${HALO_PVBATCH_SCRIPT:-}"; then
    echo "broken setup: run through 'make check' (HALO_IMAGE_COMPARE or HALO_PVBATCH_SCRIPT unset)" >&2
    exit 99
fi
if test -z "${HALO_PARAVIEW_PLUGIN:-}" || test ! -f "$HALO_PARAVIEW_PLUGIN"; then
    echo "SKIP: the ParaView plugin is not built (configure found no ParaView: install paraview-dev)"
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
    tmp=$(mktemp -d "${TMPDIR:-/tmp}/halo-paraview-test.XXXXXX") || exit 99
    trap 'rm -rf "$tmp"' EXIT
    . "$srcdir/tests/xrun.sh"
    HALO_PARAVIEW_UNDER_X=1 xrun sh "$0"
    exit $?
fi

scenes="$srcdir/examples/scenes"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/halo-paraview-test.XXXXXX") || exit 99
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() {
    echo "FAIL: $*" >&2
    failures=$((failures + 1))
}
# OpenMPI refuses root unless told (CI runs as root)
OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_ALLOW_RUN_AS_ROOT OMPI_ALLOW_RUN_AS_ROOT_CONFIRM
"$HALO_VTK" --quiet --scene "$scenes/default.json" --volume-size 64 --size 96x96 --export "$tmp/volume" ||
    { echo "FAIL: halo-vtk --export exited $?"; exit 1; }

# pv OUT RANKS [ARG]...: a render; a new X connection right after the server starts is
# sometimes refused ("bad X server connection"): tried again
pv() {
    p_out=$1 p_ranks=$2
    shift 2
    p_try=1
    while :; do
        mpirun --oversubscribe -np "$p_ranks" pvbatch "$HALO_PVBATCH_SCRIPT" --plugin "$HALO_PARAVIEW_PLUGIN" \
            --view "$tmp/volume" -o "$tmp/$p_out.png" "$@" >"$tmp/$p_out.log" 2>&1 && return 0
        if test $p_try -lt 3 && grep -q "bad X server connection" "$tmp/$p_out.log"; then
            p_try=$((p_try + 1))
            sleep 1
            continue
        fi
        fail "pvbatch on $p_ranks rank(s) $* exited with an error"
        grep -v "No plugin loaded yet" "$tmp/$p_out.log" | sed 's/^/    /' | head -20 >&2
        return 1
    done
}
# metrics A B: "MEAN SHARE" (mean abs; percent of pixels over 1/255)
metrics() {
    "$HALO_IMAGE_COMPARE" "$tmp/$1.png" "$tmp/$2.png" --max-abs 1 --max-share 1 --threshold 0.00393 |
        sed -n 's/.*mean abs \([^,]*\), [0-9]* pixels (\([^ ]*\) %).*/\1 \2/p'
}
# within MEAN SHARE MAX_MEAN MAX_SHARE: 0 when both are within
within() {
    awk -v m="$1" -v s="$2" -v mm="$3" -v ms="$4" 'BEGIN { exit !(m <= mm && s <= ms) }'
}

# tolerances (docs/distributed.md): per-sample stages, and halos
sample_mean=2.5e-3 sample_share=12
halo_mean=2.0e-3 halo_share=10

pv plain-1 1
for scene in boundary-silhouette tone distance; do
    pv "$scene-1" 1 --scene "$scenes/$scene.json" || continue
    pv "$scene-2" 2 --scene "$scenes/$scene.json" || continue
    set -- $(metrics "$scene-1" "$scene-2")
    effect=$(metrics plain-1 "$scene-1" | cut -d' ' -f1)
    echo "$scene: 2 ranks against 1: mean abs $1, $2 % of pixels over 1/255; the stages change the image by $effect"
    within "$1" "$2" $sample_mean $sample_share ||
        fail "$scene: 2 ranks differ from 1 by mean abs $1, $2 % over 1/255 (tolerance $sample_mean, $sample_share %)"
    awk -v e="$effect" -v m="$1" 'BEGIN { exit !(e >= 4 * m) }' ||
        fail "$scene: the stages change the image by $effect, less than 4x the 2-rank error $1"
done

# control: each rank's distance cue in its own brick's space must fail the tolerance
HALO_PARAVIEW_LOCAL=1 pv distance-local-2 2 --scene "$scenes/distance.json" && {
    set -- $(metrics distance-1 distance-local-2)
    echo "control, distance in each brick's own space: mean abs $1, $2 % over 1/255"
    within "$1" "$2" $sample_mean $sample_share && fail "control: the brick-space distance cue passed the tolerance"
}

# volumetric halos: seeds combined over the ranks, and the naive halos (a control)
pv default-1 1 --scene "$scenes/default.json"
pv default-2 2 --scene "$scenes/default.json"
pv default-naive-2 2 --scene "$scenes/default.json" --exchange 0
set -- $(metrics default-1 default-2)
echo "halos, seeds combined over the ranks: 2 ranks against 1: mean abs $1, $2 % over 1/255"
within "$1" "$2" $halo_mean $halo_share ||
    fail "halos: 2 ranks differ from 1 by mean abs $1, $2 % over 1/255 (tolerance $halo_mean, $halo_share %)"
set -- $(metrics default-1 default-naive-2)
echo "control, each rank's own seeds: mean abs $1, $2 % over 1/255"
within "$1" "$2" $halo_mean $halo_share && fail "control: the naive halos passed the halo tolerance"

# outlines need the composited image: refused on 2 ranks, with the reason
mpirun --oversubscribe -np 2 pvbatch "$HALO_PVBATCH_SCRIPT" --plugin "$HALO_PARAVIEW_PLUGIN" --view "$tmp/volume" \
    --scene "$scenes/outline-depth.json" -o "$tmp/outline.png" >"$tmp/outline.log" 2>&1
grep -q "finished image (outlines)" "$tmp/outline.log" ||
    { fail "outlines on 2 ranks: no diagnostic"; sed 's/^/    /' "$tmp/outline.log" | head -20 >&2; }

test $failures -eq 0 || { echo "$failures failure(s)" >&2; exit 1; }
echo "PASS: ParaView on 1 and 2 ranks"
