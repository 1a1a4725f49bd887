#!/bin/sh
# halo-view reloads its scene file when it changes on disk: an edited scene is rendered
# (the same image as halo-render's of the edited file); a broken one is reported (on
# stderr, in the window title, and on stdout as "the window shows: ...") while the
# last good scene stays on screen and the viewer keeps running.
. "$srcdir/tests/tools/halo-view/common.sh"
probe_display
limits="--max-abs 0.0009765625 --max-share 0.005"
opts="--size 96x72 --volume-size 40"

# wait_for FILE: up to 90 s for the viewer to write it
wait_for() {
    n=0
    while test ! -f "$1"; do
        n=$((n + 1))
        if test "$n" -gt 450 || ! kill -0 "$viewer" 2>/dev/null; then
            fail "$1 was not written"
            return 1
        fi
        sleep 0.2
    done
}

cp "$scenes/halo-emissive.json" "$tmp/s.json"
# S, wait for a reload, S, wait, S; then quit
xrun "$HALO_VIEW" --scene "$tmp/s.json" $opts --save-prefix "$tmp/shot-" \
    --keys "s @reload s @reload s" --quit >"$tmp/view.out" 2>"$tmp/view.err" &
viewer=$!
wait_for "$tmp/shot-001.png"
# an edit: another background (written aside and renamed, as editors do)
sed 's/"background": \[1, 1, 1\]/"background": [0.3, 0.4, 0.5]/' "$tmp/s.json" >"$tmp/edit.json"
grep -q '0.3, 0.4, 0.5' "$tmp/edit.json" || fail "the test's edit did not apply"
mv "$tmp/edit.json" "$tmp/s.json"
wait_for "$tmp/shot-002.png"
cp "$tmp/s.json" "$tmp/edited.json"
# a broken scene: a value out of range
sed 's/"delta": 0.9/"delta": 7/' "$tmp/s.json" >"$tmp/broken.json"
mv "$tmp/broken.json" "$tmp/s.json"
wait "$viewer"
status=$?
sed 's/^/    stdout: /' "$tmp/view.out"
sed 's/^/    stderr: /' "$tmp/view.err"
test "$status" -eq 0 || fail "halo-view exited $status after a broken scene, expected 0"
test -s "$tmp/shot-003.png" || fail "no screenshot after the broken scene: did the viewer stop?"

test "$(grep -c "s.json changed: reloading" "$tmp/view.out")" -eq 2 || fail "expected two reloads"
grep -q "stages\[.*\]\.halo_generate\.delta.*above the maximum" "$tmp/view.err" || fail "no diagnostic for delta 7"
grep -q "the window shows: .*s.json.*delta" "$tmp/view.out" || fail "the window does not show the diagnostic"
grep -q "keeping the last good scene" "$tmp/view.err" || fail "no 'keeping the last good scene'"
test "$(grep -c "above the maximum" "$tmp/view.err")" -eq 1 || fail "the reload's error is not on stderr once"

# A broken scene at start: the viewer exits 1 and says each error once.
cp "$tmp/s.json" "$tmp/broken-start.json"
run 1 xrun "$HALO_VIEW" --scene "$tmp/broken-start.json" --size 16x16 --volume-size 8 --frames 1 --quit
test "$(grep -c "above the maximum" "$tmp/err")" -eq 1 || fail "a scene error at start is printed $(grep -c "above the maximum" "$tmp/err") times"

different "$tmp/shot-001.png" "$tmp/shot-002.png"
same "$tmp/shot-002.png" "$tmp/shot-003.png"
run 0 "$HALO_RENDER" --quiet --scene "$tmp/edited.json" $opts -o "$tmp/edited-render.png"
same "$tmp/shot-002.png" "$tmp/edited-render.png" $limits
finish
