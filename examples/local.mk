# Example hosts (shaders and their C side), the built-in volume, image output, halo-render.
HALO_HOST_SHADERS = examples/hosts/raycast.vert examples/hosts/raycast.frag examples/hosts/probe.frag \
	examples/hosts/slice.vert examples/hosts/slice.frag examples/hosts/slab.frag
EXTRA_DIST += $(HALO_HOST_SHADERS)
BUILT_SOURCES += examples/hosts/embedded_hosts.c
CLEANFILES += examples/hosts/embedded_hosts.c

examples/hosts/embedded_hosts.c: $(HALO_HOST_SHADERS) $(top_srcdir)/build-aux/embed.sh
	$(AM_V_GEN)$(MKDIR_P) examples/hosts && \
	$(SHELL) $(top_srcdir)/build-aux/embed.sh halo_embedded_hosts $@ $(top_srcdir) $(HALO_HOST_SHADERS)

noinst_LTLIBRARIES += examples/libhalo-hosts.la
examples_libhalo_hosts_la_SOURCES = examples/hosts/raycast.c examples/hosts/raycast.h \
	examples/hosts/slice.c examples/hosts/slice.h examples/hosts/slab.c examples/hosts/slab.h \
	examples/volume.c examples/volume.h examples/image_write.cc examples/image_write.h
nodist_examples_libhalo_hosts_la_SOURCES = examples/hosts/embedded_hosts.c
examples_libhalo_hosts_la_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples $(OIIO_CFLAGS)
examples_libhalo_hosts_la_LIBADD = $(OIIO_LIBS)

HALO_TOOL_LIBS = examples/libhalo-hosts.la libhalo/libhalo-core.la libhalo/libhalo-headless.la -lm

# halo-render: volumes from NIfTI and raw files (volume_io), and its default scene
# embedded from examples/scenes/default.json (one source for the file and the binary).
HALO_EMBEDDED_SCENES = examples/scenes/default.json
BUILT_SOURCES += examples/embedded_scenes.c
CLEANFILES += examples/embedded_scenes.c
examples/embedded_scenes.c: $(HALO_EMBEDDED_SCENES) $(top_srcdir)/build-aux/embed.sh
	$(AM_V_GEN)$(MKDIR_P) examples && \
	$(SHELL) $(top_srcdir)/build-aux/embed.sh halo_embedded_scenes $@ $(top_srcdir) $(HALO_EMBEDDED_SCENES)

bin_PROGRAMS += examples/halo-render
examples_halo_render_SOURCES = examples/halo-render.c examples/volume_io.c examples/volume_io.h
nodist_examples_halo_render_SOURCES = examples/embedded_scenes.c
nodist_EXTRA_examples_halo_render_SOURCES = build-aux/force-cxx-link.cc
examples_halo_render_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples $(NIFTI_CFLAGS) $(JANSSON_CFLAGS)
examples_halo_render_CFLAGS = $(AM_CFLAGS) -pthread
examples_halo_render_LDADD = $(HALO_TOOL_LIBS) $(NIFTI_LIBS) $(JANSSON_LIBS) -lpthread
dist_man_MANS += examples/halo-render.1

HALO_SCENES = examples/scenes/default.json examples/scenes/plain.json examples/scenes/boundary-silhouette.json \
	examples/scenes/sketch.json examples/scenes/tone.json examples/scenes/distance.json \
	examples/scenes/orientation.json examples/scenes/color-cue.json \
	examples/scenes/halo-delta-0.70.json examples/scenes/halo-delta-0.80.json \
	examples/scenes/halo-delta-0.90.json examples/scenes/halo-delta-0.95.json \
	examples/scenes/halo-emissive.json examples/scenes/halo-occlusive.json examples/scenes/halo-directional.json \
	examples/scenes/halo-focus.json examples/scenes/halo-multi.json examples/scenes/halo-transparent.json \
	examples/scenes/halo-cartoon.json examples/scenes/mri-head.json
EXTRA_DIST += $(HALO_SCENES)

# Lines (Everts et al. 2009, docs/lines.md): the line host, line data and halo-lines.
HALO_HOST_SHADERS += examples/hosts/line.vert examples/hosts/line.frag \
	examples/hosts/line_probe.vert examples/hosts/line_probe.frag
examples_libhalo_hosts_la_SOURCES += examples/hosts/lines.c examples/hosts/lines.h \
	examples/linegen.c examples/linegen.h
bin_PROGRAMS += examples/halo-lines
examples_halo_lines_SOURCES = examples/halo-lines.c validate/conform_lines.c validate/conform_lines.h
nodist_EXTRA_examples_halo_lines_SOURCES = build-aux/force-cxx-link.cc
examples_halo_lines_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples -I$(top_srcdir)/validate
examples_halo_lines_LDADD = $(HALO_TOOL_LIBS)
HALO_SCENES += examples/scenes/lines-default.json examples/scenes/lines-knots.json
EXTRA_DIST += docs/lines.md docs/polyline-format.md docs/stages/line_strip.md docs/stages/line_halo.md
