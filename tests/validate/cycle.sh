#!/bin/sh
# Two user modules that each run 'after' the other, both enabled: exit 1, a cycle
# reported at one of the modules' own lines.
. "$srcdir/tests/validate/common.sh"

run 1 "$HALO_VALIDATE" link --module "$data/modules/cycle_a.glsl" --module "$data/modules/cycle_b.glsl" \
    --scene "$data/scenes/cycle.json" --host "$data/hosts/minimal.frag"
expect_stderr "cycle_[ab]\.glsl:3:[0-9]+: error:"
expect_no_stdout
finish
