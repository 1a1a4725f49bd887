#!/bin/sh
# docs/accuracy.md holds the registry of conformance rows as `halo-validate conform
# --list` prints it, between the markers "<!-- conform --list: begin -->" and
# "<!-- conform --list: end -->": the copy is the program's output, so the page's
# tolerances cannot drift from validate/conform_rows.c. With --write (run by hand, from
# the top source directory with HALO_VALIDATE set) it rewrites the copy instead.
. "$srcdir/tests/validate/common.sh"

doc="$srcdir/docs/accuracy.md"
begin='<!-- conform --list: begin -->'
end='<!-- conform --list: end -->'
run 0 "$HALO_VALIDATE" conform --list
# the page's copy: the lines between the markers, without the code fence
awk -v b="$begin" -v e="$end" '$0 == e { inside = 0 } inside && !/^```$/ { print } $0 == b { inside = 1 }' \
    "$doc" >"$tmp/doc"
test -s "$tmp/doc" || fail "docs/accuracy.md has no '$begin' ... '$end' block"
if test "${1:-}" = --write; then
    awk -v b="$begin" -v e="$end" -v list="$tmp/out" '
        $0 == e { print "```"; while ((getline line < list) > 0) print line; print "```"; inside = 0 }
        !inside { print }
        $0 == b { inside = 1 }' "$doc" >"$tmp/new" && cp "$tmp/new" "$doc"
elif ! cmp -s "$tmp/out" "$tmp/doc"; then
    fail "docs/accuracy.md's copy of 'halo-validate conform --list' differs from its output (rewrite it: tests/validate/accuracy_doc.sh --write)"
    diff "$tmp/doc" "$tmp/out" | head -20 >&2
fi
finish
