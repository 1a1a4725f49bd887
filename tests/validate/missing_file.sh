#!/bin/sh
# A file that does not exist is an I/O failure: exit 2, named on stderr.
. "$srcdir/tests/validate/common.sh"

run 2 "$HALO_VALIDATE" link --scene "$tmp/missing.json" --host "$data/hosts/minimal.frag"
expect_error_in missing.json
expect_no_stdout

run 2 "$HALO_VALIDATE" link --scene "$data/scenes/good.json" --host "$tmp/missing.frag"
expect_error_in missing.frag

run 2 "$HALO_VALIDATE" check "$tmp/missing.glsl"
expect_error_in missing.glsl

run 2 "$HALO_VALIDATE" check "$tmp/missing.frag"
expect_error_in missing.frag

run 2 "$HALO_VALIDATE" link --module "$tmp/missing_module.glsl" --scene "$data/scenes/good.json" \
    --host "$data/hosts/minimal.frag"
expect_error_in missing_module.glsl

# An output file that cannot be written.
run 2 "$HALO_VALIDATE" link --scene "$data/scenes/good.json" --host "$data/hosts/minimal.frag" \
    -o "$tmp/no/such/dir/out.frag"
expect_error_in out.frag
finish
