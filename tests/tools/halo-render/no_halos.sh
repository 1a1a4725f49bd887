#!/bin/sh
# --no-halos renders the same scene with the halo stages off: a different image, the
# same host, and no halo stage in the stage list.
. "$srcdir/tests/tools/halo-render/common.sh"

for scene in "$scenes/default.json" "$scenes/halo-emissive.json"; do
    name=$(basename "$scene" .json)
    run 0 "$HALO_RENDER" --quiet --scene "$scene" --size 64x64 --volume-size 48 -o "$tmp/$name-halos.png"
    expect_png "$tmp/$name-halos.png"
    expect_stdout "slice host, .*halo_seed, halo_generate, halo_map"
    run 0 "$HALO_RENDER" --quiet --scene "$scene" --size 64x64 --volume-size 48 --no-halos -o "$tmp/$name-plain.png"
    expect_png "$tmp/$name-plain.png"
    expect_stdout "slice host"
    if grep -q "halo_" "$tmp/out"; then
        fail "--no-halos still links a halo stage: $(cat "$tmp/out")"
    fi
    if cmp -s "$tmp/$name-halos.png" "$tmp/$name-plain.png"; then
        fail "$name: --no-halos gives the same image as with halos"
    fi
done

# The built-in default (no --scene) is examples/scenes/default.json.
run 0 "$HALO_RENDER" --quiet --size 64x64 --volume-size 48 -o "$tmp/builtin.png"
if ! cmp -s "$tmp/builtin.png" "$tmp/default-halos.png"; then
    fail "the built-in default scene renders differently from examples/scenes/default.json"
fi

# A scene without halo stages defaults to the ray caster; --no-halos changes nothing.
run 0 "$HALO_RENDER" --quiet --scene "$scenes/tone.json" --size 48x48 --volume-size 32 -o "$tmp/tone.png"
expect_stdout "raycast host"
run 0 "$HALO_RENDER" --scene "$scenes/tone.json" --size 48x48 --volume-size 32 --no-halos -o "$tmp/tone2.png"
expect_stderr "no halo stages"
if ! cmp -s "$tmp/tone.png" "$tmp/tone2.png"; then
    fail "--no-halos changed a scene without halo stages"
fi

# Every host renders a halo scene.
for host in slice slab; do
    run 0 "$HALO_RENDER" --quiet --host $host --size 48x48 --volume-size 32 -o "$tmp/$host.png"
    expect_png "$tmp/$host.png"
    expect_stdout "$host host"
done
finish
