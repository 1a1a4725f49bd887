#!/bin/sh
# halo-validate conform --list: the registry of conformance rows (validate/conform_rows.c)
# without a GL context: every family, the example ray casters' rows, and every per-sample
# stage of the library (a stage without a row would only get the default tolerance),
# each with a tolerance and a reason.
. "$srcdir/tests/validate/common.sh"

run 0 "$HALO_VALIDATE" conform --list
for family in render sample frame pass outline slice segments feature lines figure3; do
    grep -q "^[^ ]*  *$family " "$tmp/out" || fail "conform --list shows no row of the family $family"
done
# the per-sample stages are the library's (halo-validate list), not a list kept here: a
# new stage without a row fails this test. halo_math holds helpers only (no halo_apply
# step, no description).
cp "$tmp/out" "$tmp/rows"
run 0 "$HALO_VALIDATE" list
stages=$(awk '/^[a-z_0-9]+ +sample / && $1 != "halo_math" { print $1 }' "$tmp/out")
test -n "$stages" || fail "halo-validate list shows no per-sample stage"
for stage in $stages; do
    grep -q "^$stage " "$tmp/rows" || fail "conform --list has no row $stage"
done
# every example ray caster has rows against its emulation (docs/accuracy.md, segments)
for row in ray ray@webgl ray@webgl_sample ray@exit_points ray@exit_points_sample ray@tf2d ray@tf2d_sample \
    ray@iso ray@iso_sample ray@mip; do
    grep -q "^$row  *segments " "$tmp/rows" || fail "conform --list has no row $row"
done
# every row line has a name, a family and a tolerance; its second line the reason
awk 'NR > 1 && NR % 2 == 0 && NF < 4 { bad = 1 } NR > 1 && NR % 2 == 1 && NF < 1 { bad = 1 } END { exit bad }' \
    "$tmp/rows" || fail "conform --list: a row without family, tolerance or reason"
finish
