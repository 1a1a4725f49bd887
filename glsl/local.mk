# Stage modules, embedded into the library at build time.
HALO_MODULES = \
	glsl/halo_math.glsl \
	glsl/sample/gradient.glsl \
	glsl/sample/opacity_power.glsl \
	glsl/sample/boundary.glsl \
	glsl/sample/silhouette.glsl \
	glsl/sample/orientation_fade.glsl \
	glsl/sample/sketch.glsl \
	glsl/sample/tone_shading.glsl \
	glsl/sample/distance_blend.glsl \
	glsl/sample/distance_cue.glsl \
	glsl/lines/strip.glsl \
	glsl/lines/halo.glsl \
	glsl/halo/seed.glsl \
	glsl/halo/generate.glsl \
	glsl/halo/map.glsl \
	glsl/outline/feature.glsl \
	glsl/feature/feature_halo.glsl \
	glsl/outline/outlines.glsl

EXTRA_DIST += $(HALO_MODULES)

libhalo/embedded_modules.c: $(HALO_MODULES) $(top_srcdir)/build-aux/embed.sh $(top_srcdir)/glsl/local.mk
	$(AM_V_GEN)$(MKDIR_P) libhalo && \
	$(SHELL) $(top_srcdir)/build-aux/embed.sh halo_embedded_modules $@ $(top_srcdir) \
		$(HALO_MODULES)
