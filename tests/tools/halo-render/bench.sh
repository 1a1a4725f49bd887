#!/bin/sh
# halo-validate bench (docs/performance.md) on a tiny image and volume: the sweep writes
# its table, the approximation wide's error on the image and on the halo field, CSV (every axis, the halo image resolutions included, no non-finite
# image, a bytes-per-voxel memory column on every row, the skips row's image equal to
# the M = 4 row's) and plot, and verifies the --max-error choice; --table1 and
# --specialize run;
# halo-validate blur writes its variant and truncation rows as CSV. The times are not
# checked (speed goals live in the benchmark's output, not in make check).
. "$srcdir/tests/tools/halo-render/common.sh"
HALO_VALIDATE=${HALO_VALIDATE:-${top_builddir:-.}/validate/halo-validate}
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}

run 0 "$HALO_VALIDATE" bench --size 16 --volume-size 16 --repeat 1 --csv "$tmp/bench.csv" \
    --plot "$tmp/bench.png" --max-error 1 --memory-size 40
expect_stdout "^axis +host +M +N +bits +res +step"
expect_stdout "^# B/vox: peak resident bytes per voxel of halo-render --host slice at 40\\^3"
# the skips (issue 16, item 1) are exact: the skips row renders the M = 4 row's image
expect_stdout "^# skips: .*max abs between the two images 0 "
expect_stdout "budget: max error 1: .*verified"
# the approximation wide's error on the halo field itself, not only on one image (issue
# 26): measured at 0.31, halos 8..22 % weaker; the line must exist and show a real error
expect_stdout "^# wide: on the halo field itself .*max abs 0\\.[1-9]"
if grep -q NONFINITE "$tmp/out"; then
    fail "a configuration rendered a non-finite value"
fi
test -s "$tmp/bench.gp" || fail "no gnuplot script next to the plot"
if command -v gnuplot >/dev/null 2>&1; then
    expect_png "$tmp/bench.png"
fi
if test -s "$tmp/bench.csv"; then
    rows=$(($(wc -l <"$tmp/bench.csv") - 1))
    test "$rows" -ge 30 || fail "the CSV has $rows configurations, expected the whole sweep (>= 30)"
    for axis in reference M N precision gradient resolution step slab combined "no halos"; do
        grep -q "^$axis," "$tmp/bench.csv" || fail "no '$axis' row in the CSV"
    done
    for res in full 1/2 1/4; do
        grep -q "^resolution,slice,1,4,4,32,0.5,$res,\|^M,slice,1,4,4,32,0.5,$res," "$tmp/bench.csv" ||
            fail "no M = 4 row at halo resolution $res in the CSV"
    done
    # the memory column: a number on every row (halo-render ran for each gradient format)
    awk -F, 'NR > 1 && $22 !~ /^-?[0-9]+\.[0-9]$/ { bad = 1 } END { exit bad }' "$tmp/bench.csv" ||
        fail "a row has no bytes per voxel"
    # every halo row has an error against the reference, finite and in [0, 1]
    awk -F, 'NR > 1 && $3 == 1 && !($14 >= 0 && $14 <= 1) { bad = 1 } END { exit bad }' "$tmp/bench.csv" ||
        fail "a halo row's max_abs is not in [0, 1]"
else
    fail "no CSV written"
fi

run 0 "$HALO_VALIDATE" bench --table1 --size 16 --volume-size 16 --repeat 1
expect_stdout "^halo1/2 +slice +4 "
expect_stdout "^# target: .*(MET|NOT MET)"
# host contract 3: the one-draw ray caster's rows (1 host draw) and the goal line
expect_stdout "^one-draw +ray +4 +1 "
# the image passes' fetches a pixel, counted (halo_gl_desc.count_fetches): a number, not nan
expect_stdout "^row +host +M +draws +passes +fetch/px +MiB "
expect_stdout "^one-draw +ray +4 +1 +[0-9]+ +[0-9]*[1-9][0-9]*\\.[0-9] "
expect_stdout "^# goal \\(issue 25\\): .*(MET|NOT MET)"
run 0 "$HALO_VALIDATE" bench --specialize --size 16 --volume-size 16 --repeat 1
expect_stdout "all_live"

run 0 "$HALO_VALIDATE" blur --size 32 --kernels 5,9 --repeat 1 --csv "$tmp/blur.csv"
expect_stdout "^truncation: "
if test -s "$tmp/blur.csv"; then
    test "$(grep -c '^variants,' "$tmp/blur.csv")" -eq 10 || fail "blur CSV: expected 10 variant rows"
    test "$(grep -c '^truncation,' "$tmp/blur.csv")" -eq 6 || fail "blur CSV: expected 6 truncation rows"
else
    fail "halo-validate blur wrote no CSV"
fi

# usage errors
run 2 "$HALO_VALIDATE" bench --size 0
run 2 "$HALO_VALIDATE" bench --repeat nan
run 2 "$HALO_VALIDATE" bench --memory-size 32
run 2 "$HALO_VALIDATE" blur --kernels 4
finish
