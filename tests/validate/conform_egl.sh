#!/bin/sh
# Conformance through EGL (surfaceless, or a device): the rows of tests/validate/conform.sh on
# the backend of GPUs and of Mesa >= 25.1 (tests/validate/conform_backend.sh).
. "${srcdir:-.}/tests/validate/conform_backend.sh"
conform_backend egl "${HALO_HAVE_EGL:-}"
