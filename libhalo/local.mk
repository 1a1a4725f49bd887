# The library. libhalo-core.la holds everything (tests link it for internal
# symbols); libhalo.la is the installed library exporting only halo_* symbols.
# Installed as <libhalo/halo.h> ($(includedir)/libhalo: no clash with another halo.h);
# libhalo.pc also puts that folder on the path, so #include <halo.h> keeps working.
pkginclude_HEADERS += libhalo/halo.h libhalo/halo_feature.h libhalo/halo_gl_loader.h
noinst_HEADERS += libhalo/diag.h libhalo/strbuf.h libhalo/internal.h libhalo/glsl_lex.h libhalo/glsl_locate.h libhalo/glslang_parse.h libhalo/host_scan.h libhalo/host_check.h libhalo/emit.h \
	libhalo/emu/emu.h libhalo/emu/stages.h libhalo/emu/feature_internal.h libhalo/gl/glfuncs.h libhalo/gl/headless.h

BUILT_SOURCES += libhalo/embedded_modules.c
CLEANFILES += libhalo/embedded_modules.c

# The stages' emulations, a file per stage (outline.c: both outline stages), defining HALO_EMU_STAGE(name) (a per-sample or
# line stage) or HALO_EMU_PASS(module, entry) (each pass of an image stage): the registry's
# lists (libhalo/emu/registry_list.h) are generated from them, so a stage's emulation is
# its file and its line here.
halo_emu_stage_files = \
	libhalo/emu/gradient.c libhalo/emu/opacity_power.c libhalo/emu/boundary.c \
	libhalo/emu/silhouette.c libhalo/emu/orientation_fade.c libhalo/emu/sketch.c \
	libhalo/emu/tone_shading.c libhalo/emu/distance_blend.c libhalo/emu/distance_cue.c \
	libhalo/emu/halo_seed.c libhalo/emu/halo_map.c libhalo/emu/outline.c libhalo/emu/feature_halo.c \
	libhalo/emu/line_strip.c libhalo/emu/line_halo.c libhalo/emu/halo_generate.c
# What needs neither glslang nor desktop GL: the linker, modules, scenes, reflection and
# the emulation (the web package builds these for WebAssembly: adapters/web/local.mk).
halo_portable_files = \
	libhalo/diag.c libhalo/strbuf.c libhalo/glsl_lex.c libhalo/module.c libhalo/library.c \
	libhalo/scene.c libhalo/link.c libhalo/link_entry.c libhalo/emit.c libhalo/host_check.c libhalo/program.c libhalo/segment.c \
	libhalo/prepass.c libhalo/compose.c libhalo/piece_expression.c libhalo/contract.c libhalo/host_scan.c \
	libhalo/target.c libhalo/budget.c \
	libhalo/emu/apply.c libhalo/emu/math.c libhalo/emu/registry.c \
	libhalo/emu/frame.c $(halo_emu_stage_files)

BUILT_SOURCES += libhalo/emu/registry_list.h
CLEANFILES += libhalo/emu/registry_list.h
libhalo/emu/registry_list.h: $(halo_emu_stage_files) $(top_srcdir)/build-aux/emu_registry.sh $(top_srcdir)/libhalo/local.mk
	$(AM_V_GEN)$(MKDIR_P) libhalo/emu && \
	$(SHELL) $(top_srcdir)/build-aux/emu_registry.sh $@ $(top_srcdir) $(halo_emu_stage_files)

noinst_LTLIBRARIES += libhalo/libhalo-core.la
libhalo_libhalo_core_la_SOURCES = $(halo_portable_files) \
	libhalo/validate.c libhalo/check.c libhalo/glsl_locate.c libhalo/setup.c libhalo/glslang_parse.cpp \
	libhalo/gl/glfuncs.c libhalo/gl/runtime.c libhalo/gl/runtime.h libhalo/gl/frame.c libhalo/gl/camera.c \
	libhalo/gl/segments.c libhalo/gl/field.c libhalo/gl/field_atlas.c libhalo/gl/field_atlas.h libhalo/gl/frame.h libhalo/gl/feature_splat.c
nodist_libhalo_libhalo_core_la_SOURCES = libhalo/embedded_modules.c
libhalo_libhalo_core_la_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_builddir)/libhalo/emu -DHALO_BUILDING $(JANSSON_CFLAGS) $(GLSLANG_CFLAGS)
libhalo_libhalo_core_la_CFLAGS = $(AM_CFLAGS) -fvisibility=hidden
# glslang_parse.cpp: glslang's TShader is C++ only. No RTTI, as glslang is built: with it
# UBSan's vptr check would refer to glslang's type information, which its library lacks.
libhalo_libhalo_core_la_CXXFLAGS = $(AM_CXXFLAGS) -fvisibility=hidden -fno-rtti
libhalo_libhalo_core_la_LIBADD = $(JANSSON_LIBS) $(GLSLANG_LIBS)

lib_LTLIBRARIES += libhalo/libhalo.la
libhalo_libhalo_la_SOURCES =
# glslang is C++: link through the C++ linker (automake picks it for a .cc source).
nodist_EXTRA_libhalo_libhalo_la_SOURCES = build-aux/force-cxx-link.cc
libhalo_libhalo_la_LIBADD = libhalo/libhalo-core.la
# A version script, not -export-symbols-regex: with the C++ linker libtool turns the
# regex into -retain-symbols-file, which leaves glslang's symbols in the dynamic table.
libhalo_libhalo_la_LDFLAGS = $(AM_LDFLAGS) -version-info $(HALO_LT_VERSION) -no-undefined \
	-Wl,--version-script=$(top_srcdir)/libhalo/libhalo.map
EXTRA_libhalo_libhalo_la_DEPENDENCIES = libhalo/libhalo.map
EXTRA_DIST += libhalo/libhalo.map

# Headless contexts for the tools and tests (not installed: hosts bring their own context):
# EGL and OSMesa, each when configure finds it (HEADLESS_CPPFLAGS defines HALO_HAVE_EGL,
# HALO_HAVE_OSMESA).
noinst_LTLIBRARIES += libhalo/libhalo-headless.la
libhalo_libhalo_headless_la_SOURCES = libhalo/gl/headless.c
libhalo_libhalo_headless_la_CPPFLAGS = $(AM_CPPFLAGS) $(HEADLESS_CPPFLAGS)
libhalo_libhalo_headless_la_LIBADD = $(HEADLESS_LIBS)
