#!/bin/sh
# halo-validate check agrees with glslangValidator (Debian's glslang-tools), the
# reference, on plain shaders: one small shader per class in tests/data/glslang (its own
# #version or none, no precision added, '#version' after comments, old-Mac line ends,
# '#include' beside the file, errors after a preprocessing error, a link error after a
# compile error, the parser stopping at a syntax error and the preprocessor at a bad
# macro, '#line' with and without a file name, string escapes the parser reads as
# written, '__FILE__' as the file's name). Each gets the reference's
# verdict and its error lines (file:line), and its link errors. A file on which the
# compiler crashes is an input error at the file, and the files after it are checked; a
# crash on one of several targets keeps the other targets' errors.
. "$srcdir/tests/validate/common.sh"

command -v glslangValidator >/dev/null 2>&1 || {
    echo "glslangValidator not found (Debian: glslang-tools): skipped"
    exit 77
}
dir="$srcdir/tests/data/glslang"

# ref_lines, check_lines FILE: the sorted file:line pairs and link messages of the errors in a log, the
# reference's ("ERROR: f:N: msg", "ERROR: Linking ...") or check's ("f:N:C: error: msg", or
# "f:N: error: msg" where it knows no column: a '#line' numbering of the shader's own).
ref_lines() {
    sed -n -e 's/^ERROR: \([^ ]*:[0-9][0-9]*\): .*/\1/p' -e 's/^ERROR: \(Linking .*\)/\1/p' "$1" |
        sed 's/ *$//' | sort -u
}
check_lines() {
    sed -n -e 's/^\([^ ]*:[0-9][0-9]*\):[0-9][0-9]*: error: .*/\1/p' -e 's/^\([^ ]*:[0-9][0-9]*\): error: .*/\1/p' \
        -e 's/^[^ ]*: error: \(Linking .*\)/\1/p' "$1" |
        sed 's/ *$//' | sort -u
}

for f in "$dir"/*.frag "$dir"/*.vert "$dir"/include/*.frag; do
    case $f in */compiler_crash.vert) continue ;; esac
    glslangValidator -l -C "$f" >"$tmp/ref" 2>&1
    ref=$?
    test "$ref" -eq 0 || ref=1
    run "$ref" "$HALO_VALIDATE" check "$f"
    case $f in
    */cr_*)
        # glslang counts no line end in a file with old-Mac "\r" line ends (every error is
        # at its line 1); check numbers the lines as an editor shows them
        continue ;;
    esac
    ref_lines "$tmp/ref" >"$tmp/ref.lines"
    check_lines "$tmp/err" >"$tmp/check.lines"
    if ! cmp -s "$tmp/ref.lines" "$tmp/check.lines"; then
        fail "$f: error lines differ from glslangValidator's"
        diff "$tmp/ref.lines" "$tmp/check.lines" | sed 's/^/    /' >&2
    fi
done

# the lines of an old-Mac file as an editor shows them
run 1 "$HALO_VALIDATE" check "$dir/cr_endings_error.frag"
expect_stderr "cr_endings_error\.frag:4:[0-9]+: error: 'missing'"
# without #version: GLSL ES 1.00, and a note says so
run 0 "$HALO_VALIDATE" check "$dir/no_version.frag"
expect_stderr "no_version\.frag: note: no '#version': checked as GLSL ES 1\.00"
# --target still chooses: GLSL ES 3.00 has no gl_FragColor
run 1 "$HALO_VALIDATE" check --target es300 "$dir/own_version.frag"
expect_stderr "own_version\.frag:5:[0-9]+: error: 'gl_FragColor'"
# a compiler crash: an input error at the file, and the next file is still checked
# (under AddressSanitizer the crash must stay a signal, as in a plain build: ASan would
# catch it and exit with its own report)
ASAN_OPTIONS="handle_segv=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
TSAN_OPTIONS="handle_segv=0${TSAN_OPTIONS:+:$TSAN_OPTIONS}"
export ASAN_OPTIONS TSAN_OPTIONS
run 1 "$HALO_VALIDATE" check "$dir/compiler_crash.vert" "$dir/own_version.frag"
expect_stderr "compiler_crash\.vert(:[0-9]+:[0-9]+)?: error: "
grep -q "own_version\.frag: ok" "$tmp/out" || fail "the file after a compiler crash was not checked"
# a crash on one target of several (450 here) keeps the errors of the others, before and
# after it, and names the target that crashed
run 1 "$HALO_VALIDATE" check --target all "$dir/compiler_crash.vert"
expect_stderr "compiler_crash\.vert:5:[0-9]+: error: 'atomicMax' .*\[330, es300\]"
expect_stderr "compiler_crash\.vert: error: the GLSL compiler crashed on this file \(.*\) \[450\]"
finish
