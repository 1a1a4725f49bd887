#!/bin/sh
# One code style for every C and C++ source git tracks: .clang-format at the root, as
# Debian 12's clang-format (14) applies it (setup.sh installs it). Fails naming each file
# that clang-format would change, with the first lines it would change; `make style`
# rewrites them. Skips (77) outside a git checkout (distcheck's tarball), without
# clang-format, or with another major version (each formats a little differently).
top=${top_srcdir:-${srcdir:-.}}
cd "$top" || exit 99
command -v clang-format >/dev/null 2>&1 ||
    { echo "clang-format not found (Debian package clang-format): skipping" >&2; exit 77; }
version=$(clang-format --version | sed -n 's/.*version \([0-9][0-9]*\)\..*/\1/p')
test "$version" = 14 || { echo "clang-format $version, not 14 (the style's): skipping" >&2; exit 77; }
command -v git >/dev/null 2>&1 && git rev-parse --show-toplevel >/dev/null 2>&1 &&
    test "$(cd "$(git rev-parse --show-toplevel)" && pwd -P)" = "$(pwd -P)" ||
    { echo "not the top of a git checkout: skipping" >&2; exit 77; }
test -f .clang-format || { echo "broken setup: no .clang-format in $top" >&2; exit 99; }
tmp=$(mktemp -d) || exit 99
trap 'rm -rf "$tmp"' EXIT
status=0 count=0
for f in $(git ls-files '*.c' '*.h' '*.cc' '*.cxx' '*.cpp'); do
    test -f "$f" || continue # deleted in the work tree, not yet in git
    count=$((count + 1))
    clang-format --style=file "$f" >"$tmp/formatted" || { echo "FAIL: clang-format cannot read $f" >&2; status=1; continue; }
    if ! cmp -s "$f" "$tmp/formatted"; then
        echo "FAIL: $f is not in the style of .clang-format (make style rewrites it):" >&2
        diff -u "$f" "$tmp/formatted" | sed -n '3,14p' >&2
        status=1
    fi
done
test "$status" -eq 0 && echo "$count C and C++ files in the style of .clang-format"
exit "$status"
