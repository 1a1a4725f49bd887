#!/bin/sh
# Conformance on OpenGL ES (issue 26): the rows a host can run on ES, through an EGL
# OpenGL ES 3.0 context (the WebGL 2 feature set) and an ES 3.2 one, linked for GLSL ES
# 300 (halo-validate conform --backend egl-es3.0, egl-es3.2). Every row that runs must
# pass; the rows that need desktop OpenGL are skipped with their reason (the slice and
# slab hosts, feature halos, lines, a GLSL 450 host, and on ES 3.0 the programs with
# extra outputs, which the runtime refuses there); at least MIN rows must run, so that a
# change that skips more fails here. 77 without an EGL build or an ES context.
if test ! -x "${HALO_VALIDATE:-}"; then
    echo "broken setup: HALO_VALIDATE missing" >&2
    exit 99
fi
if test "${HALO_HAVE_EGL:-}" != yes; then
    echo "SKIP: this build has no EGL backend"
    exit 77
fi
# Mesa 22.3's EGL leaks a little at eglTerminate (tests/validate/conform_backend.sh)
ASAN_OPTIONS="detect_leaks=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export ASAN_OPTIONS
log=$(mktemp) || exit 99
trap 'rm -f "$log"' EXIT
status=0
ran=0
# measured (session 11): ES 3.2 runs 95 rows, skips 31; ES 3.0 runs 45, skips 81
for case in egl-es3.2:90 egl-es3.0:40; do
    backend=${case%%:*} least=${case#*:}
    "$HALO_VALIDATE" conform --backend "$backend" --size 25 -v >"$log" 2>&1
    rc=$?
    if test $rc -eq 2 && grep -q "no headless OpenGL context" "$log"; then
        echo "no $backend context here:"
        sed 's/^/    /' "$log" | tail -3
        continue
    fi
    summary=$(tail -1 "$log")
    echo "$backend: $summary"
    grep "skipped on OpenGL ES" "$log" | sed 's/^/    /' | sort -u -k2 | head -12
    if test $rc -ne 0; then
        echo "FAIL: halo-validate conform --backend $backend exited $rc"
        grep "FAIL" "$log" | head -20
        status=1
        continue
    fi
    grep -q "^conform: egl context" "$log" || { echo "FAIL: $backend: not an EGL context"; status=1; }
    rows=$(echo "$summary" | sed -n 's/^\([0-9]*\) rows.*/\1/p')
    if test -z "$rows" || test "$rows" -lt "$least"; then
        echo "FAIL: $backend ran ${rows:-no} rows, fewer than $least"
        status=1
    fi
    ran=$((ran + 1))
done
test $status -ne 0 && exit $status # a failure is no skip (before: both backends failing read as SKIP)
test $ran -gt 0 || { echo "SKIP: no OpenGL ES context"; exit 77; }
exit $status
