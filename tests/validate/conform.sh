#!/bin/sh
# Conformance through OSMesa: every stage rendered headless matches its C emulation
# within the stated tolerance (tests/validate/conform_backend.sh; EGL: tests/validate/conform_egl.sh).
. "${srcdir:-.}/tests/validate/conform_backend.sh"
conform_backend osmesa "${HALO_HAVE_OSMESA:-}"
