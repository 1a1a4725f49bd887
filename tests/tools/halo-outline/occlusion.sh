#!/bin/sh
# The three occlusion styles of outlines behind an opaque shell (Svakhine et al. 2009,
# Fig. 7) give three different images: hidden, dashed, forced to the front; and the
# outline scene differs from the same rendering without outlines (lambda 0).
. "$srcdir/tests/tools/halo-outline/common.sh"
for style in hidden dashed front; do
    outline "outline-occluded-$style" --image importance
done
for a in hidden dashed front; do
    for b in hidden dashed front; do
        test "$a" \< "$b" || continue
        if cmp -s "$tmp/outline-occluded-$a.png" "$tmp/outline-occluded-$b.png"; then
            echo "FAIL: occlusion styles $a and $b give the same importance image" >&2
            exit 1
        fi
    done
done
sed 's/"lambda": 4/"lambda": 0/' "$scenes/outline-depth.json" >"$tmp/no-outline.json"
cp "$scenes/outline-depth.json" "$tmp/with-outline.json"
for name in no-outline with-outline; do
    "$HALO_OUTLINE" --scene "$tmp/$name.json" --size 48 --volume-size 32 -o "$tmp/$name.png" >/dev/null 2>&1 || {
        echo "FAIL: halo-outline $name" >&2
        exit 1
    }
done
if cmp -s "$tmp/no-outline.png" "$tmp/with-outline.png"; then
    echo "FAIL: lambda 4 draws no outline" >&2
    exit 1
fi
exit 0
