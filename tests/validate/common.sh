# Helpers for the command-line tests, sourced by each tests/validate/*.sh (tests/harness.sh).
# The harness sets srcdir (the top source directory), HALO_VALIDATE and HALO_RENDER.
. "${srcdir:-.}/tests/harness.sh"
harness_need srcdir HALO_VALIDATE
harness_program "$HALO_VALIDATE"
data="$srcdir/tests/data"
harness_tmp halo-test

# A regex fragment matching a path ending in NAME (with . escaped).
re_file() {
    printf '%s' "$1" | sed 's/[.[\*^$]/\\&/g'
}

# expect_error_in NAME: the last command's stderr has an error in the file NAME
# ("NAME: error:" or "NAME:LINE:COLUMN: error:").
expect_error_in() {
    expect_stderr "$(re_file "$1")(:[0-9]+:[0-9]+)?: error:"
}
