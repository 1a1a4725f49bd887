#!/bin/sh
# A malformed polyline file: every error reported at its file:line, exit status 1.
. "${srcdir:-.}/tests/tools/halo-lines/common.sh"
bad="$tmp/bad.txt"
cat >"$bad" <<'DATA'
halo-polylines 1
# a good line
line
0 0 0
1 0 0
line
0 1
2 x 3
nan 0 0
line
5 5 5
wobble
DATA
run_lines --lines "$bad" --size 32x32 -o "$tmp/bad.png"
status=$?
cat "$tmp/out"
test "$status" -eq 1 || { echo "FAIL: exit status $status, expected 1" >&2; exit 1; }
for where in "bad.txt:7:1: error" "bad.txt:8:3: error" "bad.txt:9:1: error" "bad.txt:10:1: error" \
    "bad.txt:12:1: error"; do
    grep -q "$where" "$tmp/out" || { echo "FAIL: no diagnostic at $where" >&2; exit 1; }
done
test ! -e "$tmp/bad.png" || { echo "FAIL: an image was written" >&2; exit 1; }
# One problem, one error: a bad point (a word that is no number, or the wrong number of
# coordinates, even with a bad word) is not also a polyline "with too few points".
printf 'halo-polylines 1\nline\n0 0 0\n1 x 0\nline\n1 y\n3 3 3\nline\n0 0 0\n' >"$tmp/one.txt"
run_lines --lines "$tmp/one.txt" --size 16x16 -o "$tmp/one.png"
test $? -eq 1 || { cat "$tmp/out" >&2; echo "FAIL: one.txt should exit 1" >&2; exit 1; }
errors=$(grep -c ": error: " "$tmp/out")
test "$errors" -eq 3 || { cat "$tmp/out" >&2; echo "FAIL: $errors errors for the 3 problems of one.txt" >&2; exit 1; }
for where in "one.txt:4:3: error" "one.txt:6:1: error" "one.txt:8:1: error"; do
    grep -q "$where" "$tmp/out" || { echo "FAIL: no diagnostic at $where" >&2; exit 1; }
done
# a file without the header, and an empty file
printf '0 0 0\n1 1 1\n' >"$tmp/noheader.txt"
run_lines --lines "$tmp/noheader.txt" --size 32x32 -o "$tmp/x.png"
test $? -eq 1 && grep -q "noheader.txt:1:1: error" "$tmp/out" || { cat "$tmp/out" >&2; echo "FAIL: no header" >&2; exit 1; }
: >"$tmp/empty.txt"
run_lines --lines "$tmp/empty.txt" --size 32x32 -o "$tmp/x.png"
test $? -eq 1 || { cat "$tmp/out" >&2; echo "FAIL: empty file" >&2; exit 1; }
run_lines --lines "$tmp/missing.txt" --size 32x32 -o "$tmp/x.png"
test $? -eq 2 || { cat "$tmp/out" >&2; echo "FAIL: a missing file should exit 2" >&2; exit 1; }
exit 0
