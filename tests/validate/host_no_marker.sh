#!/bin/sh
# A host without '#pragma halo declarations': exit 1, reported at the host's file:line.
. "$srcdir/tests/validate/common.sh"

run 1 "$HALO_VALIDATE" link --scene "$data/scenes/good.json" --host "$data/hosts/no_marker.frag"
expect_stderr "no_marker\.frag:1:[0-9]+: error:"
expect_no_stdout
finish
