#!/bin/sh
# JSON has no NaN, and 1e999 is no finite double: both scenes are rejected (exit 1).
. "$srcdir/tests/validate/common.sh"

for scene in nan.json huge.json; do
    run 1 "$HALO_VALIDATE" link --scene "$data/scenes/$scene" --host "$data/hosts/minimal.frag"
    expect_error_in "$scene"
    expect_no_stdout
done
finish
