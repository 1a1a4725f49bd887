#!/bin/sh
# What a user copies uses only what is installed (issue 28): no example, tool, validation
# file or adapter includes a header of libhalo's own (every header under libhalo/ but the
# installed halo.h, halo_feature.h and halo_gl_loader.h). gl/headless.h is the one
# exception: the tools' and tests' static headless context (libhalo-headless.la), which
# libhalo.so does not carry on purpose (its header says why).
cd "${srcdir:-.}" || exit 99
private=$(cd libhalo && find . -name '*.h' | sed 's|^\./||' |
    grep -v -x -e halo.h -e halo_feature.h -e halo_gl_loader.h -e gl/headless.h)
[ -n "$private" ] || { echo "FAIL: no private headers found under libhalo/"; exit 1; }
files=$(find examples tools validate adapters \( -name '*.c' -o -name '*.h' -o -name '*.cxx' -o -name '*.cpp' \) \
    -type f | grep -v -e '/node_modules/' -e '/\.' | sort)
status=0
for header in $private; do
    # "internal.h", "libhalo/internal.h", <libhalo/internal.h>
    found=$(grep -n -E "^[[:space:]]*#[[:space:]]*include[[:space:]]*[\"<](libhalo/)?$header[\">]" $files /dev/null)
    if [ -n "$found" ]; then
        echo "FAIL: libhalo's own header $header is included outside libhalo/:"
        echo "$found" | sed 's/^/  /'
        status=1
    fi
done
[ $status = 0 ] && echo "PASS: $(echo "$files" | wc -l) files of examples/, tools/, validate/ and adapters/ include only installed headers (and gl/headless.h)"
exit $status
