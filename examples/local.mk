# examples/: what a host renderer does with libhalo. The example hosts (shaders and their
# C side), the render driver over them (render_driver.c: scene + volume + host + camera
# -> frame, with progress), the built-in volume, volume files, image output and the
# example scenes. It depends on libhalo/ only; validate/ (conformance, bench) and tools/
# (the command-line front ends) build on it.
HALO_HOST_SHADERS = examples/hosts/raycast.vert examples/hosts/raycast.frag examples/hosts/probe.frag \
	examples/hosts/slice.vert examples/hosts/slice.frag examples/hosts/slab.frag \
	examples/hosts/webgl_caster.frag examples/hosts/exit_point_caster.frag examples/hosts/exit_points.vert \
	examples/hosts/exit_points.frag examples/hosts/tf2d_caster.frag examples/hosts/mip_iso_caster.frag \
	examples/hosts/gradient.frag examples/hosts/niivue_caster.frag
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
	examples/volume.c examples/volume.h examples/image_write.cc examples/image_write.h \
	examples/render_driver.c examples/render_driver.h examples/progress.c examples/progress.h
nodist_examples_libhalo_hosts_la_SOURCES = examples/hosts/embedded_hosts.c
examples_libhalo_hosts_la_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples $(OIIO_CFLAGS)
examples_libhalo_hosts_la_CFLAGS = $(AM_CFLAGS) -pthread
examples_libhalo_hosts_la_LIBADD = $(OIIO_LIBS) -lpthread

# The libraries the tools and halo-validate link.
HALO_TOOL_LIBS = examples/libhalo-hosts.la libhalo/libhalo-core.la libhalo/libhalo-headless.la -lm

HALO_SCENES = examples/scenes/default.json examples/scenes/plain.json examples/scenes/boundary-silhouette.json \
	examples/scenes/sketch.json examples/scenes/tone.json examples/scenes/distance.json \
	examples/scenes/orientation.json examples/scenes/color-cue.json \
	examples/scenes/halo-delta-0.70.json examples/scenes/halo-delta-0.80.json \
	examples/scenes/halo-delta-0.90.json examples/scenes/halo-delta-0.95.json \
	examples/scenes/halo-emissive.json examples/scenes/halo-occlusive.json examples/scenes/halo-directional.json \
	examples/scenes/halo-focus.json examples/scenes/halo-multi.json examples/scenes/halo-transparent.json \
	examples/scenes/halo-cartoon.json examples/scenes/mri-head.json examples/scenes/mri-vtk.json examples/scenes/mri-paraview.json \
	examples/scenes/feature-halos.json examples/scenes/feature-volumetric.json examples/scenes/feature-default.json
EXTRA_DIST += $(HALO_SCENES)

# Lines (Everts et al. 2009, docs/lines.md): the line host and line data.
HALO_HOST_SHADERS += examples/hosts/line.vert examples/hosts/line.frag \
	examples/hosts/line_probe.vert examples/hosts/line_probe.frag
examples_libhalo_hosts_la_SOURCES += examples/hosts/lines.c examples/hosts/lines.h \
	examples/linegen.c examples/linegen.h
HALO_SCENES += examples/scenes/lines-default.json examples/scenes/lines-knots.json

# Outline and depth scenes (docs/outlines.md).
HALO_SCENES += examples/scenes/outline-depth.json examples/scenes/outline-mask.json \
	examples/scenes/outline-silhouette.json examples/scenes/outline-normals.json \
	examples/scenes/outline-occluded-hidden.json examples/scenes/outline-occluded-dashed.json \
	examples/scenes/outline-occluded-front.json examples/scenes/outline-colors-user.json \
	examples/scenes/outline-colors-fraction.json examples/scenes/outline-colors-contrast.json examples/scenes/atlas-aal.json \
	examples/scenes/depth-subtle.json examples/scenes/depth-line-fading.json
