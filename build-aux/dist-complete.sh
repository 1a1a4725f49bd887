#!/bin/sh
# dist-complete.sh SRCDIR DISTDIR: every file git tracks in SRCDIR is in DISTDIR (the
# tarball's tree), but for the few named below that are not shipped on purpose.
# `make distcheck` runs it (distcheck-hook) before it builds the tarball, so a tarball
# missing a file fails even where the distcheck's own build leaves out the component that
# reads it (.ci/run's distcheck is configured with sanitizers, without the ParaView plugin
# and the web package). Outside a git checkout (distcheck run from a tarball) it says so
# and passes.
srcdir=$1 distdir=$2
test -d "$distdir" || { echo "dist-complete: $distdir is not a folder" >&2; exit 2; }
if ! command -v git >/dev/null 2>&1 || ! git -C "$srcdir" rev-parse --git-dir >/dev/null 2>&1; then
    echo "dist-complete: $srcdir is not a git checkout: not checked"
    exit 0
fi
# not shipped on purpose: git's own file
not_shipped='^\.gitignore$'
missing=$(git -C "$srcdir" ls-files | grep -v -E "$not_shipped" | while IFS= read -r f; do
    test -e "$distdir/$f" || test -L "$distdir/$f" || printf '%s\n' "$f"
done)
if test -n "$missing"; then
    echo "dist-complete: tracked by git but not in the tarball (add to EXTRA_DIST or a _SOURCES):" >&2
    printf '  %s\n' $missing >&2
    exit 1
fi
echo "dist-complete: all $(git -C "$srcdir" ls-files | grep -c -v -E "$not_shipped") tracked files are in the tarball"
