#!/bin/sh
# halo-validate link --pieces --composed checks the engine's shader as a host is checked
# (issue 26): without the sample piece, the finish piece or a segment call it is an error
# at the composed file's own line, not exit 0; an error on a line libhalo wrote is at the
# composed file's line, not "line N of the linked shader"; a CRLF file is no "changed"
# declarations piece.
. "$srcdir/tests/validate/common.sh"

template="$data/composer/template.frag"
link="link --pieces --scene $data/scenes/halo_pieces.json --target 150 --segmented
      --sample position=g_dataPos --sample value=scalar --sample color=g_srcColor --sample volume=in_volume[0]"
mkdir -p "$tmp/pieces"
run 0 "$HALO_VALIDATE" $link --pieces-dir "$tmp/pieces"
# compose SED_SCRIPT OUT: the template, edited, with the pieces in its tags
compose() {
    sed "$1" "$template" | awk -v dir="$tmp/pieces" -f "$data/composer/compose.awk" >"$2"
}
compose '' "$tmp/composed.frag"
run 0 "$HALO_VALIDATE" $link --composed "$tmp/composed.frag"
main_line=$(grep -n '^void main' "$tmp/composed.frag" | cut -d: -f1)

# missing SED_SCRIPT NAME CALL: the template without a line is an error at its main
missing() {
    compose "$1" "$tmp/$2.frag"
    run 1 "$HALO_VALIDATE" $link --composed "$tmp/$2.frag"
    expect_stderr "$2\.frag:$main_line:6: error: the composed shader never calls $3"
}
missing '/ENGINE::Sample/d' no_sample halo_apply
missing '/ENGINE::Finish/d' no_finish halo_finish
missing '/halo_segment_end/d' no_end halo_segment_end
missing '/halo_segment_begin/d' no_begin halo_segment_begin

# the engine's colour a vec3: the sample piece's line (libhalo's) is reported at its own line
compose 's/vec4 g_srcColor = vec4(scalar, scalar, scalar, 0.1)/vec3 g_srcColor = vec3(scalar)/' "$tmp/vec3.frag"
run 1 "$HALO_VALIDATE" $link --composed "$tmp/vec3.frag"
line=$(grep -n 'halo_view_at(g_dataPos), halo_depth_at' "$tmp/vec3.frag" | cut -d: -f1)
expect_stderr "vec3\.frag:$line:[0-9]+: error: 'a' : vector swizzle"
if grep -q 'of the linked shader' "$tmp/err"; then fail "an error is reported at a line of the linked shader"; fi

# CRLF line ends: the same shader
sed 's/$/\r/' "$tmp/composed.frag" >"$tmp/crlf.frag"
run 0 "$HALO_VALIDATE" $link --composed "$tmp/crlf.frag"
if grep -q 'not in the composed shader' "$tmp/err"; then fail "a CRLF composed shader is said to lack its piece"; fi

# composed from another link's pieces (the same scene without live parameters): it compiles,
# but the live uniforms the engine sets for this program are not there; an error (before:
# a warning and exit 0)
sed 's/, "live": \["[a-z]*"\]//' "$data/scenes/halo_pieces.json" >"$tmp/constant.json"
mkdir -p "$tmp/stale"
run 0 "$HALO_VALIDATE" $(echo "$link" | sed "s|$data/scenes/halo_pieces.json|$tmp/constant.json|") --pieces-dir "$tmp/stale"
sed "" "$template" | awk -v dir="$tmp/stale" -f "$data/composer/compose.awk" >"$tmp/stale.frag"
run 1 "$HALO_VALIDATE" $link --composed "$tmp/stale.frag"
expect_stderr "stale\.frag: error: the composed shader has no uniform halo_halo_[a-z_]+ \\(halo_[a-z_]+\\.[a-z]+, live in this program\\)"
# the same with the missing uniforms declared in comments only: still an error (before: the
# word "uniform" and the name on one line passed the check)
for name in $(grep -o 'uniform [a-z_]* halo_halo_[a-z_0-9]*' "$tmp/pieces/declarations.glsl" | sed 's/.* //'); do
    printf '// uniform float %s;\n/* uniform float %s; */\n' "$name" "$name"
done >"$tmp/comments.glsl"
test -s "$tmp/comments.glsl" || fail "no live uniform found in the declarations piece"
{ sed -n '1p' "$tmp/stale.frag"; cat "$tmp/comments.glsl"; sed '1d' "$tmp/stale.frag"; } >"$tmp/commented.frag"
run 1 "$HALO_VALIDATE" $link --composed "$tmp/commented.frag"
expect_stderr "commented\.frag: error: the composed shader has no uniform halo_halo_[a-z_]+"
finish
