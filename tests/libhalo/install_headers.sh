#!/bin/sh
# The public headers install as <libhalo/halo.h> and <libhalo/halo_feature.h>, in a
# folder of their own where no other package's halo.h can clash with them; libhalo.pc's
# Cflags also put that folder on the path, so that #include <halo.h> keeps working.
# Installs the data (headers, libhalo.pc, manual) under a temporary DESTDIR and compiles against
# them, with nothing of the source tree on the include path; with VTK, the whole install.
command -v pkg-config >/dev/null 2>&1 || { echo "pkg-config not found: skipping" >&2; exit 77; }
tmp=$(mktemp -d) || exit 99
trap 'rm -rf "$tmp"' EXIT
${MAKE:-make} -s -C "$top_builddir" install-data DESTDIR="$tmp" >"$tmp/log" 2>&1 ||
    { cat "$tmp/log" >&2; echo "broken setup: cannot install the headers" >&2; exit 99; }
pc=$(find "$tmp" -name libhalo.pc)
test -n "$pc" || { echo "broken setup: libhalo.pc not installed" >&2; exit 99; }
prefix=$(sed -n 's/^prefix=//p' "$pc")
include="$tmp$prefix/include"
status=0
test -f "$include/libhalo/halo.h" || { echo "FAIL: halo.h is not installed in $include/libhalo" >&2; status=1; }
test ! -e "$include/halo.h" || { echo "FAIL: halo.h is installed in $include itself" >&2; status=1; }
printf '#include <libhalo/halo.h>\n#include <libhalo/halo_feature.h>\nint main(void) { return HALO_OK; }\n' >"$tmp/new.c"
printf '#include <halo.h>\nint main(void) { return HALO_OK; }\n' >"$tmp/old.c"
${CC:-cc} -fsyntax-only -I"$include" "$tmp/new.c" ||
    { echo "FAIL: #include <libhalo/halo.h> with -I$include" >&2; status=1; }
cflags=$(pkg-config --define-variable=prefix="$tmp$prefix" --cflags "$pc") || exit 99
# shellcheck disable=SC2086
${CC:-cc} -fsyntax-only $cflags "$tmp/old.c" ||
    { echo "FAIL: #include <halo.h> with libhalo.pc's Cflags ($cflags)" >&2; status=1; }
# shellcheck disable=SC2086
${CC:-cc} -fsyntax-only $cflags "$tmp/new.c" ||
    { echo "FAIL: #include <libhalo/halo.h> with libhalo.pc's Cflags ($cflags)" >&2; status=1; }
# libhalo-vtk (built with VTK): docs/hosts/vtk.md's snippet, taken from the doc, compiles
# and links with `pkg-config --cflags --libs libhalo-vtk` against the installed files (a
# whole install under DESTDIR: libraries too); with the sanitizers the build's flags come
# with it, their runtime being the program's
vtk_pc=$(find "$tmp" -name libhalo-vtk.pc)
doc="$top_srcdir/docs/hosts/vtk.md"
if test -n "$vtk_pc"; then
    ${MAKE:-make} -s -C "$top_builddir" install DESTDIR="$tmp" >"$tmp/log" 2>&1 ||
        { cat "$tmp/log" >&2; echo "broken setup: cannot install libhalo" >&2; exit 99; }
    # the doc's first cpp block: its #include first, the rest inside main, "..." left out
    snippet=$(awk '/^```cpp/ { if (!done) { on = 1; next } } /^```/ { if (on) { on = 0; done = 1 } } on' "$doc")
    test -n "$snippet" || { echo "FAIL: no cpp block in $doc" >&2; exit 1; }
    {
        printf '%s\n' "$snippet" | grep '^#include'
        cat <<'CXX'
#include <vtkGPUVolumeRayCastMapper.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkVolume.h>
int main()
{
    vtkVolume *volume = vtkVolume::New();
    vtkRenderer *renderer = vtkRenderer::New();
    vtkRenderWindow *render_window = vtkRenderWindow::New();
    double v = 0.5;
CXX
        printf '%s\n' "$snippet" | grep -v '^#include' | grep -v '^\.\.\.$'
        printf '    return 0;\n}\n'
    } >"$tmp/vtk.cxx"
    libdir="$tmp$(sed -n 's/^libdir=//p' "$pc" | sed "s|\${prefix}|$prefix|; s|\${exec_prefix}|$prefix|")"
    vtk_flags=$(PKG_CONFIG_PATH=$(dirname "$pc") pkg-config --define-variable=prefix="$tmp$prefix" \
        --cflags --libs "$vtk_pc") || { echo "FAIL: pkg-config --cflags --libs libhalo-vtk" >&2; status=1; }
    # shellcheck disable=SC2086
    ${HALO_CXX:-${CXX:-c++}} $HALO_SANITIZER_FLAGS -o "$tmp/my_viewer" "$tmp/vtk.cxx" $vtk_flags \
        -Wl,-rpath-link,"$libdir" >"$tmp/link.log" 2>&1 ||
        { cat "$tmp/link.log" >&2; echo "FAIL: docs/hosts/vtk.md's snippet with pkg-config --cflags --libs libhalo-vtk ($vtk_flags)" >&2; status=1; }
    test "$status" -eq 0 && echo "libhalo-vtk.pc: docs/hosts/vtk.md's snippet compiles and links against the installed libhalo-vtk"
fi
test "$status" -eq 0 && echo "headers installed in $prefix/include/libhalo; both include paths compile"
exit $status
