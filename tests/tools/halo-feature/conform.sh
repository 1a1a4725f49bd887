#!/bin/sh
# Feature halos: the GPU halo buffer against its emulation (splat rows, hard cases:
# constant volume, single voxel, features at the volume's edge), the emulation against
# the exact reference, and the per-sample stage against its emulation.
if test ! -x "${HALO_FEATURE:-}"; then
    echo "broken setup: HALO_FEATURE missing" >&2
    exit 99
fi
"$HALO_FEATURE" conform
status=$?
case $status in
0) exit 0 ;;
77) echo "no headless OpenGL context: skipping" >&2; exit 77 ;;
*) echo "FAIL: halo-feature conform exited $status" >&2; exit 1 ;;
esac
