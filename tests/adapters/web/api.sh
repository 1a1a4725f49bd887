#!/bin/sh
# The web package's JavaScript API under node (tests/adapters/web/api.test.mjs): skipped (77) when
# configure left the web package out.
. "${srcdir:-.}/tests/harness.sh"
if test "${HALO_HAVE_WEB:-}" != yes; then
    echo "the web package is not built (configure --with-web: emscripten and node): skipping"
    exit 77
fi
harness_need srcdir HALO_VALIDATE HALO_WEB_PACKAGE NODE
test -f "$HALO_WEB_PACKAGE/dist/libhalo-core.wasm" || { echo "broken setup: $HALO_WEB_PACKAGE has no dist/libhalo-core.wasm"; exit 99; }
export srcdir HALO_VALIDATE HALO_WEB_PACKAGE
exec "$NODE" --test "$srcdir/tests/adapters/web/api.test.mjs"
