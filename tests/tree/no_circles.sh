#!/bin/sh
# No circles (tests/tools/circles.py): between the C files of each folder (libhalo/,
# examples/, validate/, tools/ each call downwards only), and between the folders
# (tools -> validate -> examples -> libhalo). Skipped (77) without python3.
command -v python3 >/dev/null 2>&1 || { echo "SKIP: python3 not found"; exit 77; }
cd "${srcdir:-.}" || exit 99
python3 tests/tools/circles.py libhalo examples validate tools || exit 1
python3 tests/tools/circles.py --folders libhalo examples validate tools
