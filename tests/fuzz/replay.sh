#!/bin/sh
# Replays each fuzz target's seed corpus plus deterministic mutations (no engine needed).
# Every crash found by run-libfuzzer.sh is added to the corpus and so replayed here.
set -u
srcdir=${srcdir:-.}
top_builddir=${top_builddir:-.}
status=0
for target in module scene host; do
    "$top_builddir/tests/fuzz/fuzz_$target" -n "${HALO_FUZZ_MUTATIONS:-1000}" "$srcdir/tests/fuzz/corpus/$target"
    rc=$?
    if [ $rc -ne 0 ]; then
        echo "FAIL: fuzz_$target exited $rc" >&2
        status=1
    fi
done
exit $status
