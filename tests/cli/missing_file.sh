#!/bin/sh
# A file that does not exist is an I/O failure: exit 2, named on stderr.
. "$srcdir/tests/cli/common.sh"

run 2 "$HALO_VALIDATE" link --scene "$tmp/missing.json" --host "$data/hosts/minimal.frag"
expect_stderr "missing\.json(:[0-9]+:[0-9]+)?: error:"
expect_no_stdout

run 2 "$HALO_VALIDATE" link --scene "$data/scenes/good.json" --host "$tmp/missing.frag"
expect_stderr "missing\.frag(:[0-9]+:[0-9]+)?: error:"

run 2 "$HALO_VALIDATE" check "$tmp/missing.glsl"
expect_stderr "missing\.glsl(:[0-9]+:[0-9]+)?: error:"

run 2 "$HALO_VALIDATE" check "$tmp/missing.frag"
expect_stderr "missing\.frag(:[0-9]+:[0-9]+)?: error:"

run 2 "$HALO_VALIDATE" link --module "$tmp/missing_module.glsl" --scene "$data/scenes/good.json" \
    --host "$data/hosts/minimal.frag"
expect_stderr "missing_module\.glsl(:[0-9]+:[0-9]+)?: error:"

# An output file that cannot be written.
run 2 "$HALO_VALIDATE" link --scene "$data/scenes/good.json" --host "$data/hosts/minimal.frag" \
    -o "$tmp/no/such/dir/out.frag"
expect_stderr "out\.frag(:[0-9]+:[0-9]+)?: error:"
finish
