#!/bin/sh
# Every stage module (glsl/**/*.glsl) and every example host validates with glslang
# for GLSL 330, 450 and ES 300 (halo-validate check does all three).
if test -z "${srcdir:-}" || test ! -x "${HALO_VALIDATE:-}"; then
    echo "broken setup: srcdir or HALO_VALIDATE missing" >&2
    exit 99
fi
modules=$(find "$srcdir/glsl" -name '*.glsl' | LC_ALL=C sort)
hosts=$(ls "$srcdir"/examples/hosts/*.frag "$srcdir"/examples/hosts/*.vert 2>/dev/null)
count=$(echo $modules | wc -w)
if test "$count" -lt 9; then
    echo "broken setup: only $count modules found under $srcdir/glsl" >&2
    exit 99
fi
if test -z "$hosts"; then
    echo "broken setup: no example hosts under $srcdir/examples/hosts" >&2
    exit 99
fi
# shellcheck disable=SC2086 # the lists are split on purpose (no spaces in these names)
"$HALO_VALIDATE" check $modules $hosts
status=$?
if test "$status" -ne 0; then
    echo "FAIL: halo-validate check exited $status" >&2
    exit 1
fi
exit 0
