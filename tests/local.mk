# tests/: everything make check runs, laid out as the tree it tests (one axis: the test of
# a file or program is found under its path):
#   tests/libhalo/        libhalo's files (test_link.c for link.c, test_emit.c for emit.c, ...;
#                         exports.sh, install_headers.sh), tests/libhalo/gl/ its GL runtime
#   tests/glsl/           the modules (check_modules.sh)
#   tests/validate/       halo-validate: check, link and its diagnostics, conform, bench rows
#   tests/tools/NAME/     each tool (halo-render, halo-view, halo-lines, halo-feature, halo-outline)
#   tests/examples/       the example hosts (hosts/) and the public-header rule
#   tests/adapters/NAME/  VTK, ParaView, the web package
#   tests/tree/           the whole tree: style, no circles, a clean checkout, setup.sh's packages
#   tests/fuzz/           the fuzz targets, their driver and corpus (replayed here; CI fuzzes)
# and the shared helpers (harness.sh, gl_fixture.h, hostile.h, xrun.sh) and data (tests/data).
# Every test finds its data through $srcdir, so they run from a build directory other
# than the source directory (make distcheck).

# ---- Unit tests: C programs linked with the static core library (internal symbols) ----
HALO_UNIT_TESTS = \
	tests/libhalo/test_module \
	tests/libhalo/test_scene \
	tests/libhalo/test_scene_counts \
	tests/libhalo/test_link \
	tests/libhalo/test_emit \
	tests/libhalo/test_program \
	tests/libhalo/test_prepass \
	tests/libhalo/test_host_check \
	tests/libhalo/test_compose \
	tests/libhalo/test_host_scan \
	tests/libhalo/test_emu \
	tests/libhalo/test_input_classes \
	tests/libhalo/test_lifetimes \
	tests/libhalo/test_threads \
	tests/libhalo/test_amplify \
	tests/libhalo/test_api_bounds
check_PROGRAMS += $(HALO_UNIT_TESTS) tests/libhalo/test_public
noinst_HEADERS += tests/libhalo/check.h tests/libhalo/link_fixture.h tests/gl_fixture.h

HALO_TEST_CORE_LIBS = libhalo/libhalo-core.la -lm

# A test program is its own .c file (automake's default sources), linked with the core
# library unless it says otherwise (LDADD, the default of every program without its own;
# the tools and libraries all set theirs) and by the C++ linker, glslang in the core being
# C++: HALO_TEST_CXX_LINK names a C++ source that is never built. (Not the libraries'
# build-aux/force-cxx-link.cc: automake refuses one object built both with libtool and
# without.)
LDADD = $(HALO_TEST_CORE_LIBS)
HALO_TEST_CXX_LINK = tests/cxx-link.cc
nodist_EXTRA_tests_libhalo_test_module_SOURCES = $(HALO_TEST_CXX_LINK)
nodist_EXTRA_tests_libhalo_test_scene_SOURCES = $(HALO_TEST_CXX_LINK)
nodist_EXTRA_tests_libhalo_test_scene_counts_SOURCES = $(HALO_TEST_CXX_LINK)
nodist_EXTRA_tests_libhalo_test_compose_SOURCES = $(HALO_TEST_CXX_LINK)
nodist_EXTRA_tests_libhalo_test_link_SOURCES = $(HALO_TEST_CXX_LINK)
nodist_EXTRA_tests_libhalo_test_emit_SOURCES = $(HALO_TEST_CXX_LINK)
nodist_EXTRA_tests_libhalo_test_program_SOURCES = $(HALO_TEST_CXX_LINK)
nodist_EXTRA_tests_libhalo_test_prepass_SOURCES = $(HALO_TEST_CXX_LINK)
nodist_EXTRA_tests_libhalo_test_host_check_SOURCES = $(HALO_TEST_CXX_LINK)
nodist_EXTRA_tests_libhalo_test_host_scan_SOURCES = $(HALO_TEST_CXX_LINK)
nodist_EXTRA_tests_libhalo_test_emu_SOURCES = $(HALO_TEST_CXX_LINK)
nodist_EXTRA_tests_libhalo_test_input_classes_SOURCES = $(HALO_TEST_CXX_LINK)
nodist_EXTRA_tests_libhalo_test_lifetimes_SOURCES = $(HALO_TEST_CXX_LINK)
nodist_EXTRA_tests_libhalo_test_amplify_SOURCES = $(HALO_TEST_CXX_LINK)
nodist_EXTRA_tests_libhalo_test_api_bounds_SOURCES = $(HALO_TEST_CXX_LINK)
# Two threads at once (halo.h, "Threads"); .ci/run also runs it under ThreadSanitizer.
nodist_EXTRA_tests_libhalo_test_threads_SOURCES = $(HALO_TEST_CXX_LINK)
tests_libhalo_test_threads_LDADD = $(HALO_TEST_CORE_LIBS) -lpthread
# The public API only, through the installed-style shared library.
nodist_EXTRA_tests_libhalo_test_public_SOURCES = $(HALO_TEST_CXX_LINK)
tests_libhalo_test_public_LDADD = libhalo/libhalo.la

