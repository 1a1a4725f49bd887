#!/bin/sh
# tests/examples/hosts/test_host_state on OpenGL ES (issue 26): the ray caster, hostile between
# its draws, through an EGL OpenGL ES 3.0 context (the WebGL 2 feature set: one draw) and
# an ES 3.2 one (one draw and segments), against a tidy host. 77 without an EGL build or
# an ES context.
if test "${HALO_HAVE_EGL:-}" != yes; then
    echo "SKIP: this build has no EGL backend"
    exit 77
fi
program=${HALO_TEST_HOST_STATE:-tests/examples/hosts/test_host_state}
# Mesa 22.3's EGL leaks a little at eglTerminate (tests/validate/conform_backend.sh)
ASAN_OPTIONS="detect_leaks=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export ASAN_OPTIONS
status=0
ran=0
for backend in egl-es3.0 egl-es3.2; do
    echo "== $backend"
    "$program" --backend "$backend"
    rc=$?
    case $rc in
    0) ran=$((ran + 1)) ;;
    77) echo "no $backend context here" ;;
    *) status=1 ;;
    esac
done
if test $status -eq 0 && test $ran -eq 0; then
    exit 77
fi
exit $status
