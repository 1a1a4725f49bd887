#!/bin/sh
# A build and make check leave the git checkout clean: no build output is tracked
# (so no build dirties a tracked file) and every file the build writes is ignored.
#
# What it checks, and why not simply `git status --porcelain` is empty: a developer
# runs make check with edits and new sources not yet committed, and the parallel
# harness runs this test while other tests still run, so the check must not depend on
# the order of tests nor fail on the developer's own work. It fails on
#   1. a tracked file that make builds (the programs, libraries and generated sources
#      that make passes in HALO_BUILD_OUTPUTS) or that autotools writes;
#   2. a tracked file that is an object or an executable (ELF), wherever it is;
#   3. an untracked file that is not ignored and is a build output by its name (*.o,
#      *.lo, *.la, *.log, *.trs, *.png, a program of HALO_BUILD_OUTPUTS) or an ELF file.
# An untracked new source (*.c, *.sh, ...) passes: adding it is the developer's job.
# Skips (77) outside a git checkout of this tree (make distcheck's unpacked tarball)
# or without git.
top=${top_srcdir:-${srcdir:-.}}
command -v git >/dev/null 2>&1 || { echo "no git: skipping" >&2; exit 77; }
top=$(cd "$top" && pwd -P) || exit 99
root=$(git -C "$top" rev-parse --show-toplevel 2>/dev/null) || { echo "not a git checkout: skipping" >&2; exit 77; }
root=$(cd "$root" && pwd -P)
if test "$root" != "$top"; then
    # e.g. distcheck's libhalo-X/ unpacked inside a checkout: not the checkout itself
    echo "$top is not the top of a git checkout: skipping" >&2
    exit 77
fi
cd "$top" || exit 99

scratch=$(mktemp -d "${TMPDIR:-/tmp}/tree_clean.XXXXXX") || exit 99
trap 'rm -rf "$scratch"' EXIT
status=0
fail() {
    echo "FAIL: $1" >&2
    status=1
}

is_elf() { # FILE: starts with 0x7f 'E' 'L' 'F'
    test -f "$1" && test "$(od -An -tx1 -N4 "$1" 2>/dev/null | tr -d ' \n')" = "7f454c46"
}

# 1. build outputs and autotools outputs tracked
autotools="configure configure~ aclocal.m4 config.status config.log libtool Makefile.in Makefile libhalo.pc"
for path in $autotools ${HALO_BUILD_OUTPUTS:-}; do
    if test -n "$(git ls-files -- ":(literal)$path")"; then
        fail "$path is a build output but git tracks it (git rm --cached it, add it to .gitignore)"
    fi
done

# 2. tracked objects and executables
git ls-files -z | xargs -0 -n 200 sh -c 'for f; do
    if test -f "$f" && test "$(od -An -tx1 -N4 "$f" 2>/dev/null | tr -d " \n")" = "7f454c46"; then
        echo "$f"; fi; done' sh >"$scratch/tracked-elf"
while read -r path; do
    fail "$path is an object or executable (ELF) and git tracks it"
done <"$scratch/tracked-elf"

# 3. build outputs neither tracked nor ignored
git ls-files --others --exclude-standard >"$scratch/untracked"
while read -r path; do
    case $path in
    *.o | *.lo | *.la | *.a | *.so | *.log | *.trs | *.png)
        fail "$path is a build output that .gitignore does not cover"; continue ;;
    esac
    for output in ${HALO_BUILD_OUTPUTS:-}; do
        if test "$path" = "$output"; then
            fail "$path is a build output that .gitignore does not cover"
            continue 2
        fi
    done
    if is_elf "$path"; then
        fail "$path is an executable (ELF) that .gitignore does not cover"
    fi
done <"$scratch/untracked"

test $status -eq 0 && echo "the checkout holds no build output; every build output is ignored"
exit $status