TESTS += $(HALO_UNIT_TESTS) tests/libhalo/test_public

# Every public function given NULL where it expects an object (one row per HALO_API
# function; the rows are checked against the headers). The GL calls with a valid
# runtime need a headless context.
check_PROGRAMS += tests/libhalo/test_null_api
nodist_EXTRA_tests_libhalo_test_null_api_SOURCES = $(HALO_TEST_CXX_LINK)
tests_libhalo_test_null_api_LDADD = $(HALO_TEST_CORE_LIBS) libhalo/libhalo-headless.la
TESTS += tests/libhalo/test_null_api

# ---- Shell tests: the command-line tools on good and bad input ----
HALO_SHELL_TESTS = \
	tests/glsl/check_modules.sh \
	tests/libhalo/exports.sh \
	tests/libhalo/install_headers.sh \
	tests/validate/conform.sh \
	tests/validate/conform_egl.sh \
	tests/validate/conform_es.sh \
	tests/tools/halo-render/default.sh \
	tests/validate/link_ok.sh \
	tests/validate/missing_file.sh \
	tests/validate/bad_annotation.sh \
	tests/validate/unknown_stage.sh \
	tests/validate/cycle.sh \
	tests/validate/host_no_marker.sh \
	tests/validate/host_diagnostics.sh \
	tests/validate/bad_json.sh \
	tests/validate/out_of_range.sh \
	tests/validate/nonfinite.sh \
	tests/validate/usage.sh \
	tests/validate/conform_list.sh \
	tests/validate/accuracy_doc.sh \
	tests/tree/tree_clean.sh \
	tests/validate/nul_byte.sh \
	tests/validate/directory.sh \
	tests/validate/bom.sh \
	tests/validate/error_limit.sh \
	tests/validate/glsl_diagnostics.sh \
	tests/validate/glslang_agree.sh \
	tests/validate/render_output.sh \
	tests/validate/file_bounds.sh \
	tests/validate/pieces_composed.sh \
	tests/validate/pieces_versions.sh \
	tests/validate/pieces_reflect.sh \
	tests/validate/host_contract_rules.sh \
	tests/examples/public_headers.sh \
	tests/tree/style.sh
TESTS += $(HALO_SHELL_TESTS)

TEST_EXTENSIONS = .sh
SH_LOG_COMPILER = $(SHELL)
AM_TESTS_ENVIRONMENT = \
	srcdir='$(srcdir)'; export srcdir; \
	top_srcdir='$(top_srcdir)'; export top_srcdir; \
	top_builddir='$(top_builddir)'; export top_builddir; \
	HALO_CXX='$(CXX)'; export HALO_CXX; \
	HALO_SANITIZER_FLAGS='$(SANITIZER_FLAGS)'; export HALO_SANITIZER_FLAGS; \
	HALO_VALIDATE='$(abs_top_builddir)/validate/halo-validate'; export HALO_VALIDATE; \
	HALO_RENDER='$(abs_top_builddir)/tools/halo-render'; export HALO_RENDER; \
	HALO_LIBDIR='$(abs_top_builddir)/libhalo'; export HALO_LIBDIR; \
	HALO_HAVE_EGL='$(HALO_HAVE_EGL)'; export HALO_HAVE_EGL; \
	HALO_HAVE_OSMESA='$(HALO_HAVE_OSMESA)'; export HALO_HAVE_OSMESA; \
	LP_NUM_THREADS=2; export LP_NUM_THREADS; \
	MESA_SHADER_CACHE_DISABLE=true; export MESA_SHADER_CACHE_DISABLE; \
	LSAN_OPTIONS="suppressions=$(abs_top_srcdir)/tests/lsan.supp:print_suppressions=0$${LSAN_OPTIONS:+:$$LSAN_OPTIONS}"; \
	export LSAN_OPTIONS; \
	TSAN_OPTIONS="suppressions=$(abs_top_srcdir)/tests/tsan.supp:halt_on_error=1$${TSAN_OPTIONS:+:$$TSAN_OPTIONS}"; \
	export TSAN_OPTIONS;

