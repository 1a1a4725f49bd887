# tools/: the command-line front ends over examples/' hosts and render driver: halo-render,
# halo-view, halo-lines, halo-feature and halo-outline. Each keeps only what is its own
# (options through tool_options.c, output, the window); rendering is examples/render_driver.c.
# The tools use validate/ (halo-render --max-error: the error budget; halo-lines and
# halo-feature: their conformance rows through validate/'s harness); nothing below
# depends on tools/.
# halo-render: volumes from NIfTI and raw files (volume_io), and its default scene
# embedded from examples/scenes/default.json (one source for the file and the binary;
# halo-feature's is feature-default.json, halo-lines' lines-default.json).
HALO_EMBEDDED_SCENES = examples/scenes/default.json examples/scenes/feature-default.json \
	examples/scenes/lines-default.json
BUILT_SOURCES += tools/embedded_scenes.c
CLEANFILES += tools/embedded_scenes.c
tools/embedded_scenes.c: $(HALO_EMBEDDED_SCENES) $(top_srcdir)/build-aux/embed.sh $(top_srcdir)/tools/local.mk
	$(AM_V_GEN)$(MKDIR_P) tools && \
	$(SHELL) $(top_srcdir)/build-aux/embed.sh halo_embedded_scenes $@ $(top_srcdir) $(HALO_EMBEDDED_SCENES)

# Its --max-error runs the error budget of validate/bench_budget.c.

bin_PROGRAMS += tools/halo-render
tools_halo_render_SOURCES = tools/halo-render.c tools/tool_options.c tools/tool_options.h examples/volume_io.c examples/volume_io.h \
	examples/json_file.c examples/json_file.h \
	validate/bench_run.c validate/bench_run.h validate/bench_budget.c validate/bench_budget.h
nodist_tools_halo_render_SOURCES = tools/embedded_scenes.c
nodist_EXTRA_tools_halo_render_SOURCES = build-aux/force-cxx-link.cc
tools_halo_render_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples -I$(top_srcdir)/validate \
	$(NIFTI_CFLAGS) $(JANSSON_CFLAGS)
tools_halo_render_CFLAGS = $(AM_CFLAGS) -pthread
tools_halo_render_LDADD = $(HALO_TOOL_LIBS) $(NIFTI_LIBS) $(JANSSON_LIBS) -lpthread
dist_man_MANS += tools/halo-render.1

# halo-lines: lines with halos (Everts et al. 2009, docs/lines.md) through the line host.
bin_PROGRAMS += tools/halo-lines
tools_halo_lines_SOURCES = tools/halo-lines.c tools/tool_options.c tools/tool_options.h validate/conform_lines.c validate/conform_lines.h \
	validate/conform_harness.c validate/conform_harness.h
nodist_tools_halo_lines_SOURCES = tools/embedded_scenes.c
nodist_EXTRA_tools_halo_lines_SOURCES = build-aux/force-cxx-link.cc
tools_halo_lines_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples -I$(top_srcdir)/validate
tools_halo_lines_LDADD = $(HALO_TOOL_LIBS)

# halo-view: the interactive viewer (GLFW window; docs/halo-view.md). Built when
# configure finds GLFW 3 (libglfw3-dev); its sources and manual are distributed always.
if HALO_HAVE_GLFW
bin_PROGRAMS += tools/halo-view
dist_man_MANS += tools/halo-view.1
endif
tools_halo_view_SOURCES = tools/halo-view.c tools/view.h tools/view_scene.c tools/tool_options.c tools/tool_options.h examples/volume_io.c examples/volume_io.h \
	examples/json_file.c examples/json_file.h
nodist_tools_halo_view_SOURCES = tools/embedded_scenes.c
nodist_EXTRA_tools_halo_view_SOURCES = build-aux/force-cxx-link.cc
tools_halo_view_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples $(NIFTI_CFLAGS) $(JANSSON_CFLAGS) $(GLFW_CFLAGS)
tools_halo_view_LDADD = $(HALO_TOOL_LIBS) $(NIFTI_LIBS) $(JANSSON_LIBS) $(GLFW_LIBS)

# halo-feature: feature halos (docs/feature-halos.md): render with the halo buffer, the
# measurements (report) and the conformance rows (conform).
bin_PROGRAMS += tools/halo-feature
tools_halo_feature_SOURCES = tools/halo-feature.c tools/tool_options.c tools/tool_options.h examples/volume_io.c examples/volume_io.h \
	validate/conform_feature.c validate/conform_feature.h validate/feature_report.c validate/feature_report.h \
	validate/conform_harness.c validate/conform_harness.h
nodist_tools_halo_feature_SOURCES = tools/embedded_scenes.c
nodist_EXTRA_tools_halo_feature_SOURCES = build-aux/force-cxx-link.cc
tools_halo_feature_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples -I$(top_srcdir)/validate $(NIFTI_CFLAGS)
tools_halo_feature_LDADD = $(HALO_TOOL_LIBS) $(NIFTI_LIBS)

# Outlines and depth enhancement (Svakhine et al. 2009, docs/outlines.md): halo-outline.
bin_PROGRAMS += tools/halo-outline
tools_halo_outline_SOURCES = tools/halo-outline.c tools/tool_options.c tools/tool_options.h
nodist_EXTRA_tools_halo_outline_SOURCES = build-aux/force-cxx-link.cc
tools_halo_outline_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples -I$(top_srcdir)/libhalo
tools_halo_outline_LDADD = $(HALO_TOOL_LIBS)
