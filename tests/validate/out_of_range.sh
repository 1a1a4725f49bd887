#!/bin/sh
# A parameter below its minimum: exit 1, the JSON path of the value named.
. "$srcdir/tests/validate/common.sh"

run 1 "$HALO_VALIDATE" link --scene "$data/scenes/out_of_range.json" --host "$data/hosts/minimal.frag"
expect_error_in out_of_range.json
expect_stderr "stages\[1\]\.boundary\.k_gs"
expect_no_stdout
finish