# Test data: scenes, hosts and modules, good and bad.
HALO_TEST_FILES = \
	tests/validate/common.sh tests/harness.sh \
	tests/validate/conform_backend.sh \
	tests/lsan.supp \
	tests/tsan.supp \
	tests/data/hosts/minimal.frag \
	tests/data/glslang/own_version.frag tests/data/glslang/no_version.frag \
	tests/data/glslang/es_missing_precision.frag tests/data/glslang/version_after_comments.frag \
	tests/data/glslang/cr_endings.frag tests/data/glslang/cr_endings_error.frag \
	tests/data/glslang/include/include_main.frag tests/data/glslang/include/include_part.h \
	tests/data/glslang/error_then_more.frag tests/data/glslang/compile_and_link.frag \
	tests/data/glslang/line_directive.frag tests/data/glslang/line_file.frag \
	tests/data/glslang/syntax_stops.frag tests/data/glslang/macro_stops.frag tests/data/glslang/compiler_crash.vert \
	tests/data/glslang/printf_escapes.frag tests/data/glslang/line_file_sum.frag \
	tests/data/hosts/no_marker.frag \
	tests/data/hosts/marker_commented.frag \
	tests/data/hosts/marker_es_only.frag \
	tests/data/hosts/no_apply.frag \
	tests/data/hosts/line_directive.frag \
	tests/data/hosts/macro_clash.frag \
	tests/data/hosts/no_location.frag \
	tests/data/hosts/host.glsl \
	tests/data/scenes/seed.json \
	tests/data/modules/bad_param.glsl \
	tests/data/modules/cycle_a.glsl \
	tests/data/modules/cycle_b.glsl \
	tests/data/scenes/good.json \
	tests/data/scenes/cycle.json \
	tests/data/scenes/unknown_stage.json \
	tests/data/scenes/bad_json.json \
	tests/data/scenes/out_of_range.json \
	tests/data/scenes/nan.json \
	tests/data/scenes/huge.json \
	tests/data/scenes/halo_pieces.json \
	tests/data/composer/template.frag tests/data/composer/compose.awk
EXTRA_DIST += $(HALO_SHELL_TESTS) $(HALO_TEST_FILES)

# ---- Fuzz targets (tests/fuzz): make check replays the seed corpus and a fixed set of
# deterministic mutations of it; tests/fuzz/run-libfuzzer.sh fuzzes for real (CI). ----
HALO_FUZZ_TARGETS = tests/fuzz/fuzz_module tests/fuzz/fuzz_scene tests/fuzz/fuzz_host tests/fuzz/fuzz_volume \
	tests/fuzz/fuzz_polyline
