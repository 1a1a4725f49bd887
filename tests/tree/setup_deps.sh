#!/bin/sh
# setup.sh installs everything the build uses (issue 24): each library the build links
# and each header it includes belongs to a Debian package that setup.sh installs or that
# one of those depends on, so a fresh Debian 12 machine builds what this one built, and
# a package that only the developer's machine has is caught here. Read from the build:
#   - configure's results: the Makefile's *_LIBS, *_CFLAGS, *_CPPFLAGS, *_CXXFLAGS and
#     *_LDFLAGS values (-l found on their -L folders and the compiler's search path;
#     -I, -isystem and -L folders); those of a component configure left out (its
#     conditional HALO_HAVE_X false in config.status) are not checked;
#   - every header the objects included (automake's .deps, CMake's .o.d files);
#   - the ParaView plugin's CMake build, when there is one: the package folders in
#     CMakeCache.txt, the imported targets its targets reach with their include folders
#     and libraries (halo-uses.txt, written by adapters/paraview/uses.cmake), the flags
#     in flags.make and link.txt (CMakeCache.txt's other paths are what CMake's finds
#     found on this machine, used or not);
#   - ldd of every program and shared library built.
# Files are resolved with dpkg -S; setup.sh's packages (its packages="..." list) are
# closed over their dependencies with one apt-cache depends --recurse. Files of packages
# of priority required or Essential (libc6, libgcc-s1, ...) count as the base system.
# Prints each missing package with the files that need it and exits 1. Skips (77)
# without dpkg-query, apt-cache or ldd, or without a configured build.
#   HALO_SETUP_SH   the setup.sh to read (default: the source tree's)
src=$(cd "${top_srcdir:-${srcdir:-.}}" && pwd -P) || exit 99
build=$(cd "${top_builddir:-.}" && pwd -P) || exit 99
setup=${HALO_SETUP_SH:-$src/setup.sh}
for tool in dpkg-query apt-cache ldd realpath; do
    command -v $tool >/dev/null 2>&1 || { echo "SKIP: $tool not found (not a Debian system?)"; exit 77; }
done
test -f "$build/Makefile" || { echo "SKIP: no configured build in $build"; exit 77; }
test -r "$setup" || { echo "broken setup: $setup not found" >&2; exit 99; }
LC_ALL=C
export LC_ALL
tmp=$(mktemp -d "${TMPDIR:-/tmp}/setup_deps.XXXXXX") || exit 99
trap 'rm -rf "$tmp"' EXIT

