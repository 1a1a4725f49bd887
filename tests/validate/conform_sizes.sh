#!/bin/sh
# Conformance rows at larger images than the suite's 25 x 25 (issue 26: a row must pass at
# every size, or state the sizes it holds for): ray@ortho, whose rays meet the planes between
# segments at the same depths, at 128 x 128 (5 pixels over before the plane decisions were
# bracketed) and 256 x 256 (1 pixel over, 3.3e-3, before each plane was also bracketed on
# its own), through the default headless context.
validate="${HALO_VALIDATE:-$top_builddir/validate/halo-validate}"
test -x "$validate" || { echo "broken setup: $validate not built" >&2; exit 99; }
status=0
for size in 128 256; do
    out=$("$validate" conform --stage ray@ortho --size "$size" 2>&1)
    rc=$?
    if test $rc -eq 2 && echo "$out" | grep -qi "no headless OpenGL context"; then
        echo "no OpenGL context: skipping"
        exit 77
    fi
    echo "$size x $size: $(echo "$out" | grep '^ray@ortho')"
    if test $rc -ne 0 || ! echo "$out" | grep -q '^ray@ortho .* PASS$'; then
        echo "$out"
        echo "FAIL: conform --stage ray@ortho --size $size (exit $rc)"
        status=1
    fi
done
exit $status