check_PROGRAMS += $(HALO_FUZZ_TARGETS)
noinst_HEADERS += tests/fuzz/fuzz.h
tests_fuzz_fuzz_module_SOURCES = tests/fuzz/fuzz_module.c tests/fuzz/driver.c
nodist_EXTRA_tests_fuzz_fuzz_module_SOURCES = $(HALO_TEST_CXX_LINK)
tests_fuzz_fuzz_scene_SOURCES = tests/fuzz/fuzz_scene.c tests/fuzz/driver.c
nodist_EXTRA_tests_fuzz_fuzz_scene_SOURCES = $(HALO_TEST_CXX_LINK)
tests_fuzz_fuzz_host_SOURCES = tests/fuzz/fuzz_host.c tests/fuzz/driver.c
nodist_EXTRA_tests_fuzz_fuzz_host_SOURCES = $(HALO_TEST_CXX_LINK)
tests_fuzz_fuzz_volume_SOURCES = tests/fuzz/fuzz_volume.c tests/fuzz/driver.c examples/volume_io.c
tests_fuzz_fuzz_volume_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/tests/fuzz -I$(top_srcdir)/examples $(NIFTI_CFLAGS)
tests_fuzz_fuzz_volume_LDADD = $(NIFTI_LIBS)
tests_fuzz_fuzz_polyline_SOURCES = tests/fuzz/fuzz_polyline.c tests/fuzz/driver.c examples/linegen.c
tests_fuzz_fuzz_polyline_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples
nodist_EXTRA_tests_fuzz_fuzz_polyline_SOURCES = $(HALO_TEST_CXX_LINK)
TESTS += tests/fuzz/replay.sh
EXTRA_DIST += tests/fuzz/replay.sh tests/fuzz/run-libfuzzer.sh tests/fuzz/corpus

# ---- Lines (Everts et al. 2009): halo-lines renders, conformance rows, bad polylines ----
HALO_LINES_TESTS = \
	tests/tools/halo-lines/depth_gap.sh \
	tests/tools/halo-lines/conform.sh \
	tests/tools/halo-lines/render.sh \
	tests/tools/halo-lines/bad_polyline.sh
TESTS += $(HALO_LINES_TESTS)
EXTRA_DIST += $(HALO_LINES_TESTS) tests/tools/halo-lines/common.sh

# ---- halo-render: every example scene, --no-halos, volume files (NIfTI, raw), the MRI
# head of mricron-data (skipped without it), bad volumes and options, --max-error, feature
# halos and outline post passes ----
HALO_RENDER_TESTS = \
	tests/tools/halo-render/scenes.sh \
	tests/tools/halo-render/no_halos.sh \
	tests/tools/halo-render/volumes.sh \
	tests/tools/halo-render/bad_volumes.sh \
	tests/tools/halo-render/nifti_header.sh \
	tests/tools/halo-render/volume_memory.sh \
	tests/tools/halo-render/mri.sh \
	tests/tools/halo-render/max_error.sh \
	tests/tools/halo-render/bench.sh \
	tests/tools/halo-render/features.sh \
	tests/tools/halo-render/gradient_format.sh \
	tests/tools/halo-render/es.sh \
	tests/tools/halo-render/field_cap.sh
TESTS += $(HALO_RENDER_TESTS)
EXTRA_DIST += $(HALO_RENDER_TESTS) tests/tools/halo-render/common.sh \
	tests/data/volumes/sphere.nii tests/data/volumes/sphere.nii.gz

# ---- halo-view, the interactive viewer (needs GLFW and xvfb-run, else skipped): its
# screenshot against halo-render's image of the same view, keys and saved scenes, and
# reloading an edited or broken scene file ----
HALO_VIEW_TESTS = \
	tests/tools/halo-view/screenshot.sh \
	tests/tools/halo-view/keys.sh \
	tests/tools/halo-view/reload.sh
TESTS += $(HALO_VIEW_TESTS)
EXTRA_DIST += $(HALO_VIEW_TESTS) tests/tools/halo-view/common.sh
check_PROGRAMS += tests/tools/halo-view/image_compare
tests_tools_halo_view_image_compare_SOURCES = tests/tools/halo-view/image_compare.cc
tests_tools_halo_view_image_compare_CPPFLAGS = $(AM_CPPFLAGS) $(OIIO_CFLAGS)
tests_tools_halo_view_image_compare_LDADD = $(OIIO_LIBS)
if HALO_HAVE_GLFW
AM_TESTS_ENVIRONMENT += HALO_VIEW='$(abs_top_builddir)/tools/halo-view'; export HALO_VIEW;
endif
AM_TESTS_ENVIRONMENT += HALO_IMAGE_COMPARE='$(abs_top_builddir)/tests/tools/halo-view/image_compare'; export HALO_IMAGE_COMPARE;

# ---- Hard cases (docs/hard-cases.md): whole renders on the GPU path (slice host, slab
# ray caster) against the emulation on fragile inputs, and the conformance rows that
# already hold per-stage hard inputs ----
check_PROGRAMS += tests/examples/hosts/test_hard_render
# The programs that drive the example hosts: examples/ and validate/ headers, the tools'
# libraries.
HALO_TEST_HOST_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples -I$(top_srcdir)/validate
tests_examples_hosts_test_hard_render_SOURCES = tests/examples/hosts/test_hard_render.c validate/conform_slice.c \
	validate/conform_harness.c
