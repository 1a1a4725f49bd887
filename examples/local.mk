# examples/: what a host renderer does with libhalo, and the tools built on it. The
# example hosts (shaders and their C side, libhalo-hosts), the built-in volume, volume
# files and image output; halo-render, halo-view, halo-lines, halo-feature and
# halo-outline; the example scenes. halo-lines and halo-feature print their conformance
# rows through validate/'s harness (conform_harness.c) and family files.
HALO_HOST_SHADERS = examples/hosts/raycast.vert examples/hosts/raycast.frag examples/hosts/probe.frag \
	examples/hosts/slice.vert examples/hosts/slice.frag examples/hosts/slab.frag \
	examples/hosts/webgl_caster.frag examples/hosts/exit_point_caster.frag examples/hosts/exit_points.vert \
	examples/hosts/exit_points.frag examples/hosts/tf2d_caster.frag examples/hosts/mip_iso_caster.frag \
	examples/hosts/gradient.frag
EXTRA_DIST += $(HALO_HOST_SHADERS)
BUILT_SOURCES += examples/hosts/embedded_hosts.c
CLEANFILES += examples/hosts/embedded_hosts.c

examples/hosts/embedded_hosts.c: $(HALO_HOST_SHADERS) $(top_srcdir)/build-aux/embed.sh $(top_srcdir)/examples/local.mk
	$(AM_V_GEN)$(MKDIR_P) examples/hosts && \
	$(SHELL) $(top_srcdir)/build-aux/embed.sh halo_embedded_hosts $@ $(top_srcdir) $(HALO_HOST_SHADERS)

noinst_LTLIBRARIES += examples/libhalo-hosts.la
examples_libhalo_hosts_la_SOURCES = examples/hosts/raycast.c examples/hosts/raycast.h \
	examples/hosts/host_common.c examples/hosts/host_common.h \
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

# Its --max-error runs the error budget of validate/bench_budget.c.

bin_PROGRAMS += examples/halo-render
examples_halo_render_SOURCES = examples/halo-render.c examples/volume_io.c examples/volume_io.h \
	examples/json_file.c examples/json_file.h \
	validate/bench_run.c validate/bench_run.h validate/bench_budget.c validate/bench_budget.h
nodist_examples_halo_render_SOURCES = examples/embedded_scenes.c
nodist_EXTRA_examples_halo_render_SOURCES = build-aux/force-cxx-link.cc
examples_halo_render_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples -I$(top_srcdir)/validate \
	$(NIFTI_CFLAGS) $(JANSSON_CFLAGS)
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
	examples/scenes/halo-cartoon.json examples/scenes/mri-head.json examples/scenes/mri-vtk.json \
	examples/scenes/feature-halos.json examples/scenes/feature-volumetric.json
EXTRA_DIST += $(HALO_SCENES)

# Lines (Everts et al. 2009, docs/lines.md): the line host, line data and halo-lines.
HALO_HOST_SHADERS += examples/hosts/line.vert examples/hosts/line.frag \
	examples/hosts/line_probe.vert examples/hosts/line_probe.frag
examples_libhalo_hosts_la_SOURCES += examples/hosts/lines.c examples/hosts/lines.h \
	examples/linegen.c examples/linegen.h
bin_PROGRAMS += examples/halo-lines
examples_halo_lines_SOURCES = examples/halo-lines.c validate/conform_lines.c validate/conform_lines.h \
	validate/conform_harness.c validate/conform_harness.h
nodist_EXTRA_examples_halo_lines_SOURCES = build-aux/force-cxx-link.cc
examples_halo_lines_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples -I$(top_srcdir)/validate
examples_halo_lines_LDADD = $(HALO_TOOL_LIBS)
HALO_SCENES += examples/scenes/lines-default.json examples/scenes/lines-knots.json

# halo-view: the interactive viewer (GLFW window; docs/halo-view.md). Built when
# configure finds GLFW 3 (libglfw3-dev); its sources and manual are distributed always.
if HALO_HAVE_GLFW
bin_PROGRAMS += examples/halo-view
dist_man_MANS += examples/halo-view.1
endif
examples_halo_view_SOURCES = examples/halo-view.c examples/volume_io.c examples/volume_io.h \
	examples/json_file.c examples/json_file.h
nodist_examples_halo_view_SOURCES = examples/embedded_scenes.c
nodist_EXTRA_examples_halo_view_SOURCES = build-aux/force-cxx-link.cc
examples_halo_view_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples $(NIFTI_CFLAGS) $(JANSSON_CFLAGS) $(GLFW_CFLAGS)
examples_halo_view_LDADD = $(HALO_TOOL_LIBS) $(NIFTI_LIBS) $(JANSSON_LIBS) $(GLFW_LIBS)

# halo-feature: feature halos (docs/feature-halos.md): render with the halo buffer, the
# measurements (report) and the conformance rows (conform).
bin_PROGRAMS += examples/halo-feature
examples_halo_feature_SOURCES = examples/halo-feature.c examples/volume_io.c examples/volume_io.h \
	validate/conform_feature.c validate/conform_feature.h validate/feature_report.c validate/feature_report.h \
	validate/conform_harness.c validate/conform_harness.h
nodist_EXTRA_examples_halo_feature_SOURCES = build-aux/force-cxx-link.cc
examples_halo_feature_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples -I$(top_srcdir)/validate $(NIFTI_CFLAGS)
examples_halo_feature_LDADD = $(HALO_TOOL_LIBS) $(NIFTI_LIBS)

# Outlines and depth enhancement (Svakhine et al. 2009, docs/outlines.md): halo-outline.
bin_PROGRAMS += examples/halo-outline
examples_halo_outline_SOURCES = examples/halo-outline.c
nodist_EXTRA_examples_halo_outline_SOURCES = build-aux/force-cxx-link.cc
examples_halo_outline_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples -I$(top_srcdir)/libhalo
examples_halo_outline_LDADD = $(HALO_TOOL_LIBS)
HALO_SCENES += examples/scenes/outline-depth.json examples/scenes/outline-mask.json \
	examples/scenes/outline-silhouette.json examples/scenes/outline-normals.json \
	examples/scenes/outline-occluded-hidden.json examples/scenes/outline-occluded-dashed.json \
	examples/scenes/outline-occluded-front.json examples/scenes/outline-colors-user.json \
	examples/scenes/outline-colors-fraction.json examples/scenes/outline-colors-contrast.json examples/scenes/atlas-aal.json \
	examples/scenes/depth-subtle.json examples/scenes/depth-line-fading.json