# ---- setup.sh's packages and their dependencies ----
packages=$(awk '/^packages="/ { on = 1; sub(/^packages="/, "") }
    on { last = sub(/".*/, ""); print; if (last) exit }' "$setup" | tr -s ' \t' '\n\n' | sed '/^$/d')
test -n "$packages" || { echo "broken setup: no packages=\"...\" list in $setup" >&2; exit 99; }
for p in $packages; do
    case $p in *[!a-z0-9+.-]*) echo "broken setup: '$p' in $setup's list is not a package name" >&2; exit 99 ;; esac
done
echo "$packages" | sort -u >"$tmp/listed"
# shellcheck disable=SC2086 # one word per package
apt-cache depends --recurse --no-recommends --no-suggests --no-conflicts --no-breaks --no-replaces \
    --no-enhances $packages 2>"$tmp/apt.err" | awk '/^[^ <]/ { sub(/:.*/, ""); print }' | sort -u >"$tmp/closure"
status=0
for p in $(comm -23 "$tmp/listed" "$tmp/closure"); do
    echo "FAIL: setup.sh installs $p, which apt does not know"
    status=1
done

# ---- what the build uses: "PATH<TAB>ORIGIN" lines in $tmp/needs ----
# flags: lines "ORIGIN<TAB>FLAGS..." in, "dir|file|L|lib<TAB>VALUE<TAB>ORIGIN" out
flags() {
    awk -F '\t' '{
        n = split($2, t, /[ \t]+/)
        for (i = 1; i <= n; i++) {
            w = t[i]
            if ((w == "-I" || w == "-isystem" || w == "-L") && i < n) { w = w t[++i] }
            if (w ~ /^-isystem\//) print "dir\t" substr(w, 9) "\t" $1
            else if (w ~ /^-I\//) print "dir\t" substr(w, 3) "\t" $1
            else if (w ~ /^-L\//) print "L\t" substr(w, 3) "\t" $1
            else if (w ~ /^-l[^ ]/) print "lib\t" substr(w, 3) "\t" $1
            else if (w ~ /^\//) print "file\t" w "\t" $1
        }
    }'
}
# configure's results; config.status says which components it left out (the conditional
# HALO_HAVE_X false: the X_* values are not used)
test -f "$build/config.status" || { echo "SKIP: no config.status in $build"; exit 77; }
sed -n 's/^S\["HALO_HAVE_\([A-Z0-9]*\)_TRUE"\]="#"$/\1/p' "$build/config.status" >"$tmp/off"
awk 'FILENAME == ARGV[1] { off[$1] = 1; next }
    /^[A-Z][A-Z0-9_]* = / && $1 ~ /(^|_)(LIBS|CFLAGS|CPPFLAGS|CXXFLAGS|LDFLAGS)$/ && $0 !~ /\$[({]/ {
        c = $1; sub(/_[A-Z]*$/, "", c); if (c in off) next
        v = $0; sub(/^[^=]*= */, "", v); print $1 "\t" v }' "$tmp/off" "$build/Makefile" | flags >"$tmp/flags"
pv="$build/adapters/paraview/build"
if test -f "$pv/CMakeCache.txt"; then
    # the package folders CMake found (ParaView_DIR, VTK_DIR, ...), the imported targets
    # the plugin reaches (uses.cmake), the compile and link lines
    awk -F= '/^[A-Za-z0-9_]+_DIR:(PATH|UNINITIALIZED)=\// && !/(INCLUDE|HEADER)_DIR:/ { name = $1; sub(/:.*/, "", name)
        print "file\t" $2 "\tCMakeCache.txt " name }' "$pv/CMakeCache.txt" >>"$tmp/flags"
    test -f "$pv/halo-uses.txt" &&
        awk -F '\t' '{ print "file\t" $2 "\tCMake target " $1 }' "$pv/halo-uses.txt" >>"$tmp/flags"
    find "$pv" \( -name flags.make -o -name link.txt \) -print | while read -r f; do
        sed -n "s,^[A-Z_]* = ,,p; /^[^#A-Z]/p" "$f" | sed "s,^,${f#"$build"/}	,"
    done | flags >>"$tmp/flags"
fi
# -l: the -L folders, then the compiler's search path
cc=$(sed -n 's/^CC = //p' "$build/Makefile")
search=$({ awk -F '\t' '$1 == "L" { print $2 }' "$tmp/flags"; ${cc:-cc} -print-search-dirs 2>/dev/null |
    sed -n 's/^libraries: =//p' | tr ':' '\n'; } | sed '/^$/d' | tr '\n' '\0' | xargs -0 realpath -m)
awk -F '\t' '$1 == "lib" { print $2 "\t" $3 }' "$tmp/flags" | sort -u | while IFS='	' read -r lib origin; do
    for dir in $search; do
        for f in "$dir/lib$lib.so" "$dir/lib$lib.a"; do
            test -e "$f" && { printf '%s\t-l%s in %s\n' "$f" "$lib" "$origin"; continue 3; }
        done
    done
    echo "FAIL: -l$lib ($origin) is not found on the linker's search path" >&2
done >"$tmp/needs" 2>"$tmp/unfound"
awk -F '\t' '$1 != "lib" { print $2 "\t" $3 }' "$tmp/flags" >>"$tmp/needs"
# the headers each object included
find "$build" \( -name .git -o -name autom4te.cache \) -prune -o \
    \( -path '*/.deps/*.P*o' -o -name '*.o.d' \) -type f -print >"$tmp/depfiles"
if test -s "$tmp/depfiles"; then
    tr '\n' '\0' <"$tmp/depfiles" | xargs -0 awk '{ for (i = 1; i <= NF; i++) { w = $i; sub(/:$/, "", w)
        if (w ~ /^\// && !(w in seen)) { seen[w] = 1; print w "\tincluded by " FILENAME } } }' >>"$tmp/needs"
fi
# ldd of what was built, the build's own libraries found in the build
find "$build" \( -name .git -o -name autom4te.cache \) -prune -o -type f \
    \( -perm -u+x -o -name '*.so' -o -name '*.so.*' \) ! -name '*.sh' ! -name '*.py' -print >"$tmp/built"
libpath=$(find "$build" -type d -name .libs | tr '\n' ':')
tr '\n' '\0' <"$tmp/built" | LD_LIBRARY_PATH="$libpath${LD_LIBRARY_PATH:-}" xargs -0 ldd 2>/dev/null | awk '
    /^[^\t].*:$/ { f = substr($0, 1, length($0) - 1); next }
    $2 == "=>" && $3 == "not" { print "FAIL: " f " needs " $1 ", which is not found" > "/dev/stderr"; next }
    $2 == "=>" && $3 ~ /^\// { print $3 "\tldd " f }
    $1 ~ /^\// { print $1 "\tldd " f }' >>"$tmp/needs" 2>>"$tmp/unfound"
# the build's own files are not from a package
awk -F '\t' -v src="$src" -v build="$build" 'function inside(p, d) { return p == d || index(p, d "/") == 1 }
    !inside($1, src) && !inside($1, build) && !seen[$1]++' \
    "$tmp/needs" | sed "s,$build/,,g" >"$tmp/used"
if test -s "$tmp/unfound"; then
    sed "s,$build/,,g" "$tmp/unfound"
    status=1
fi

# ---- who owns each file: dpkg -S of the path and of its twin across the /usr merge
# (ldd's /lib/x86_64-linux-gnu/libz.so.1 is the package's /usr/lib/...); a file no
# package has is tried again where its links lead (/etc/alternatives) ----
owners() { # paths in, "PATH<TAB>PACKAGE" out, for each path and its twin
    twin='function twin(p) { if (sub(/^\/usr\//, "/", p)) return p; return "/usr" p }'
    awk "$twin"' { print; print twin($0) }' | tr '\n' '\0' | xargs -0 dpkg-query -S 2>/dev/null |
        awk "$twin"' !/^diversion by/ && (i = index($0, ": /")) {
            path = substr($0, i + 2); n = split(substr($0, 1, i - 1), pk, ", ")
            for (k = 1; k <= n; k++) { sub(/:.*/, "", pk[k]); print path "\t" pk[k]; print twin(path) "\t" pk[k] } }'
}
cut -f1 "$tmp/used" | owners >"$tmp/owners"
awk -F '\t' 'FILENAME == ARGV[1] { owned[$1] = 1; next } !($1 in owned) { print $1 }' \
    "$tmp/owners" "$tmp/used" >"$tmp/unowned"
: >"$tmp/links"
: >"$tmp/gone"
if test -s "$tmp/unowned"; then
    while read -r path; do test -e "$path" || echo "$path"; done <"$tmp/unowned" >"$tmp/gone"
    tr '\n' '\0' <"$tmp/unowned" | xargs -0 realpath -m | paste "$tmp/unowned" - >"$tmp/links"
    cut -f2 "$tmp/links" | owners >>"$tmp/owners"
fi
# packages of the base system: priority required, or Essential
cut -f2 "$tmp/owners" | sort -u | comm -23 - "$tmp/closure" | tr '\n' '\0' |
    xargs -0 -r dpkg-query -W -f='${Package}\t${Priority}\t${Essential}\n' 2>/dev/null |
    awk -F '\t' '$2 == "required" || $3 == "yes" { sub(/:.*/, "", $1); print $1 }' >"$tmp/base"

# ---- the verdict ----
awk -F '\t' -v setup="$setup" '
    FILENAME == ARGV[1] || FILENAME == ARGV[2] { ok[$1] = 1; next }
    FILENAME == ARGV[3] { owner[$1] = owner[$1] " " $2; next }
    FILENAME == ARGV[4] { link[$1] = $2; next }
    FILENAME == ARGV[5] { gone[$1] = 1; next }
    {
        checked++
        if ($1 in gone) { print "FAIL: " $1 " (" $2 ") does not exist (removed since the build?)"; bad++; next }
        pk = owner[$1]; if ($1 in link) pk = pk owner[link[$1]]
        n = split(pk, p, " ")
        for (k = 1; k <= n; k++) if (p[k] in ok) next
        if (n == 0) { print "FAIL: " $1 " (" $2 ") is in no Debian package (installed by hand?)"; bad++; next }
        if (!(p[1] in missing)) order[++packages] = p[1]
        missing[p[1]] = missing[p[1]] "\n    " $1 " (" $2 ")"; count[p[1]]++
    }
    END {
        for (i = 1; i <= packages; i++) {
            m = order[i]; lines = missing[m]
            if (count[m] > 3) { split(lines, l, "\n"); lines = "\n" l[2] "\n" l[3] "\n" l[4] "\n    and " count[m] - 3 " more files" }
            print "FAIL: " m " is needed, and " setup " neither installs it nor any of its packages depends on it:" lines
        }
        print checked " files and folders of the build checked against the packages of " setup " and their dependencies"
        exit bad + packages > 0
    }' "$tmp/closure" "$tmp/base" "$tmp/owners" "$tmp/links" "$tmp/gone" "$tmp/used" || status=1
exit $status
