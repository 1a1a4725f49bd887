#!/bin/sh
# A module with a malformed parameter line (line 5): exit 1, file:line:col on stderr.
. "$srcdir/tests/validate/common.sh"

module="$data/modules/bad_param.glsl"
run 1 "$HALO_VALIDATE" check "$module"
expect_stderr "bad_param\.glsl:5:[0-9]+: error:"

run 1 "$HALO_VALIDATE" link --module "$module" --scene "$data/scenes/good.json" --host "$data/hosts/minimal.frag"
expect_stderr "bad_param\.glsl:5:[0-9]+: error:"
expect_no_stdout

# A good file checked alongside still gets its own verdict; the worst status wins.
run 1 "$HALO_VALIDATE" check "$srcdir/glsl/sample/boundary.glsl" "$module"
expect_stderr "bad_param\.glsl:5:[0-9]+: error:"
grep -q 'boundary\.glsl: ok' "$tmp/out" || fail "the good module is not reported ok"
finish
