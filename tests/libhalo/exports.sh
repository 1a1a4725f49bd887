#!/bin/sh
# The shared library exports only the public API: every defined dynamic symbol of
# libhalo.so starts with halo_, and the halo_ ones are exactly the functions that
# the installed headers declare (no internal helper leaks out, no public function is missing).
lib="${HALO_LIBDIR:-$top_builddir/libhalo}/.libs/libhalo.so"
header="$srcdir/libhalo/halo.h"
if ! command -v nm >/dev/null 2>&1; then
    echo "nm not found: skipping" >&2
    exit 77
fi
if test ! -f "$lib"; then
    echo "$lib not built (static-only build?): skipping" >&2
    exit 77
fi
if test ! -f "$header"; then
    echo "broken setup: $header not found" >&2
    exit 99
fi
symbols=$(nm -D --defined-only "$lib" | awk 'NF >= 3 { print $3 }' | LC_ALL=C sort -u) || exit 99
if test -z "$symbols"; then
    echo "FAIL: $lib exports nothing" >&2
    exit 1
fi
status=0
outside=$(echo "$symbols" | grep -v '^halo_')
if test -n "$outside"; then
    echo "FAIL: $lib exports $(echo "$outside" | wc -l) symbols outside the halo_ namespace, e.g.:" >&2
    echo "$outside" | head -20 >&2
    status=1
fi
# the installed public headers: halo.h, halo_feature.h (feature halos) and
# halo_gl_loader.h (the GL loader a host without one may use)
api=$(cat "$header" "$srcdir/libhalo/halo_feature.h" "$srcdir/libhalo/halo_gl_loader.h" | grep -o 'halo_[a-z0-9_]*(' | tr -d '(' | LC_ALL=C sort -u)
for name in $(echo "$symbols" | grep '^halo_'); do
    echo "$api" | grep -qx "$name" || { echo "FAIL: $name is exported but not declared in the public headers" >&2; status=1; }
done
for name in $api; do
    echo "$symbols" | grep -qx "$name" || { echo "FAIL: $name is declared in a public header but not exported" >&2; status=1; }
done
test "$status" -eq 0 && echo "$(echo "$symbols" | wc -l) symbols exported, all declared in the public headers"
exit $status
