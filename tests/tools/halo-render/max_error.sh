#!/bin/sh
# --max-error E: the error budget (validate/bench_budget.c) picks the cheapest
# configuration of the scene whose measured error against the exact reference is <= E,
# halo-render applies it and renders. Small images: each run sweeps about 30
# configurations (a few seconds on llvmpipe).
. "$srcdir/tests/tools/halo-render/common.sh"

# budget_error: the verified error of the choice, from the "budget:" line on stdout.
budget_error() {
    sed -n 's/.*, \([0-9.e+-]*\) (verified: within).*/\1/p' "$tmp/out"
}

# E = 0: only the exact reference (or a configuration that renders the same image) fits.
run 0 "$HALO_RENDER" --quiet --max-error 0 --size 32x32 --volume-size 24 -o "$tmp/exact.exr"
expect_stdout "budget: max error 0: (slice|slab), M = [0-9]+, N = [0-9]+, [0-9]+-bit halo images at (full|1/2|1/4) resolution, step"
expect_stdout "verified: within"
expect_stdout "wrote .*exact\.exr"
e=$(budget_error)
if test -z "$e" || ! awk -v e="$e" 'BEGIN { exit !(e + 0 <= 0) }'; then
    fail "--max-error 0: the chosen configuration's error is '$e'"
fi

# E = 0.6: a cheaper configuration, its measured error within E; halo-render's own render
# of it is within E of its render of the exact reference.
run 0 "$HALO_RENDER" --quiet --max-error 0.6 --size 32x32 --volume-size 24 -o "$tmp/budget.exr"
expect_stdout "verified: within"
expect_stdout "wrote .*budget\.exr"
e=$(budget_error)
if test -z "$e" || ! awk -v e="$e" 'BEGIN { exit !(e + 0 <= 0.6) }'; then
    fail "--max-error 0.6: the chosen configuration's error is '$e'"
fi
if test -x "${HALO_IMAGE_COMPARE:-}" && test -s "$tmp/exact.exr" && test -s "$tmp/budget.exr"; then
    if ! "$HALO_IMAGE_COMPARE" "$tmp/exact.exr" "$tmp/budget.exr" --max-abs 0.600001 --max-share 1 >"$tmp/cmp" 2>&1; then
        fail "the --max-error 0.6 image is not within 0.6 of the exact one: $(cat "$tmp/cmp")"
    fi
fi

# E = 1 (colours are in [0,1]): everything fits; the cheapest is a slab configuration on
# llvmpipe (fewest draws), and the image is the chosen host's.
run 0 "$HALO_RENDER" --quiet --max-error 1 --size 32x32 --volume-size 24 -o "$tmp/cheap.png"
expect_png "$tmp/cheap.png"
host=$(sed -n 's/.*budget: max error 1: \(slice\|slab\),.*/\1/p' "$tmp/out")
expect_stdout "wrote .*cheap\.png \(32x32, $host host"

# Usage errors.
run 2 "$HALO_RENDER" --max-error -1 -o "$tmp/x.png"
run 2 "$HALO_RENDER" --max-error nan -o "$tmp/x.png"
run 2 "$HALO_RENDER" --max-error 0.1 --no-halos -o "$tmp/x.png"
expect_stderr "not with --no-halos"
run 2 "$HALO_RENDER" --max-error 0.1 --host slab -o "$tmp/x.png"
expect_stderr "not with --host"
run 2 "$HALO_RENDER" --max-error 0.1 --halo-scale 2 -o "$tmp/x.png"
expect_stderr "not with --halo-scale"

# --halo-scale: halo images at 1/2 and 1/4 render; other scales are refused.
for s in 2 4; do
    run 0 "$HALO_RENDER" --quiet --halo-scale $s --size 32x32 --volume-size 24 -o "$tmp/scale$s.png"
    expect_png "$tmp/scale$s.png"
done
run 2 "$HALO_RENDER" --halo-scale 3 -o "$tmp/x.png"
expect_stderr "not 1, 2 or 4"
run 2 "$HALO_RENDER" --halo-scale 8 -o "$tmp/x.png"
run 2 "$HALO_RENDER" --max-error 0.1 --scene "$scenes/feature-halos.json" --size 32x32 --volume-size 24 -o "$tmp/x.png"
expect_stderr "feature_halo"
finish
