#!/bin/sh
# Conformance through EGL (surfaceless, or a device): the rows of tests/conform.sh on
# the backend of GPUs and of Mesa >= 25.1 (tests/conform_backend.sh).
. "${srcdir:-.}/tests/conform_backend.sh"
conform_backend egl "${HALO_HAVE_EGL:-}"
