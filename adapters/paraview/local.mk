# adapters/paraview/: libhalo in ParaView (docs/distributed.md). The HaloVolume plugin adds
# the "Halo Volume" representation of image data (vtkHaloVolumeRepresentation, on top of
# libhalo-vtk); halo_pvbatch.py renders with it under pvbatch on any number of MPI ranks.
# ParaView plugins are built with ParaView's CMake package: make runs CMake in
# adapters/paraview/build with the flags configure tried it with (configure runs the same
# CMake configure in a scratch folder and leaves the plugin out when it fails; setup.sh
# installs paraview-dev and the development packages its CMake package needs).
paraview_sources = adapters/paraview/CMakeLists.txt adapters/paraview/uses.cmake adapters/paraview/Plugin/CMakeLists.txt \
	adapters/paraview/Plugin/paraview.plugin adapters/paraview/HaloRepresentations/CMakeLists.txt \
	adapters/paraview/HaloRepresentations/vtk.module adapters/paraview/HaloRepresentations/HaloVolume.xml \
	adapters/paraview/HaloRepresentations/vtkHaloVolumeRepresentation.h \
	adapters/paraview/HaloRepresentations/vtkHaloVolumeRepresentation.cxx
EXTRA_DIST += $(paraview_sources) adapters/paraview/halo_pvbatch.py
dist_noinst_SCRIPTS += adapters/paraview/halo_pvbatch.py

if HALO_HAVE_PARAVIEW
paraview_build = adapters/paraview/build
# where the plugin lands, in the build tree and installed
paraview_plugin = $(paraview_build)/lib/paraview-plugins/HaloVolume/HaloVolume.so
paraview_plugindir = $(pkglibdir)/paraview
all-local: $(paraview_build)/stamp
$(paraview_build)/stamp: $(paraview_sources:%=$(srcdir)/%) adapters/vtk/halo_vtk.cxx adapters/vtk/halo_vtk.h \
		libhalo/libhalo.la
	@mkdir -p $(paraview_build)
	$(AM_V_GEN)$(CMAKE) -S $(srcdir)/adapters/paraview -B $(paraview_build) $(HALO_PARAVIEW_CMAKE_FLAGS) \
		-DHALO_SOURCE_DIR=$(abs_top_srcdir) -DHALO_LIBRARY=$(abs_top_builddir)/libhalo/.libs/libhalo.so \
		>$(paraview_build)/cmake.log 2>&1 || \
		{ cat $(paraview_build)/cmake.log; exit 1; }
	$(AM_V_at)$(CMAKE) --build $(paraview_build) >$(paraview_build)/build.log 2>&1 || \
		{ cat $(paraview_build)/build.log; exit 1; }
	$(AM_V_at)test -f $(paraview_plugin) && touch $@
install-exec-local:
	$(MKDIR_P) $(DESTDIR)$(paraview_plugindir)
	$(INSTALL_PROGRAM) $(paraview_plugin) $(DESTDIR)$(paraview_plugindir)/HaloVolume.so
uninstall-local:
	rm -f $(DESTDIR)$(paraview_plugindir)/HaloVolume.so
clean-local:
	rm -rf $(paraview_build)
endif
