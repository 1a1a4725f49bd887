#!/bin/sh
# A scene naming a stage that no module provides: exit 1, the scene file named.
. "$srcdir/tests/validate/common.sh"

run 1 "$HALO_VALIDATE" link --scene "$data/scenes/unknown_stage.json" --host "$data/hosts/minimal.frag"
expect_error_in unknown_stage.json
expect_stderr "stages\[1\]"
expect_stderr "no_such_stage"
expect_no_stdout
finish
