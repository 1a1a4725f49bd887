#!/bin/sh
# Every file reader is bounded (halo.h, HALO_MAX_FILE_BYTES: 64 MiB): a scene, a
# module, a host, a composed shader, a polyline file or a shader to check that never
# ends (/dev/zero) is refused with exit 2 and an error naming the file and the limit,
# after at most 64 MiB were read; a regular file past the limit is refused by its size.
# Before the bound each of these read until memory ran out, then spun.
. "$srcdir/tests/validate/common.sh"

# bounded STATUS COMMAND...: COMMAND exits STATUS within 20 s, naming /dev/zero and the limit
bounded() {
    bounded_status=$1
    shift
    run "$bounded_status" timeout 20 "$@"
    expect_stderr "^/dev/zero: error: .*larger than the 64 MiB .*HALO_MAX_FILE_BYTES"
}

host="$data/hosts/minimal.frag"
bounded 2 "$HALO_VALIDATE" link --scene /dev/zero --host "$host"
bounded 2 "$HALO_VALIDATE" link --module /dev/zero --host "$host"
bounded 2 "$HALO_VALIDATE" link --host /dev/zero
bounded 2 "$HALO_VALIDATE" link --pieces --composed /dev/zero
bounded 2 "$HALO_VALIDATE" check /dev/zero
if test -n "${HALO_RENDER:-}" && test -x "$HALO_RENDER"; then
    bounded 2 "$HALO_RENDER" --scene /dev/zero -o "$tmp/x.png"
    test ! -e "$tmp/x.png" || fail "halo-render wrote an image for /dev/zero"
fi
lines="${top_builddir:-.}/tools/halo-lines"
if test -x "$lines"; then
    bounded 2 "$lines" --lines /dev/zero -o "$tmp/l.png"
fi

# a sparse regular file one byte past the limit: refused by its size
truncate -s $((64 * 1024 * 1024 + 1)) "$tmp/big.json"
run 2 timeout 20 "$HALO_VALIDATE" link --scene "$tmp/big.json" --host "$host"
expect_stderr "big\.json: error: .*HALO_MAX_FILE_BYTES"
finish
