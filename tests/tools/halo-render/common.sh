# Helpers for the halo-render tests, sourced by each tests/tools/halo-render/*.sh (tests/harness.sh).
# The harness sets srcdir (the top source directory) and HALO_RENDER.
. "${srcdir:-.}/tests/harness.sh"
harness_need srcdir HALO_RENDER
harness_program "$HALO_RENDER"
scenes="$srcdir/examples/scenes"
volumes="$srcdir/tests/data/volumes"
harness_tmp halo-render-test