tests_examples_hosts_test_hard_render_CPPFLAGS = $(HALO_TEST_HOST_CPPFLAGS)
nodist_EXTRA_tests_examples_hosts_test_hard_render_SOURCES = $(HALO_TEST_CXX_LINK)
tests_examples_hosts_test_hard_render_LDADD = $(HALO_TOOL_LIBS)
check_PROGRAMS += tests/libhalo/test_budget
nodist_EXTRA_tests_libhalo_test_budget_SOURCES = $(HALO_TEST_CXX_LINK)
TESTS += tests/examples/hosts/test_hard_render tests/libhalo/test_budget tests/validate/hard_rows.sh
EXTRA_DIST += tests/validate/hard_rows.sh

# ---- Feature halos (Svakhine & Ebert 2003, docs/feature-halos.md): conformance rows of
# the GPU halo buffer and the stage, and the side-by-side scenes ----
HALO_FEATURE_TESTS = tests/tools/halo-feature/conform.sh tests/tools/halo-feature/render.sh
TESTS += $(HALO_FEATURE_TESTS)
EXTRA_DIST += $(HALO_FEATURE_TESTS) glsl/feature/feature_halo.glsl
AM_TESTS_ENVIRONMENT += HALO_FEATURE='$(abs_top_builddir)/tools/halo-feature'; export HALO_FEATURE;

# ---- Outlines and depth enhancement (Svakhine et al. 2009, docs/outlines.md): every
# outline/depth scene through halo-outline (GPU post passes against their emulation),
# and the occlusion styles give different images ----
HALO_OUTLINE_TESTS = tests/tools/halo-outline/render.sh tests/tools/halo-outline/occlusion.sh tests/tools/halo-outline/atlas.sh
TESTS += $(HALO_OUTLINE_TESTS)
EXTRA_DIST += $(HALO_OUTLINE_TESTS) tests/tools/halo-outline/common.sh
AM_TESTS_ENVIRONMENT += HALO_OUTLINE='$(abs_top_builddir)/tools/halo-outline'; export HALO_OUTLINE;

# ---- Host contract 2 (docs/host-contract.md, "Segmented ray casting"): the ray caster in
# depth segments against one draw and against the slab host; the single-pass diagnostics ----
check_PROGRAMS += tests/libhalo/gl/test_segments
tests_libhalo_gl_test_segments_CPPFLAGS = $(HALO_TEST_HOST_CPPFLAGS)
nodist_EXTRA_tests_libhalo_gl_test_segments_SOURCES = $(HALO_TEST_CXX_LINK)
tests_libhalo_gl_test_segments_LDADD = $(HALO_TOOL_LIBS)
TESTS += tests/libhalo/gl/test_segments
# ---- halo_gl_desc.count_fetches: the passes' fetches against their definitions ----
check_PROGRAMS += tests/libhalo/gl/test_fetch_count
tests_libhalo_gl_test_fetch_count_CPPFLAGS = $(HALO_TEST_HOST_CPPFLAGS)
nodist_EXTRA_tests_libhalo_gl_test_fetch_count_SOURCES = $(HALO_TEST_CXX_LINK)
tests_libhalo_gl_test_fetch_count_LDADD = $(HALO_TOOL_LIBS)
TESTS += tests/libhalo/gl/test_fetch_count
TESTS += tests/libhalo/gl/link_cli.sh
EXTRA_DIST += tests/libhalo/gl/link_cli.sh tests/data/hosts/single_pass.frag
TESTS += tests/libhalo/gl/render_cli.sh
EXTRA_DIST += tests/libhalo/gl/render_cli.sh

# ---- tree_clean.sh: what the build writes is neither tracked nor left unignored; it
# checks the names make builds, so it does not depend on the order the tests run in ----
AM_TESTS_ENVIRONMENT += HALO_BUILD_OUTPUTS='$(bin_PROGRAMS) $(check_PROGRAMS) $(BUILT_SOURCES) \
	$(lib_LTLIBRARIES) $(noinst_LTLIBRARIES) $(CLEANFILES)'; export HALO_BUILD_OUTPUTS;

