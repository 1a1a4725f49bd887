#!/bin/sh
# The example hosts and tools' sources (examples/) are what a user copies: they include
# only libhalo's installed headers (halo.h, halo_feature.h, halo_gl_loader.h, halo_vtk.h:
# pkginclude_HEADERS) and the examples' own, never a header of libhalo's sources
# (internal.h, diag.h, strbuf.h, emu/..., gl/...).
top=${top_srcdir:-${srcdir:-.}}
cd "$top" || exit 99
test -d examples && test -f libhalo/halo.h || { echo "broken setup: no examples/ in $top" >&2; exit 99; }
installed="halo.h halo_feature.h halo_gl_loader.h halo_vtk.h"
status=0
for f in $(find examples -name '*.c' -o -name '*.h' -o -name '*.cc' -o -name '*.cxx' | sort); do
    dir=$(dirname "$f")
    # the quoted includes, with their line numbers
    grep -n '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$f" |
        sed 's/^\([0-9]*\):[^"]*"\([^"]*\)".*/\1 \2/' >"${TMPDIR:-/tmp}/public_headers.$$"
    while read -r line name; do
        base=${name#libhalo/}
        case " $installed " in *" $base "*) continue ;; esac
        if test -f "$dir/$name" || test -f "examples/$name"; then
            continue # the examples' own header
        fi
        if test -f "libhalo/$base" || test -f "libhalo/$name"; then
            echo "$f:$line:1: error: includes \"$name\", a private header of libhalo (not installed)" >&2
        else
            echo "$f:$line:1: error: includes \"$name\", which is neither an installed header nor the examples' own" >&2
        fi
        status=1
    done <"${TMPDIR:-/tmp}/public_headers.$$"
done
rm -f "${TMPDIR:-/tmp}/public_headers.$$"
test "$status" -eq 0 && echo "examples/ includes only installed headers and its own"
exit "$status"
