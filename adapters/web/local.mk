# The web package (docs/hosts/web.md): libhalo's linker, modules, scenes, reflection,
# live parameters, line map and emulation in WebAssembly (emscripten, from the same
# sources as the native library, without glslang: the browser's WebGL compiler checks the
# shaders), and its JavaScript API. jansson is built for WebAssembly from Debian's source
# package (adapters/web/deps.sh). The package is assembled in $(WEB_PACKAGE): npm pack
# there makes the installable tarball.
web_package_files = adapters/web/halo_web.c adapters/web/libhalo.mjs adapters/web/libhalo.d.ts \
	adapters/web/three.mjs adapters/web/three.d.ts adapters/web/niivue.mjs adapters/web/niivue.d.ts \
	adapters/web/vtkjs.mjs adapters/web/vtkjs.d.ts \
	adapters/web/package.json adapters/web/README.md
EXTRA_DIST += $(web_package_files) adapters/web/deps.sh adapters/web/local.mk

if HALO_HAVE_WEB
WEB_PACKAGE = adapters/web/package
# libhalo-core's sources that need no glslang and no desktop GL (libhalo/local.mk)
web_core_files = $(halo_portable_files)
WEB_DEPS = adapters/web/deps
# emscripten's tools run on node and need Debian's node-acorn, which a node of another
# origin does not find by itself
WEB_EMCC = NODE_PATH=/usr/share/nodejs$${NODE_PATH:+:$$NODE_PATH} $(EMCC)
WEB_EXPORTS = _malloc _free _halo_web_init _halo_web_version _halo_web_diagnostics _halo_web_modules _halo_web_link _halo_web_program_destroy _halo_web_program_source _halo_web_program_piece _halo_web_program_reflect _halo_web_program_set _halo_web_map_line \
	_halo_web_gl_create _halo_web_gl_destroy _halo_web_frame_create _halo_web_frame_destroy _halo_web_frame_draw _halo_web_frame_segment_count _halo_web_frame_gpu_bytes _halo_web_frame_post _halo_web_frame_read \
	_halo_web_feature_create _halo_web_feature_build _halo_web_feature_texture _halo_web_feature_destroy
# libhalo's GL runtime (the image passes and host contract 3's halo field) over WebGL 2: the
# same sources as the native runtime, which take OpenGL ES 3.0 entry points through
# emscripten_webgl_get_proc_address. Their one header from outside, GL/glcorearb.h (types
# and enums: emscripten has only GLES3/), comes from the system's (libgl-dev, which the
# native build needs too), copied into the build tree.
web_gl_files = libhalo/gl/glfuncs.c libhalo/gl/runtime.c libhalo/gl/frame.c libhalo/gl/camera.c libhalo/gl/segments.c \
	libhalo/gl/field.c libhalo/gl/field_atlas.c libhalo/gl/feature_splat.c
WEB_GL_INCLUDE = adapters/web/gl-include
web_comma = ,
web_empty =
web_space = $(web_empty) $(web_empty)

$(WEB_DEPS)/lib/libjansson.a: $(srcdir)/adapters/web/deps.sh
	$(AM_V_GEN)EMCC="$(EMCC)" NODE="$(NODE)" $(SHELL) $(srcdir)/adapters/web/deps.sh $(WEB_DEPS)

$(WEB_GL_INCLUDE)/GL/glcorearb.h:
	@mkdir -p $(WEB_GL_INCLUDE)/GL
	$(AM_V_GEN)header=`printf '#include <GL/glcorearb.h>\n' | $(CC) -M -x c - | tr ' \\\\' '\n\n' | grep 'GL/glcorearb\.h$$'` && \
		test -n "$$header" && cp "$$header" $@

$(WEB_PACKAGE)/dist/libhalo-core.mjs: $(web_core_files) $(web_gl_files) adapters/web/halo_web.c libhalo/embedded_modules.c \
		libhalo/emu/registry_list.h $(WEB_GL_INCLUDE)/GL/glcorearb.h libhalo/gl/glfuncs.h libhalo/halo_gl_loader.h libhalo/gl/runtime.h libhalo/gl/frame.h \
		$(WEB_DEPS)/lib/libjansson.a libhalo/halo.h libhalo/halo_feature.h libhalo/internal.h $(srcdir)/adapters/web/local.mk
	@mkdir -p $(WEB_PACKAGE)/dist
	$(AM_V_GEN)$(WEB_EMCC) -O2 -std=gnu11 -DHALO_BUILDING -DPACKAGE_VERSION=\"$(PACKAGE_VERSION)\" \
		-I$(srcdir)/libhalo -Ilibhalo -Ilibhalo/emu -I$(srcdir) -I$(WEB_DEPS)/include -I$(WEB_GL_INCLUDE) \
		$(addprefix $(srcdir)/,$(web_core_files) $(web_gl_files) adapters/web/halo_web.c) libhalo/embedded_modules.c \
		$(WEB_DEPS)/lib/libjansson.a -o $@ -sMODULARIZE=1 -sEXPORT_ES6=1 -sEXPORT_NAME=haloCore \
		-sALLOW_MEMORY_GROWTH=1 -sENVIRONMENT=web,worker -sEXPORTED_FUNCTIONS=$(subst $(web_space),$(web_comma),$(WEB_EXPORTS)) \
		-sMIN_WEBGL_VERSION=2 -sMAX_WEBGL_VERSION=2 \
		-sEXPORTED_RUNTIME_METHODS=UTF8ToString,stringToUTF8,lengthBytesUTF8,GL

# the package's own files, copied beside the WebAssembly
$(WEB_PACKAGE)/stamp: $(srcdir)/adapters/web/libhalo.mjs $(srcdir)/adapters/web/libhalo.d.ts \
		$(srcdir)/adapters/web/three.mjs $(srcdir)/adapters/web/three.d.ts \
		$(srcdir)/adapters/web/niivue.mjs $(srcdir)/adapters/web/niivue.d.ts \
		$(srcdir)/adapters/web/vtkjs.mjs $(srcdir)/adapters/web/vtkjs.d.ts \
		$(srcdir)/adapters/web/package.json $(srcdir)/adapters/web/README.md
	@mkdir -p $(WEB_PACKAGE)
	$(AM_V_GEN)cp $(srcdir)/adapters/web/libhalo.mjs $(srcdir)/adapters/web/libhalo.d.ts \
		$(srcdir)/adapters/web/three.mjs $(srcdir)/adapters/web/three.d.ts \
		$(srcdir)/adapters/web/niivue.mjs $(srcdir)/adapters/web/niivue.d.ts \
		$(srcdir)/adapters/web/vtkjs.mjs $(srcdir)/adapters/web/vtkjs.d.ts \
		$(srcdir)/adapters/web/package.json $(srcdir)/adapters/web/README.md $(WEB_PACKAGE)/ && touch $@

all-local: $(WEB_PACKAGE)/dist/libhalo-core.mjs $(WEB_PACKAGE)/stamp
clean-local: clean-web
clean-web:
	rm -rf $(WEB_PACKAGE) $(WEB_DEPS) $(WEB_GL_INCLUDE)
.PHONY: clean-web
endif
