#!/bin/sh
# A scene that is not JSON (a stray comma on line 3): exit 1, scene:line:col.
. "$srcdir/tests/validate/common.sh"

run 1 "$HALO_VALIDATE" link --scene "$data/scenes/bad_json.json" --host "$data/hosts/minimal.frag"
expect_stderr "bad_json\.json:3:[0-9]+: error:"
expect_no_stdout
# Not even text.
printf '\000\001\002' >"$tmp/binary.json"
run 1 "$HALO_VALIDATE" link --scene "$tmp/binary.json" --host "$data/hosts/minimal.frag"
expect_error_in binary.json
# Empty.
: >"$tmp/empty.json"
run 1 "$HALO_VALIDATE" link --scene "$tmp/empty.json" --host "$data/hosts/minimal.frag"
expect_error_in empty.json
finish
