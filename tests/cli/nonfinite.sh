#!/bin/sh
# JSON has no NaN, and 1e999 is no finite double: both scenes are rejected (exit 1).
. "$srcdir/tests/cli/common.sh"

run 1 "$HALO_VALIDATE" link --scene "$data/scenes/nan.json" --host "$data/hosts/minimal.frag"
expect_stderr "nan\.json(:[0-9]+:[0-9]+)?: error:"
expect_no_stdout
run 1 "$HALO_VALIDATE" link --scene "$data/scenes/huge.json" --host "$data/hosts/minimal.frag"
expect_stderr "huge\.json(:[0-9]+:[0-9]+)?: error:"
expect_no_stdout
finish
