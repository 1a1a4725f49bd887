# Example hosts (shaders and their C side), the built-in volume, image output, halo-render.
HALO_HOST_SHADERS = examples/hosts/raycast.vert examples/hosts/raycast.frag examples/hosts/probe.frag
EXTRA_DIST += $(HALO_HOST_SHADERS)
BUILT_SOURCES += examples/hosts/embedded_hosts.c
CLEANFILES += examples/hosts/embedded_hosts.c

examples/hosts/embedded_hosts.c: $(HALO_HOST_SHADERS) $(top_srcdir)/build-aux/embed.sh
	$(AM_V_GEN)$(MKDIR_P) examples/hosts && \
	$(SHELL) $(top_srcdir)/build-aux/embed.sh halo_embedded_hosts $@ $(top_srcdir) $(HALO_HOST_SHADERS)

noinst_LTLIBRARIES += examples/libhalo-hosts.la
examples_libhalo_hosts_la_SOURCES = examples/hosts/raycast.c examples/hosts/raycast.h \
	examples/volume.c examples/volume.h examples/image_write.cc examples/image_write.h
nodist_examples_libhalo_hosts_la_SOURCES = examples/hosts/embedded_hosts.c
examples_libhalo_hosts_la_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples $(OIIO_CFLAGS)
examples_libhalo_hosts_la_LIBADD = $(OIIO_LIBS)

HALO_TOOL_LIBS = examples/libhalo-hosts.la libhalo/libhalo-core.la libhalo/libhalo-headless.la -lm

bin_PROGRAMS += examples/halo-render
examples_halo_render_SOURCES = examples/halo-render.c
nodist_EXTRA_examples_halo_render_SOURCES = build-aux/force-cxx-link.cc
examples_halo_render_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples
examples_halo_render_LDADD = $(HALO_TOOL_LIBS)

HALO_SCENES = examples/scenes/default.json examples/scenes/plain.json examples/scenes/boundary-silhouette.json \
	examples/scenes/sketch.json examples/scenes/tone.json examples/scenes/distance.json \
	examples/scenes/orientation.json examples/scenes/color-cue.json
EXTRA_DIST += $(HALO_SCENES)
