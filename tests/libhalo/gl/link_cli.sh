#!/bin/sh
# halo-validate link and host contract 2: a halo scene in the segmented ray caster links
# and reflects its ray-state output; in a single-pass ray caster it is refused with
# HOST_SINGLE_PASS at the host's marker line, naming the stage; per-sample stages still
# link there (they need no passes).
. "$srcdir/tests/validate/common.sh"

expect_stdout() {
    grep -E -q -e "$1" "$tmp/out" || fail "stdout does not match /$1/"
}

run 0 "$HALO_VALIDATE" link --scene "$srcdir/examples/scenes/default.json" \
    --host "$srcdir/examples/hosts/raycast.frag" --reflect
expect_stdout '"segment_state_location": [0-9]+'

run 1 "$HALO_VALIDATE" link --scene "$srcdir/examples/scenes/default.json" --host "$data/hosts/single_pass.frag"
expect_stderr "single_pass\.frag:4:1: error: the stages halo_generate run image passes between slices"
expect_no_stdout

run 0 "$HALO_VALIDATE" link --scene "$srcdir/examples/scenes/boundary-silhouette.json" \
    --host "$data/hosts/single_pass.frag" --reflect
expect_stdout '"segment_state_location": null'
finish
