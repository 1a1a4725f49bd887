#!/bin/sh
# Issue 26: every rule the host contract states is a diagnostic. A ray loop with
# halo_segment_begin but no halo_segment_end (or the reverse) linked with exit 0; the
# reserved-name message listed only contract 1's names.
. "$srcdir/tests/validate/common.sh"

host="$srcdir/examples/hosts/raycast.frag"
scene="$data/scenes/good.json"
run 0 "$HALO_VALIDATE" link --scene "$scene" --host "$host" -o "$tmp/ok.frag"
main_line=$(grep -n '^void main' "$host" | cut -d: -f1)
sed '/halo_segment_end(/d' "$host" >"$tmp/no_end.frag"
run 1 "$HALO_VALIDATE" link --scene "$scene" --host "$tmp/no_end.frag" -o "$tmp/x.frag"
expect_stderr "no_end\.frag:$main_line:6: error: the host never calls halo_segment_end"
sed 's|^\( *\)\(halo_segment_end(.*\)$|\1// \2|' "$host" >"$tmp/end_commented.frag"
run 1 "$HALO_VALIDATE" link --scene "$scene" --host "$tmp/end_commented.frag" -o "$tmp/x.frag"
expect_stderr "end_commented\.frag:[0-9]+:[0-9]+: error: this call of halo_segment_end is commented out"

# a discard that depends on the segment (after halo_segment_begin) in a program drawn in
# segments (volumetric halos) is refused at the discard; one before it (a ray that misses
# the volume) is accepted
halos="$srcdir/examples/scenes/default.json"
end_line=$(grep -n 'halo_segment_end(' "$host" | head -1 | cut -d: -f1)
sed 's|^\( *\)\(halo_segment_end(.*\)$|\1if (accumulated.a > 2.0) discard;\n\1\2|' "$host" >"$tmp/discard.frag"
run 1 "$HALO_VALIDATE" link --scene "$halos" --host "$tmp/discard.frag" -o "$tmp/x.frag"
expect_stderr "discard\.frag:$end_line:[0-9]+: error: a discard after halo_segment_begin"
sed 's|^\( *\)\(halo_segment_begin(.*\)$|\1if (t_enter > 1e30) discard;\n\1\2|' "$host" >"$tmp/discard_before.frag"
run 0 "$HALO_VALIDATE" link --scene "$halos" --host "$tmp/discard_before.frag" -o "$tmp/x.frag"

printf '#version 330 core\n#pragma halo declarations\nuniform float halo_mine;\nout vec4 c;\nvoid main() { c = vec4(halo_mine); }\n' \
    >"$tmp/reserved.frag"
run 1 "$HALO_VALIDATE" link --host "$tmp/reserved.frag" -o "$tmp/x.frag"
expect_stderr "reserved\.frag:3:15: error: 'halo_mine' is reserved: .*halo_segment_begin, halo_segment_end, halo_view_at, halo_depth_at, halo_gradient_at and HALO_RAY_MAY_END\)"
finish
