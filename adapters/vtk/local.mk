# adapters/vtk/: libhalo inside VTK (docs/hosts/vtk.md). libhalo-vtk installs a linked
# scene into vtkGPUVolumeRayCastMapper through shader replacements and custom uniforms;
# examples/halo-vtk renders with it; tests/adapters/vtk/ checks it under xvfb-run. Built only when
# configure finds VTK (setup.sh installs Debian's libvtk9-dev).
EXTRA_DIST += adapters/vtk/halo_vtk.cxx adapters/vtk/halo_vtk.h examples/halo-vtk.cxx adapters/vtk/libhalo-vtk.pc.in

if HALO_HAVE_VTK
# compile and link a VTK program with `pkg-config --cflags --libs libhalo-vtk`
pkgconfig_DATA += adapters/vtk/libhalo-vtk.pc
lib_LTLIBRARIES += adapters/vtk/libhalo-vtk.la
pkginclude_HEADERS += adapters/vtk/halo_vtk.h
adapters_vtk_libhalo_vtk_la_SOURCES = adapters/vtk/halo_vtk.cxx adapters/vtk/halo_vtk.h
adapters_vtk_libhalo_vtk_la_CPPFLAGS = $(AM_CPPFLAGS) $(VTK_CPPFLAGS)
# VTK's headers are not warning-clean under our flags: they are system headers here
adapters_vtk_libhalo_vtk_la_CXXFLAGS = $(AM_CXXFLAGS) -Wno-deprecated-copy -Wno-extra-semi
adapters_vtk_libhalo_vtk_la_LIBADD = libhalo/libhalo.la $(VTK_LIBS)

bin_PROGRAMS += examples/halo-vtk
# the adapter's source again: the example links libhalo's static core (with the hosts'
# helpers), not the shared libhalo the installed libhalo-vtk uses
examples_halo_vtk_SOURCES = examples/halo-vtk.cxx examples/volume_io.c examples/volume_io.h \
	adapters/vtk/halo_vtk.cxx
examples_halo_vtk_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples -I$(top_srcdir)/adapters/vtk \
	$(VTK_CPPFLAGS) $(NIFTI_CFLAGS)
examples_halo_vtk_CXXFLAGS = $(AM_CXXFLAGS) -Wno-deprecated-copy -Wno-extra-semi
examples_halo_vtk_LDADD = $(HALO_TOOL_LIBS) $(VTK_LIBS) $(NIFTI_LIBS)
endif
