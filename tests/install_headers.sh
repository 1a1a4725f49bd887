#!/bin/sh
# The public headers install as <libhalo/halo.h> and <libhalo/halo_feature.h>, in a
# folder of their own where no other package's halo.h can clash with them; libhalo.pc's
# Cflags also put that folder on the path, so that #include <halo.h> keeps working.
# Installs the data (headers, libhalo.pc, manual) under a temporary DESTDIR and compiles against
# them, with nothing of the source tree on the include path.
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
# libhalo-vtk (built with VTK): docs/hosts/vtk.md's snippet compiles with libhalo-vtk.pc's
# Cflags alone (VTK's include folder with them)
vtk_pc=$(find "$tmp" -name libhalo-vtk.pc)
if test -n "$vtk_pc"; then
    cat >"$tmp/vtk.cxx" <<'CXX'
#include <libhalo/halo_vtk.h>
#include <vtkVolume.h>
#include <vtkRenderer.h>
int main()
{
    halo_setup(nullptr);
    halo_diagnostics *diag = halo_diagnostics_create();
    halo_library *lib = halo_library_create(diag);
    halo_scene *scene = halo_scene_load("scene.json", lib, diag);
    vtkGPUVolumeRayCastMapper *mapper = halo_vtk_mapper_new();
    vtkVolume *volume = vtkVolume::New();
    vtkRenderer *renderer = vtkRenderer::New();
    halo_vtk_desc desc = {};
    desc.mapper = mapper;
    desc.volume = volume;
    desc.renderer = renderer;
    desc.library = lib;
    desc.scene = scene;
    halo_vtk *h = halo_vtk_install(&desc, diag);
    halo_vtk_check(h, diag);
    halo_vtk_remove(h);
    return 0;
}
CXX
    vtk_cflags=$(PKG_CONFIG_PATH=$(dirname "$pc") pkg-config --define-variable=prefix="$tmp$prefix" --cflags "$vtk_pc") ||
        { echo "FAIL: pkg-config --cflags libhalo-vtk" >&2; status=1; }
    # shellcheck disable=SC2086
    ${CXX:-c++} -fsyntax-only $vtk_cflags "$tmp/vtk.cxx" ||
        { echo "FAIL: docs/hosts/vtk.md's snippet with libhalo-vtk.pc's Cflags ($vtk_cflags)" >&2; status=1; }
    test "$status" -eq 0 && echo "libhalo-vtk.pc: the VTK snippet compiles"
fi
test "$status" -eq 0 && echo "headers installed in $prefix/include/libhalo; both include paths compile"
exit $status
