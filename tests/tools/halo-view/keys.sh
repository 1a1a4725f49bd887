#!/bin/sh
# Keys (injected with --keys) relink the scene: toggle a stage, select parameters from
# the reflection (P walks back from the last: halo_map.profile_exponent .. mode, then
# halo_generate's fold, wide, interval, median, delta, passes) and step them (a bool
# flips, M doubles, delta moves by 1/20 of its range, N by 1), orbit and zoom; the S key saves the image and the scene, and the
# saved scene renders with halo-render to the same image. Tab cycles the scenes of the
# scene's folder.
. "$srcdir/tests/tools/halo-view/common.sh"
probe_display
limits="--max-abs 0.0009765625 --max-share 0.005"
opts="--size 112x84 --volume-size 40"

cp "$scenes/halo-emissive.json" "$tmp/emissive.json"
run 0 xrun "$HALO_VIEW" --scene "$tmp/emissive.json" $opts --save-prefix "$tmp/a-" \
    --keys "s 1 P P P P P P ] P P P ] P P [ [ P ] left up + s" --quit
for msg in "tone_shading disabled" "halo_map.mode = 1" "halo_generate.delta = 0.8\$" "halo_generate.interval = 8" \
    "halo_generate.passes = 5" "wrote $tmp/a-002.png"; do
    grep -q "$msg" "$tmp/out" || fail "stdout lacks '$msg'"
done
for f in a-001.png a-001.json a-002.png a-002.json; do
    test -s "$tmp/$f" || fail "$f was not written"
done
grep -q '"enabled": false' "$tmp/a-002.json" || fail "a-002.json does not disable tone_shading"
grep -q '"interval": 8' "$tmp/a-002.json" || fail "a-002.json lacks interval 8"
different "$tmp/a-001.png" "$tmp/a-002.png"
# each saved scene is the view it was saved with
for k in 001 002; do
    run 0 "$HALO_RENDER" --quiet --scene "$tmp/a-$k.json" $opts -o "$tmp/a-$k-render.png"
    same "$tmp/a-$k.png" "$tmp/a-$k-render.png" $limits
done

# stepping before selecting, and a stage key beyond the scene: reported, nothing breaks
run 0 xrun "$HALO_VIEW" --scene "$scenes/plain.json" $opts --keys "[ ] 7" --screenshot "$tmp/plain.png" --quit
grep -q "no parameter selected" "$tmp/err" || fail "no message for [ before a parameter is selected"
grep -q "no stage 7" "$tmp/err" || fail "no message for a stage key beyond the scene"

# a per-feature parameter of a scene with six features (two groups of four): the
# program holds one group at a time, so [ and ] refuse it with a message instead of
# writing one group back over the scene's six values
printf '%s\n' '{"halo_scene": 1, "stages": [' \
    '  {"outline_feature": {"value_min": [0.5, 0.55, 0.6, 0.65, 0.7, 0.75], "value_max": [1, 1, 1, 1, 1, 1]}},' \
    '  {"outlines": {}}]}' >"$tmp/six.json"
run 0 xrun "$HALO_VIEW" --scene "$tmp/six.json" --size 64x48 --volume-size 24 --save-prefix "$tmp/six-" \
    --keys "p ] s" --quit
grep -q "outline_feature.value_min has a value per feature in 2 groups" "$tmp/err" ||
    fail "no message for a grouped per-feature parameter"
grep -q '0.75' "$tmp/six-001.json" || fail "the saved scene lost the sixth feature's value"

# tab: the next scene of the folder (sorted by name), with its own camera
mkdir "$tmp/folder"
cp "$scenes/plain.json" "$tmp/folder/a.json"
cp "$scenes/tone.json" "$tmp/folder/b.json"
run 0 xrun "$HALO_VIEW" --scene "$tmp/folder/a.json" $opts --keys "left tab" --screenshot "$tmp/tab.png" --quit
grep -q "loaded $tmp/folder/b.json" "$tmp/out" || fail "tab did not load b.json"
run 0 "$HALO_RENDER" --quiet --scene "$tmp/folder/b.json" $opts -o "$tmp/b-render.png"
same "$tmp/tab.png" "$tmp/b-render.png" $limits
run 0 xrun "$HALO_VIEW" --scene "$tmp/folder/a.json" $opts --keys "shift+tab shift+tab" --quit
grep -q "loaded $tmp/folder/b.json" "$tmp/out" || fail "shift+tab did not wrap to b.json"
grep -c "loaded $tmp/folder/a.json" "$tmp/out" | grep -q 2 || fail "shift+tab twice did not come back to a.json"
finish
