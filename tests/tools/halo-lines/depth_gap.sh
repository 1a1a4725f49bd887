#!/bin/sh
# Two crossing lines at a series of depth gaps: the back line is interrupted by the
# front line's halo only where the gap exceeds d_max (Everts et al. 2009).
. "${srcdir:-.}/tests/tools/halo-lines/common.sh"
run_lines --conform --row lines@depth_gap -v
status=$?
cat "$tmp/out"
if test "$status" -ne 0 || ! grep -q "^lines@depth_gap .* PASS$" "$tmp/out"; then
    echo "FAIL: lines@depth_gap (exit $status)" >&2
    exit 1
fi

if grep -q "(expected" "$tmp/out" && grep -E -q "visible \(expected interrupted\)|interrupted \(expected visible\)" "$tmp/out"; then
    echo "FAIL: a gap on the wrong side of d_max" >&2
    exit 1
fi
exit 0
