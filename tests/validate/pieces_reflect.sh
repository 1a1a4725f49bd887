#!/bin/sh
# Issue 26: the reflection lists every uniform libhalo needs set, the derived view and
# depth's camera uniforms and the segment uniforms too (before: "host_uniforms": [], and a
# host that draws itself got a silently wrong image), each with who sets it.
. "$srcdir/tests/validate/common.sh"

# expect_uniform NAME SET_BY: the last reflection lists NAME, set by SET_BY
expect_uniform() {
    grep -A4 "\"name\": \"$1\"" "$tmp/out" | grep -q "\"set_by\": \"$2\"" ||
        fail "the reflection does not list $1 (set by $2) among host_uniforms"
}
run 0 "$HALO_VALIDATE" link --pieces --scene "$data/scenes/good.json" --sample volume=in_volume --reflect
for u in halo_camera_eye halo_camera_plane halo_camera_depth_range; do expect_uniform $u halo_gl_set_camera; done
if grep -q '"halo_segment_bounds"' "$tmp/out"; then fail "a program drawn once lists the segment uniforms"; fi
run 0 "$HALO_VALIDATE" link --pieces --scene "$data/scenes/halo_pieces.json" --segmented --sample volume=in_volume \
    --reflect
expect_uniform halo_host_screen_right host
for u in halo_camera_eye halo_camera_plane halo_camera_depth_range; do expect_uniform $u halo_gl_set_camera; done
for u in halo_segment_state halo_segment_bounds halo_segment_flags; do expect_uniform $u halo_gl_frame_draw; done
finish