# ---- The example hosts in the styles of the wild (host contract 2, examples/hosts/): link
# and validate per target, volumetric halos, outlines and feature halos through each, K
# forced segments against one draw, the exit-point caster against the ray caster, and the
# MIP variant's refusal of stages (HOST_COMPOSITING) ----
check_PROGRAMS += tests/examples/hosts/test_hosts
tests_examples_hosts_test_hosts_CPPFLAGS = $(HALO_TEST_HOST_CPPFLAGS)
nodist_EXTRA_tests_examples_hosts_test_hosts_SOURCES = $(HALO_TEST_CXX_LINK)
tests_examples_hosts_test_hosts_LDADD = $(HALO_TOOL_LIBS)
TESTS += tests/examples/hosts/test_hosts

# ray@ortho at 128 and 256 pixels a side (issue 26).
TESTS += tests/validate/conform_sizes.sh
EXTRA_DIST += tests/validate/conform_sizes.sh

# libhalo's runtime in a host's hostile GL state (issue 26): the slice and slab hosts'
# frame calls, the feature buffer, the ray caster; on OpenGL ES contexts too.
check_PROGRAMS += tests/examples/hosts/test_host_state
tests_examples_hosts_test_host_state_CPPFLAGS = $(HALO_TEST_HOST_CPPFLAGS)
nodist_EXTRA_tests_examples_hosts_test_host_state_SOURCES = $(HALO_TEST_CXX_LINK)
tests_examples_hosts_test_host_state_LDADD = $(HALO_TOOL_LIBS)
TESTS += tests/examples/hosts/test_host_state tests/examples/hosts/host_state_es.sh
EXTRA_DIST += tests/examples/hosts/host_state_es.sh tests/hostile.h

# The gradient texture built on the GPU against the CPU's central differences.
check_PROGRAMS += tests/examples/hosts/test_exact_work
tests_examples_hosts_test_exact_work_CPPFLAGS = $(HALO_TEST_HOST_CPPFLAGS)
nodist_EXTRA_tests_examples_hosts_test_exact_work_SOURCES = $(HALO_TEST_CXX_LINK)
tests_examples_hosts_test_exact_work_LDADD = $(HALO_TOOL_LIBS)
TESTS += tests/examples/hosts/test_exact_work

# ---- VTK (adapters/vtk, examples/halo-vtk): skipped (77) when configure found no VTK ----
TESTS += tests/adapters/vtk/vtk.sh
EXTRA_DIST += tests/adapters/vtk/vtk.sh tests/xrun.sh
EXTRA_DIST += tests/adapters/vtk/test_vtk_lifetimes.cxx tests/adapters/vtk/test_vtk_two_volumes.cxx tests/adapters/vtk/test_ball.h
if HALO_HAVE_VTK
AM_TESTS_ENVIRONMENT += HALO_VTK='$(abs_top_builddir)/examples/halo-vtk'; export HALO_VTK;
# the adapter's lifetimes and misuse, run by tests/adapters/vtk/vtk.sh on its X server
check_PROGRAMS += tests/adapters/vtk/test_vtk_lifetimes
tests_adapters_vtk_test_vtk_lifetimes_SOURCES = tests/adapters/vtk/test_vtk_lifetimes.cxx adapters/vtk/halo_vtk.cxx
HALO_VTK_TEST_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/adapters/vtk $(VTK_CPPFLAGS)
HALO_VTK_TEST_CXXFLAGS = $(AM_CXXFLAGS) -Wno-deprecated-copy -Wno-extra-semi
HALO_VTK_TEST_LDADD = $(HALO_TOOL_LIBS) $(VTK_LIBS)
tests_adapters_vtk_test_vtk_lifetimes_CPPFLAGS = $(HALO_VTK_TEST_CPPFLAGS)
tests_adapters_vtk_test_vtk_lifetimes_CXXFLAGS = $(HALO_VTK_TEST_CXXFLAGS)
tests_adapters_vtk_test_vtk_lifetimes_LDADD = $(HALO_VTK_TEST_LDADD)
AM_TESTS_ENVIRONMENT += HALO_VTK_LIFETIMES='$(abs_top_builddir)/tests/adapters/vtk/test_vtk_lifetimes'; export HALO_VTK_LIFETIMES;
# two volumes in one renderer: the depth order with the adapter on either one
check_PROGRAMS += tests/adapters/vtk/test_vtk_two_volumes
tests_adapters_vtk_test_vtk_two_volumes_SOURCES = tests/adapters/vtk/test_vtk_two_volumes.cxx adapters/vtk/halo_vtk.cxx
tests_adapters_vtk_test_vtk_two_volumes_CPPFLAGS = $(HALO_VTK_TEST_CPPFLAGS)
tests_adapters_vtk_test_vtk_two_volumes_CXXFLAGS = $(HALO_VTK_TEST_CXXFLAGS)
tests_adapters_vtk_test_vtk_two_volumes_LDADD = $(HALO_VTK_TEST_LDADD)
AM_TESTS_ENVIRONMENT += HALO_VTK_TWO_VOLUMES='$(abs_top_builddir)/tests/adapters/vtk/test_vtk_two_volumes'; export HALO_VTK_TWO_VOLUMES;
endif

