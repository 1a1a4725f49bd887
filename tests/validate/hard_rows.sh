#!/bin/sh
# Hard cases that are conformance rows already (docs/hard-cases.md): each row's inputs
# hold the fragile values (zero and tiny gradients, n.V rounded past +-1, depth 0 and 1,
# exponents 0 and 64; empty, full, single-pixel and border seed images; delta 0 and 1).
# Every row must PASS with no non-finite value.
validate="${HALO_VALIDATE:-$top_builddir/validate/halo-validate}"
test -x "$validate" || { echo "broken setup: $validate not built" >&2; exit 99; }
status=0
for stage in halo_seed halo_map gradient silhouette sketch orientation_fade distance_blend opacity_power \
    pass:median pass:gradient pass:spread@N1 pass:spread@delta0 pass:spread@delta1 pass:occlude \
    slice; do
    out=$("$validate" conform --stage "$stage" 2>&1)
    rc=$?
    if test $rc -eq 2 && echo "$out" | grep -qi "context"; then
        echo "no OpenGL context: skipping" >&2
        exit 77
    fi
    echo "$out" | grep -v '^stage\|rows,' 
    # columns: stage max_abs rmse over_tol nonfinite tolerance result
    bad=$(echo "$out" | awk 'NF >= 7 && $1 != "stage" && ($5 != 0 || $NF != "PASS") { print $1 }')
    if test $rc -ne 0 || test -n "$bad"; then
        echo "FAIL: conform --stage $stage (exit $rc): $bad" >&2
        status=1
    fi
done
exit $status
