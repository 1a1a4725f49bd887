#!/bin/sh
# The line conformance rows: GPU against the C emulation on controlled strips and
# fragments, degenerate inputs (a line pointing at the eye, zero-length segments,
# coincident vertices, a strip across the near plane) finite and equal.
. "${srcdir:-.}/tests/tools/halo-lines/common.sh"
run_lines --conform -v
status=$?
cat "$tmp/out"
for row in line_strip line_strip@degenerate line_halo@linear line_halo@smooth line_halo@step lines@near_plane; do
    if ! grep -q "^$row .* 0 .* PASS$" "$tmp/out"; then
        echo "FAIL: row $row did not pass with no non-finite values" >&2
        exit 1
    fi
done
test "$status" -eq 0 || { echo "FAIL: halo-lines --conform exited $status" >&2; exit 1; }
exit 0
