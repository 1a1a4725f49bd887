#!/bin/sh
# Replays each fuzz target's seed corpus plus deterministic mutations (no engine needed).
# Every crash found by run-libfuzzer.sh is added to the corpus and so replayed here.
set -u
srcdir=${srcdir:-.}
top_builddir=${top_builddir:-.}
status=0
# The seeds: the project's own modules, scenes and hosts, the test data, and the extra
# seeds (and regressions) in tests/fuzz/corpus/TARGET.
seeds() {
    case $1 in
    module) echo "$srcdir/glsl $srcdir/glsl/sample $srcdir/glsl/halo $srcdir/glsl/lines $srcdir/tests/data/modules" ;;
    scene) echo "$srcdir/examples/scenes $srcdir/tests/data/scenes" ;;
    host) echo "$srcdir/examples/hosts $srcdir/tests/data/hosts" ;;
    volume) echo "$srcdir/tests/data/volumes" ;;
    polyline) ;; # its seeds are all in tests/fuzz/corpus/polyline
    esac
    [ -d "$srcdir/tests/fuzz/corpus/$1" ] && echo "$srcdir/tests/fuzz/corpus/$1"
}
for target in module scene host volume polyline; do
    dirs=""
    for d in $(seeds $target); do [ -d "$d" ] && dirs="$dirs $d"; done
    # shellcheck disable=SC2086
    "$top_builddir/tests/fuzz/fuzz_$target" -n "${HALO_FUZZ_MUTATIONS:-1000}" $dirs
    rc=$?
    if [ $rc -ne 0 ]; then
        echo "FAIL: fuzz_$target exited $rc" >&2
        status=1
    fi
done
exit $status
