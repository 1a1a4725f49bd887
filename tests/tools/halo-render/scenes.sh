#!/bin/sh
# Every volume scene in examples/scenes renders at 96x96 (the built-in volume at 48^3,
# to stay fast) and writes a valid PNG, the feature-halo and outline scenes included.
# (lines-*.json are halo-lines' scenes.)
. "$srcdir/tests/tools/halo-render/common.sh"

count=0
for scene in "$scenes"/*.json; do
    name=$(basename "$scene" .json)
    case $name in lines-*) continue ;; esac
    run 0 "$HALO_RENDER" --quiet --scene "$scene" --size 96x96 --volume-size 48 -o "$tmp/$name.png"
    expect_png "$tmp/$name.png"
    expect_stdout "wrote .*$name\.png"
    # feature halos through the ray caster with their halo buffer; outlines through the
    # slice host and their post passes
    case $name in
    feature-halos) expect_stdout "raycast host, .*feature_halo" ;;
    outline-*) grep -q "outlines" "$tmp/out" && expect_stdout "image final of the post passes" ;;
    esac
    count=$((count + 1))
done
if test "$count" -lt 12; then
    fail "only $count scenes found in $scenes"
fi
finish
