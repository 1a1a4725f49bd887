#!/bin/sh
# No circles between the C files of each folder (tests/tools/circles.py): libhalo/,
# examples/ and validate/ each call downwards only. Skipped (77) without python3.
command -v python3 >/dev/null 2>&1 || { echo "SKIP: python3 not found"; exit 77; }
cd "${srcdir:-.}" || exit 99
python3 tests/tools/circles.py libhalo examples validate
