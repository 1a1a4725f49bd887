#!/bin/sh
# The example hosts (examples/) are what a user copies, and the tools (tools/, validate/)
# are built the way a user would build them: they include only libhalo's installed
# headers (halo.h, halo_feature.h, halo_gl_loader.h, halo_vtk.h: pkginclude_HEADERS) and
# their own (their directory's, the examples'; the tools also validate's), never a header of libhalo's sources
# (internal.h, diag.h, strbuf.h, emu/..., gl/...). Allowed beyond that, each for its
# reason:
#   tools/, validate/: gl/headless.h, the headless context of the tools and tests (a
#     static library of their own, not libhalo: libhalo/gl/headless.h says why)
# Nothing else: the conformance derives what it checks from the contracts and the public
# API (validate/conform_segment.c its segment plan; halo_reflection.march the one-draw
# march), and halo-validate reads files through halo_read_text_file.
top=${top_srcdir:-${srcdir:-.}}
cd "$top" || exit 99
test -d examples && test -f libhalo/halo.h || { echo "broken setup: no examples/ in $top" >&2; exit 99; }
installed="halo.h halo_feature.h halo_gl_loader.h halo_vtk.h"
allowed="tools/*:gl/headless.h validate/*:gl/headless.h"
status=0
files=0
for f in $(find examples tools validate -name '*.c' -o -name '*.h' -o -name '*.cc' -o -name '*.cxx' | sort); do
    files=$((files + 1))
    dir=$(dirname "$f")
    # the quoted includes, with their line numbers
    grep -n '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$f" |
        sed 's/^\([0-9]*\):[^"]*"\([^"]*\)".*/\1 \2/' >"${TMPDIR:-/tmp}/public_headers.$$"
    while read -r line name; do
        base=${name#libhalo/}
        case " $installed " in *" $base "*) continue ;; esac
        if test -f "$dir/$name" || test -f "examples/$name"; then
            continue # its own header, or the examples'
        fi
        case "$f" in tools/*) test -f "validate/$name" && continue ;; esac # the tools share validate's
        ok=0
        for a in $allowed; do
            # shellcheck disable=SC2254
            case "$f:$name" in $a) ok=1 ;; esac
        done
        test "$ok" -eq 1 && continue
        if test -f "libhalo/$base" || test -f "libhalo/$name"; then
            echo "$f:$line:1: error: includes \"$name\", a private header of libhalo (not installed)" >&2
        else
            echo "$f:$line:1: error: includes \"$name\", which is neither an installed header nor its own" >&2
        fi
        status=1
    done <"${TMPDIR:-/tmp}/public_headers.$$"
done
rm -f "${TMPDIR:-/tmp}/public_headers.$$"
test "$files" -gt 0 || { echo "broken setup: no sources found" >&2; exit 99; }
test "$status" -eq 0 && echo "examples/, tools/ and validate/ ($files files) include only installed headers, their own and the allowed ones"
exit "$status"