# ---- The house: no circles between the C files of a folder (issue 12) ----
TESTS += tests/tree/no_circles.sh
EXTRA_DIST += tests/tree/no_circles.sh tests/tools/circles.py

# ---- ParaView (adapters/paraview): skipped (77) without the plugin, pvbatch or mpirun ----
TESTS += tests/adapters/paraview/paraview.sh
EXTRA_DIST += tests/adapters/paraview/paraview.sh
AM_TESTS_ENVIRONMENT += HALO_PVBATCH_SCRIPT='$(abs_top_srcdir)/adapters/paraview/halo_pvbatch.py'; export HALO_PVBATCH_SCRIPT;
if HALO_HAVE_PARAVIEW
AM_TESTS_ENVIRONMENT += HALO_PARAVIEW_PLUGIN='$(abs_top_builddir)/$(paraview_plugin)'; export HALO_PARAVIEW_PLUGIN;
endif

# ---- setup.sh installs everything the build uses (issue 24): each library linked and
# header included, by configure's, CMake's and ldd's account, is in a package setup.sh
# installs or one of those depends on; skipped (77) without dpkg and apt ----
TESTS += tests/tree/setup_deps.sh
EXTRA_DIST += tests/tree/setup_deps.sh

# ---- The web package (adapters/web): its JavaScript API under node against the native
# linker, and the example ray caster in headless Chromium against halo-render (skipped
# when configure left the web package out, or without chromium or puppeteer-core) ----
HALO_WEB_TESTS = tests/adapters/web/api.sh tests/adapters/web/browser.sh
# NiiVue's frame drawn by libhalo's C runtime, which browser.mjs compares NiiVue's with
check_PROGRAMS += tests/adapters/web/niivue_reference
tests_adapters_web_niivue_reference_CPPFLAGS = $(HALO_TEST_HOST_CPPFLAGS)
nodist_EXTRA_tests_adapters_web_niivue_reference_SOURCES = $(HALO_TEST_CXX_LINK)
tests_adapters_web_niivue_reference_LDADD = $(HALO_TOOL_LIBS)
TESTS += $(HALO_WEB_TESTS)
EXTRA_DIST += $(HALO_WEB_TESTS) tests/adapters/web/api.test.mjs tests/adapters/web/browser.mjs tests/adapters/web/raycast.html tests/adapters/web/warnings.mjs tests/adapters/web/nifti.mjs tests/adapters/web/three.html tests/adapters/web/niivue.html tests/adapters/web/vtkjs.html \
	tests/adapters/web/package.json tests/adapters/web/package-lock.json
AM_TESTS_ENVIRONMENT += HALO_HAVE_WEB='$(HALO_HAVE_WEB)'; export HALO_HAVE_WEB; \
	HALO_WEB_PACKAGE='$(abs_top_builddir)/adapters/web/package'; export HALO_WEB_PACKAGE; \
	HALO_WEB_NIIVUE_REFERENCE='$(abs_top_builddir)/tests/adapters/web/niivue_reference'; export HALO_WEB_NIIVUE_REFERENCE; \
	NODE='$(NODE)'; export NODE;
