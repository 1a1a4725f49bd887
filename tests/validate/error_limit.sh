#!/bin/sh
# A cap on the diagnostics, as clang's -ferror-limit: 100 000 markers in a host or
# 100 000 unknown stages in a scene print 100 errors (the default) and one line
# "N more errors not shown", not 100 000 errors; --error-limit N changes the cap and
# 0 lifts it. The exit status still says the input has errors.
. "$srcdir/tests/validate/common.sh"

awk 'BEGIN { print "#version 330 core"; for (i = 0; i < 100000; i++) print "#pragma halo declarations";
             print "out vec4 c;"; print "void main() { c = vec4(1.0); }" }' >"$tmp/markers.frag"
awk 'BEGIN { printf "{\"halo_scene\": 1, \"stages\": ["; for (i = 0; i < 100000; i++) printf "%s\"nosuch%d\"", i ? ", " : "", i;
             print "]}" }' >"$tmp/stages.json"

count_errors() {
    grep -c ": error: " "$tmp/err"
}

run 1 "$HALO_VALIDATE" check --target 330 "$tmp/markers.frag"
test "$(count_errors)" -eq 100 || fail "default cap: $(count_errors) errors shown, expected 100"
expect_stderr "^99899 more errors not shown"
test "$(wc -l <"$tmp/err")" -lt 1000 || fail "$(wc -l <"$tmp/err") lines of diagnostics"

run 1 "$HALO_VALIDATE" check --error-limit 3 --target 330 "$tmp/markers.frag"
test "$(count_errors)" -eq 3 || fail "--error-limit 3: $(count_errors) errors shown"
expect_stderr "^99996 more errors not shown"

run 1 "$HALO_VALIDATE" check --error-limit 0 --target 330 "$tmp/markers.frag"
test "$(count_errors)" -eq 99999 || fail "--error-limit 0: $(count_errors) errors shown, expected all 99999"
if grep -q "more errors not shown" "$tmp/err"; then fail "--error-limit 0 still caps"; fi

run 1 "$HALO_VALIDATE" link --scene "$tmp/stages.json" --host "$data/hosts/minimal.frag"
test "$(count_errors)" -eq 100 || fail "scene: $(count_errors) errors shown, expected 100"
expect_stderr "^99900 more errors not shown"
run 1 "$HALO_VALIDATE" link --error-limit 1 --scene "$tmp/stages.json" --host "$data/hosts/minimal.frag"
test "$(count_errors)" -eq 1 || fail "scene, --error-limit 1: $(count_errors) errors shown"

run 2 "$HALO_VALIDATE" check --error-limit many "$tmp/markers.frag"
run 2 "$HALO_VALIDATE" link --error-limit -1 --host "$data/hosts/minimal.frag"
finish
