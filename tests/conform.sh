#!/bin/sh
# Conformance at a small size (25, the least conform accepts: its hard cases need
# 25x25 pixels): every stage rendered headless (OSMesa) matches its C
# emulation within the stated tolerance (halo-validate conform exits 0).
if test ! -x "${HALO_VALIDATE:-}"; then
    echo "broken setup: HALO_VALIDATE missing" >&2
    exit 99
fi
"$HALO_VALIDATE" conform --size 25
status=$?
case $status in
0) exit 0 ;;
77) echo "no headless OpenGL context: skipping" >&2; exit 77 ;;
*) echo "FAIL: halo-validate conform --size 25 exited $status" >&2; exit 1 ;;
esac
