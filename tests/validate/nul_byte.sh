#!/bin/sh
# A NUL byte in a host or a module is an error in the input: exit 1 with the file's
# line and column, never exit 2 (that is for files that cannot be read) and never a
# module silently cut short at the NUL.
. "$srcdir/tests/validate/common.sh"

printf '#version 330 core\n#pragma halo declarations\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n// \000 tail\n' \
    >"$tmp/nul.frag"
printf '#pragma halo module nul_module\n#pragma halo hook sample\nvoid apply(inout halo_sample s) {}\n  \000\n' \
    >"$tmp/nul.glsl"

run 1 "$HALO_VALIDATE" check --target 330 "$tmp/nul.frag"
expect_stderr "nul\.frag:5:4: error: .*NUL"
run 1 "$HALO_VALIDATE" link --host "$tmp/nul.frag"
expect_stderr "nul\.frag:5:4: error: .*NUL"
expect_no_stdout
run 1 "$HALO_VALIDATE" check --target 330 "$tmp/nul.glsl"
expect_stderr "nul\.glsl:4:3: error: .*NUL"
run 1 "$HALO_VALIDATE" link --host "$data/hosts/minimal.frag" --module "$tmp/nul.glsl"
expect_stderr "nul\.glsl:4:3: error: .*NUL"
expect_no_stdout
# a file that cannot be read is still exit 2
run 2 "$HALO_VALIDATE" link --host "$tmp/no-such.frag"
finish
