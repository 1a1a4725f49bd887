/* libhalo — illustrative volume rendering stages for existing OpenGL volume renderers.
 *
 * The pipeline: load modules (halo_library) → read a scene (halo_scene) → link the
 * enabled stages into the host's own shader (halo_link → halo_program) → validate with
 * glslang (halo_validate) → run it in the host's GL context (halo_gl_*), or
 * compute the same thing in double precision (halo_emu_*).
 *
 * Conventions (sokol-style): descriptor structs where zero means "use the default",
 * opaque objects with create/destroy pairs, output argument last. The library never
 * prints and never exits: every call that can fail takes a halo_diagnostics list
 * (may be NULL) and returns a status or NULL.
 *
 * NULL arguments: every function refuses NULL objects: given NULL where it expects an
 * object or a required argument (a library, scene, program, frame, runtime, a name, a
 * source text, values, an output pointer), it returns its error value — HALO_ERROR_INPUT
 * for a halo_status, NULL for a pointer, 0 for a count, a size, a GL name or a flag,
 * the COUNT member for an enum (HALO_TARGET_COUNT, HALO_HOOK_COUNT; halo_source_kind_of:
 * HALO_SOURCE_SHADER) — and reports one USAGE diagnostic naming the function and the
 * argument ("halo_scene_set: scene is NULL"): into its halo_diagnostics list when it
 * takes one, and always to the calling thread's setup logger (halo_setup_desc.logger),
 * so that a void function's refusal is seen too. Arguments documented as optional (a NULL file name, a
 * NULL desc that means the defaults, NULL out-parameters of the map_line functions) stay
 * optional. A NULL halo_diagnostics list is always valid: diagnostics are then only
 * passed to the logger, and the halo_diagnostics_* functions treat it as an empty list.
 * The destroy functions take NULL and do nothing, as free() does.
 * tests/libhalo/test_null_api.c calls each function with each such argument NULL.
 *
 * Lifetimes (tests/libhalo/test_lifetimes.c): each object is created by its create, load
 * or link function and given back with its destroy function, once; after that the
 * caller must not use the pointer. What an object is made from stays alive while the
 * object lives, whatever order the caller destroys them in:
 *   halo_diagnostics  owned by the caller; the halo_diagnostic items and their strings
 *                     live until halo_diagnostics_clear or _destroy.
 *   halo_library      freed when the caller has destroyed it and every scene and program
 *                     made from it is destroyed too (reference counts). The halo_module
 *                     and halo_param_info pointers it hands out live as long as the library.
 *                     halo_library_add with HALO_ADD_REPLACE refuses (USAGE) to replace a
 *                     module while a scene or program made from the library lives: they
 *                     point into it.
 *   halo_scene        keeps its library alive. It links only with that library: halo_link
 *                     refuses (USAGE) desc.scene with another desc.library.
 *   halo_program      keeps its library alive (not the scene: the program copies the
 *                     scene's values). The arrays, strings and structs of its reflection
 *                     (halo_program_reflection, halo_program_find_uniform, ...) live as long
 *                     as the program; halo_program_set and halo_program_select_group
 *                     change the values they point to.
 *   halo_emu_frame, halo_gl_frame
 *                     keep their program (and a GL frame its halo_gl) alive. GL objects are
 *                     deleted in whatever GL context is current: destroy a GL frame while its
 *                     context is current.
 *   halo_gl           freed when destroyed and every frame made with it is destroyed.
 * Validation (halo_validate) needs halo_setup: without it, HALO_ERROR_INPUT and a
 * USAGE diagnostic. Everything else works without setup.
 *
 * Threads (tests/libhalo/test_threads.c, run under ThreadSanitizer in CI): halo_setup and
 * halo_shutdown may be called from any thread; they count (a mutex guards the count) and
 * glslang is finalized by the last halo_shutdown only after every validation in flight on
 * any thread has ended. Validation may run on several threads at once. The logger of
 * halo_setup_desc belongs to the calling thread: it receives the diagnostics of the calls
 * that thread makes, until that thread's last halo_shutdown; another thread's calls never
 * reach it (a thread that never called halo_setup has no logger). Objects: any number of
 * threads may read one object at once (link scenes of one library, read one program's
 * reflection, validate or emulate one program); a call that changes an object
 * (halo_library_add, halo_scene_enable, _set, _render_mutable,
 * halo_program_set, _select_group, a frame's functions, halo_diagnostics_* that add or
 * clear) needs that object to itself: no other thread may use it meanwhile. One
 * halo_diagnostics list belongs to one thread at a time. Creating and destroying objects
 * made from a shared library or program is safe from several threads (the reference
 * counts are atomic). The GL runtime follows GL's rule: a context is current on one
 * thread, and a halo_gl and its frames are used where their context is current.
 */
#ifndef HALO_H
#define HALO_H

#include <stddef.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(HALO_BUILDING) && defined(__GNUC__)
#define HALO_API __attribute__((visibility("default")))
#else
#define HALO_API
#endif

/* The host contract version (docs/host-contract.md). The linker defines
 * HALO_CONTRACT_VERSION with this value in every linked shader. */
#define HALO_CONTRACT_VERSION 2

/* ---- Status and diagnostics ------------------------------------------------ */

typedef enum halo_status {
    HALO_OK = 0,
    HALO_ERROR_INPUT = 1, /* the input has errors: diagnostics say which */
    HALO_ERROR_IO = 2     /* a file could not be read or written, or memory ran out */
} halo_status;

typedef enum halo_severity { HALO_SEVERITY_ERROR, HALO_SEVERITY_WARNING, HALO_SEVERITY_NOTE } halo_severity;

/* One list of message ids; tests assert on ids, never on wording. */
#define HALO_MESSAGES(X)                                                                                 \
    X(IO_READ, "cannot read file")                                                                       \
    X(IO_WRITE, "cannot write file")                                                                     \
    X(OUT_OF_MEMORY, "out of memory")                                                                    \
    X(ANNOTATION_UNKNOWN, "unknown '#pragma halo' directive")                                            \
    X(ANNOTATION_SYNTAX, "malformed '#pragma halo' annotation")                                          \
    X(ANNOTATION_DUPLICATE, "annotation given twice")                                                    \
    X(ANNOTATION_MISSING, "required annotation missing")                                                 \
    X(MODULE_HOOK_UNKNOWN, "unknown hook")                                                               \
    X(MODULE_ENTRY_MISSING, "module does not define its entry function")                                 \
    X(MODULE_DUPLICATE, "a module with this name is already loaded")                                     \
    X(MODULE_RESERVED_NAME, "module uses a name reserved by the host contract")                          \
    X(PARAM_TYPE_UNKNOWN, "unknown parameter type")                                                      \
    X(PARAM_DEFAULT_INVALID, "parameter default does not match its type or range")                       \
    X(PARAM_DUPLICATE, "parameter declared twice")                                                       \
    X(INPUT_NUL_BYTE, "the file contains a NUL byte")                                                    \
    X(SCENE_JSON, "scene is not valid JSON")                                                             \
    X(SCENE_KEY_UNKNOWN, "unknown key")                                                                  \
    X(SCENE_TYPE, "value has the wrong type")                                                            \
    X(SCENE_STAGE_UNKNOWN, "unknown stage")                                                              \
    X(SCENE_STAGE_DUPLICATE, "stage listed twice")                                                       \
    X(SCENE_PARAM_UNKNOWN, "unknown parameter")                                                          \
    X(SCENE_VALUE_BELOW_MIN, "value is below the minimum")                                               \
    X(SCENE_VALUE_ABOVE_MAX, "value is above the maximum")                                               \
    X(SCENE_VALUE_NONFINITE, "value is not finite")                                                      \
    X(SCENE_VALUE_COUNT, "value has the wrong number of components")                                     \
    X(SCENE_VERSION, "unsupported scene version")                                                        \
    X(LINK_MISSING_PROVIDER, "no enabled stage or host provides what a stage needs")                     \
    X(LINK_DUPLICATE_PROVIDER, "two enabled stages provide the same thing")                              \
    X(LINK_CYCLE, "stage dependencies form a cycle")                                                     \
    X(LINK_HOOK_MISMATCH, "stage hook does not fit this host")                                           \
    X(HOST_MARKER_MISSING, "host has no '#pragma halo declarations' line")                               \
    X(HOST_MARKER_DUPLICATE, "host has more than one '#pragma halo declarations' line")                  \
    X(HOST_MARKER_SCOPE, "'#pragma halo declarations' must be at global scope")                          \
    X(HOST_RESERVED_NAME, "host declares a name reserved by the host contract")                          \
    X(HOST_VERSION, "host '#version' does not fit the target")                                           \
    X(HOST_FINISH_MISSING, "host never calls halo_finish but the program has extra outputs")             \
    X(HOST_MARKER_INACTIVE, "'#pragma halo declarations' is commented out or in a branch not taken")     \
    X(HOST_APPLY_MISSING, "host never calls halo_apply but the scene links stages that run in it")       \
    X(HOST_MACRO_CLASH, "a host macro rewrites a name that the libhalo declarations use")                \
    X(HOST_OUTPUT_LOCATION, "host output without layout(location) beside libhalo's extra outputs")       \
    X(PASS_INVALID, "malformed image pass")                                                              \
    X(GLSL_ERROR, "GLSL error")                                                                          \
    X(GLSL_WARNING, "GLSL warning")                                                                      \
    X(EMU_MISSING, "stage has no C emulation")                                                           \
    X(GL_PROC_MISSING, "OpenGL entry point not found")                                                   \
    X(GL_COMPILE, "driver rejected the shader")                                                          \
    X(GL_LINK, "driver rejected the program")                                                            \
    X(HOST_COMPOSITING, "the scene's stages mean nothing under the host's compositing (MIP)")            \
    X(HOST_SINGLE_PASS, "the scene needs image passes between slices, which this host cannot run")       \
    X(ENGINE_UNSUPPORTED, "the engine's mode or input cannot take the stages (docs/hosts/)")             \
    X(USAGE, "invalid argument")                                                                         \
    X(GLSL_VERSION_IMPLIED, "shader has no '#version': GLSL's default version applies")                  \
    X(INPUT_TOO_LARGE, "the file is larger than libhalo reads (HALO_MAX_FILE_BYTES)")                    \
    X(PIECE_EXPRESSION,                                                                                  \
      "a composer expression (halo_pieces_desc) is not one GLSL expression of the kind its field needs") \
    X(HOST_SEGMENT_CALLS, "the ray loop is not bracketed by halo_segment_begin and halo_segment_end")    \
    X(FIELD_MEMORY, "the halo field of the frame's depth segments is over its memory cap (field_max_bytes)")

typedef enum halo_message_id {
#define HALO_X_ENUM(id, text) HALO_MSG_##id,
    HALO_MESSAGES(HALO_X_ENUM)
#undef HALO_X_ENUM
        HALO_MSG_COUNT
} halo_message_id;

typedef struct halo_diagnostic {
    halo_severity severity;
    halo_message_id id;
    const char *file; /* origin: module, host or scene file ("" when none) */
    int line, column; /* 1-based; 0 when unknown */
    const char *text; /* the full message, naming the offending field */
    /* The line it points at, or NULL. A line longer than HALO_DIAGNOSTIC_SOURCE_MAX bytes
     * is kept as a window of that many bytes around the column, "..." marking each cut
     * (as clang does), so that a long one-line input costs each diagnostic a screen line,
     * not the whole line. */
    const char *source_line;
    int source_column; /* the column of source_line that column points at (1-based; 0
                              * when column is): column itself unless the line was cut */
} halo_diagnostic;
#define HALO_DIAGNOSTIC_SOURCE_MAX 120

typedef struct halo_diagnostics halo_diagnostics;

HALO_API halo_diagnostics *halo_diagnostics_create(void);
HALO_API void halo_diagnostics_destroy(halo_diagnostics *d);
/* What a list holds: a copy, cheap to take. A NULL list: every field 0 but limit. */
typedef struct halo_diagnostics_info {
    size_t count;   /* kept: halo_diagnostics_get(d, 0 .. count - 1) */
    size_t errors;  /* every error reported, kept or left out by the cap */
    size_t dropped; /* how many the cap left out (0 when none) */
    size_t limit;   /* the cap (halo_diagnostics_set_limit; 0: none) */
} halo_diagnostics_info;
HALO_API halo_diagnostics_info halo_diagnostics_describe(const halo_diagnostics *d);
/* The index-th kept diagnostic, or NULL past the last. */
HALO_API const halo_diagnostic *halo_diagnostics_get(const halo_diagnostics *d, size_t index);
HALO_API int halo_diagnostics_has(const halo_diagnostics *d, halo_message_id id);
HALO_API void halo_diagnostics_clear(halo_diagnostics *d);
/* Adds a diagnostic, as libhalo adds its own (for hosts, adapters and tools built on
 * libhalo); d may be NULL (then only the setup logger sees it). file may be NULL, line
 * and column 0 when there is no place; source_line (may be NULL) is the line the column
 * points into, printed with a caret; the text is printf-formatted. */
#if defined(__GNUC__) || defined(__clang__)
#define HALO_PRINTF(fmt_index, first_arg) __attribute__((format(printf, fmt_index, first_arg)))
#else
#define HALO_PRINTF(fmt_index, first_arg)
#endif
HALO_API void halo_diagnostics_report(halo_diagnostics *d, halo_severity severity, halo_message_id id, const char *file,
                                      int line, int column, const char *source_line, const char *fmt, ...)
    HALO_PRINTF(8, 9);
/* An error without a source line: HALO_REPORT_ERROR(d, HALO_MSG_IO_READ, path, 0, 0,
 * "cannot read %s", why). */
#define HALO_REPORT_ERROR(d, id, file, line, column, ...) \
    halo_diagnostics_report((d), HALO_SEVERITY_ERROR, (id), (file), (line), (column), NULL, __VA_ARGS__)
/* Reads a text file whole, as libhalo reads its scenes and modules: at most
 * HALO_MAX_FILE_BYTES, NUL-terminated (caller frees with free()), *len (may be NULL) its
 * length without the NUL. NULL after one error naming the file and why (IO_READ,
 * INPUT_TOO_LARGE, OUT_OF_MEMORY; INPUT_NUL_BYTE at its line and column: a file that
 * holds a NUL byte is no text); `what` names the file in it ("host shader"). */
HALO_API char *halo_read_text_file(const char *path, const char *what, size_t *len, halo_diagnostics *d);
/* Writes `file:line:col: error: text` (`file:line:` where the column is unknown, as
 * GCC without columns), then the source line and a caret under the column; the gutter
 * is as wide as the line number. */
HALO_API void halo_diagnostics_print(const halo_diagnostics *d, FILE *out);
HALO_API const char *halo_message_name(halo_message_id id); /* "SCENE_JSON" */
/* A cap on what a list keeps, as clang's -ferror-limit: past `limit` errors (and
 * past `limit` warnings and notes) a diagnostic is counted but neither kept nor
 * passed to the setup logger, and halo_diagnostics_print ends with "N more errors
 * not shown". halo_diagnostics_describe's errors and halo_diagnostics_has still count
 * every one. 0 means no cap. The default, 100, lets a module or scene with many mistakes
 * show them all in one go while a runaway input (100 000 markers, a million stages)
 * prints a screenful, not hundreds of megabytes. */
#define HALO_DIAGNOSTICS_DEFAULT_LIMIT 100
HALO_API void halo_diagnostics_set_limit(halo_diagnostics *d, size_t limit);
/* One input checked several times (halo-validate check: once per target). After
 * halo_diagnostics_set_run(d, "330") every diagnostic added belongs to run "330"; one
 * equal to a diagnostic of an earlier run (same severity, id, file, line, column and
 * text) is not added again (nor passed to the logger, nor counted by the cap): the
 * earlier one joins this run. With two runs or more, halo_diagnostics_print ends each
 * diagnostic with the runs it occurred in ("[330, 450, es300]"), so a problem prints
 * once. NULL ends run tagging; halo_diagnostics_clear forgets the runs. At most
 * HALO_DIAGNOSTICS_MAX_RUNS names; diagnostics of further runs are kept as they are. */
#define HALO_DIAGNOSTICS_MAX_RUNS 32
HALO_API void halo_diagnostics_set_run(halo_diagnostics *d, const char *name);

/* ---- Process-wide setup ---------------------------------------------------- */

typedef struct halo_setup_desc {
    /* Called for every diagnostic added by a call on this thread, besides collecting it
     * (per thread: "Threads" above). */
    void (*logger)(const halo_diagnostic *diagnostic, void *user_data);
    void *user_data;
} halo_setup_desc;

/* Initializes glslang and installs desc's logger for the calling thread (a NULL desc keeps
 * the thread's logger). Safe to call more than once and from any thread; pair each call
 * with halo_shutdown (on any thread): the last one finalizes glslang once no validation
 * runs. HALO_ERROR_IO when glslang cannot be initialized. */
HALO_API halo_status halo_setup(const halo_setup_desc *desc);
HALO_API void halo_shutdown(void);
HALO_API const char *halo_version(void);

/* ---- Targets ---------------------------------------------------------------- */

typedef enum halo_target {
    HALO_TARGET_DEFAULT = 0, /* GLSL 330 core */
    HALO_TARGET_GLSL330,
    HALO_TARGET_GLSL450,
    HALO_TARGET_ES300,
    HALO_TARGET_GLSL150, /* GLSL 1.50 core (OpenGL 3.2: VTK, macOS): fragment outputs carry no
                              * layout(location); halo_gl_program_build binds them by name */
    HALO_TARGET_COUNT
} halo_target;

HALO_API const char *halo_target_name(halo_target t);         /* "330", "450", "es300", "150" */
HALO_API halo_target halo_target_from_name(const char *name); /* HALO_TARGET_COUNT if unknown */

typedef enum halo_shader_kind { HALO_SHADER_FRAGMENT = 0, HALO_SHADER_VERTEX } halo_shader_kind;

/* ---- Modules ---------------------------------------------------------------- */

typedef enum halo_hook {
    HALO_HOOK_SAMPLE = 0,    /* per sample, inside the host's loop: void apply(inout halo_sample s) */
    HALO_HOOK_IMAGE,         /* image pass: a complete full-screen program run by the GL runtime */
    HALO_HOOK_LINE_VERTEX,   /* line strip expansion, in a line host's vertex shader */
    HALO_HOOK_LINE_FRAGMENT, /* line core/halo split, in a line host's fragment shader */
    HALO_HOOK_COUNT
} halo_hook;

typedef enum halo_param_type {
    HALO_PARAM_FLOAT = 0,
    HALO_PARAM_VEC2,
    HALO_PARAM_VEC3,
    HALO_PARAM_VEC4,
    HALO_PARAM_INT,
    HALO_PARAM_BOOL,
    HALO_PARAM_CHANNELS /* one float per halo (1..4): halo_channels in GLSL (docs/image-passes.md) */
} halo_param_type;

#define HALO_MAX_COMPONENTS 64

typedef struct halo_param_info {
    const char *name; /* as written in the module: "k_gs" */
    halo_param_type type;
    int array_size;    /* 0: scalar or vector; N: an array of at most N elements */
    int components;    /* per element: 1..4 */
    double min, max;   /* valid range of each component */
    int default_count; /* elements in the default (1 unless an array) */
    double default_value[HALO_MAX_COMPONENTS];
    const char *meaning; /* one line, with units */
    double step;         /* step=: the smallest change that means something (e.g. 1 for a 0/1 mode kept as
                          * a float); 0: not stated. For editors and sliders; values are not rounded to it */
} halo_param_info;

typedef struct halo_module halo_module;
typedef struct halo_library halo_library;

/* The largest text file libhalo reads (a module, scene, host or composed shader, a
 * polyline file): 64 MiB. A larger file, or a stream that does not end (/dev/zero), is
 * refused with INPUT_TOO_LARGE naming the file, after at most this many bytes were read
 * (a regular file's size is checked before reading); HALO_ERROR_IO. A read that runs out
 * of memory stops at once (OUT_OF_MEMORY). */
#define HALO_MAX_FILE_BYTES ((size_t)64 << 20)

/* A library holds the modules embedded at build time; more may be added from files.
 * halo_library_destroy gives back the caller's reference: the scenes and programs made
 * from the library keep it until they are destroyed ("Lifetimes" above). */
HALO_API halo_library *halo_library_create(halo_diagnostics *diag);
HALO_API void halo_library_destroy(halo_library *lib);
typedef enum halo_add_mode {
    HALO_ADD_NEW = 0, /* a module whose name is already loaded is refused (MODULE_DUPLICATE) */
    HALO_ADD_REPLACE  /* replaces a loaded module of the same name (to try a modified built-in stage);
                       * refused (USAGE) while a scene or program made from the library lives */
} halo_add_mode;
/* Adds a module: parsed from `source`, with `file` its name in diagnostics (NULL: "module");
 * or, with source NULL, read from the file at the path `file` (bounded: HALO_MAX_FILE_BYTES). */
HALO_API halo_status halo_library_add(halo_library *lib, const char *file, const char *source, halo_add_mode mode,
                                      halo_diagnostics *diag);
/* The modules a library holds, in the order they were added (the built-in ones first): a
 * copy of the count and a pointer into the library, valid until a module is added. A NULL
 * library: every field 0. */
typedef struct halo_library_info {
    size_t module_count;
    const halo_module *const *modules;
} halo_library_info;
HALO_API halo_library_info halo_library_describe(const halo_library *lib);
HALO_API const halo_module *halo_library_find(const halo_library *lib, const char *name);

/* What a module is, by value (strings and parameters live as long as the library holds the
 * module). A NULL module: every field 0, hook HALO_HOOK_COUNT. */
typedef struct halo_module_info {
    const char *name;    /* "boundary"; the helper library: "halo_math" */
    const char *file;    /* the file it was read from, or its name when added from a string */
    const char *summary; /* one line */
    halo_hook hook;
    size_t param_count;
    const halo_param_info *params;
    int has_emulation; /* a C emulation of its per-sample (or line) code, or of every image pass */
    /* What it adds to a frame beside the sample (a per-sample stage with any of them needs
     * a frame: halo_emu_frame, halo_gl_frame): */
    size_t output_count;       /* `#pragma halo output`: extra fragment outputs it folds into images */
    size_t image_count;        /* `#pragma halo image`: a per-sample stage's images it reads; an
                                * image-pass stage's images of its schedule */
    size_t host_uniform_count; /* `#pragma halo host_uniform`: uniforms the host sets */
} halo_module_info;
HALO_API halo_module_info halo_module_describe(const halo_module *m);
HALO_API const halo_param_info *halo_module_find_param(const halo_module *m, const char *name);

/* ---- Scenes ----------------------------------------------------------------- */

/* Rendering settings the example renderers read from a scene's "render" object.
 * libhalo itself only validates them. */
#define HALO_MAX_TRANSFER_POINTS 32
typedef struct halo_render_settings {
    double azimuth, elevation, zoom; /* degrees, degrees, 1 = volume fills the view */
    double background[3];
    double step;        /* ray step in voxels */
    double window[2];   /* intensity window mapped to [0,1] */
    int transfer_count; /* control points: value, r, g, b, opacity */
    double transfer[HALO_MAX_TRANSFER_POINTS][5];
} halo_render_settings;

typedef struct halo_scene halo_scene;

/* A scene (docs/scene.md): parsed from json_text, with file its name in diagnostics (NULL:
 * "scene"); or, with json_text NULL, read from the file at the path file (bounded:
 * HALO_MAX_FILE_BYTES), as halo_library_add takes a module. Checked against the library's
 * modules; NULL when it has errors, every error in diag with the JSON path. The scene
 * keeps the library alive and links only with it. */
HALO_API halo_scene *halo_scene_load(const char *file, const char *json_text, const halo_library *lib,
                                     halo_diagnostics *diag);
/* An empty scene: no stage enabled, default render settings. */
HALO_API halo_scene *halo_scene_create(const halo_library *lib);
HALO_API void halo_scene_destroy(halo_scene *scene);
HALO_API halo_status halo_scene_enable(halo_scene *scene, const char *stage, int enabled, halo_diagnostics *diag);
/* Fixes a parameter (stage.param) to values; live marks it a uniform the host may change. */
HALO_API halo_status halo_scene_set(halo_scene *scene, const char *stage, const char *param, const double *values,
                                    int count, int live, halo_diagnostics *diag);
/* What a scene holds: a copy of counts and pointers into the scene, valid until it is
 * changed or destroyed. A NULL scene: every field 0. */
typedef struct halo_scene_info {
    size_t stage_count;
    const char *const *stages;          /* module names, in the scene's order (enabled or not) */
    const halo_render_settings *render; /* the "render" object (halo_scene_set_render replaces it) */
} halo_scene_info;
HALO_API halo_scene_info halo_scene_describe(const halo_scene *scene);
HALO_API void halo_scene_set_render(halo_scene *scene, const halo_render_settings *render);

/* ---- Linking ---------------------------------------------------------------- */

/* halo_link_desc.version */
typedef enum halo_version_mode {
    HALO_VERSION_TARGET = 0, /* the target's #version line replaces the host's (or comes first) */
    HALO_VERSION_KEEP,       /* the host's own #version line stays as written (none if it has none) */
    HALO_VERSION_NONE        /* no #version line: the engine adds its own */
} halo_version_mode;

/* A link without host text, for engines that compose their shader from pieces (VTK's
 * //VTK:: tags, three.js chunks, any template engine). The expressions are the composer's
 * own GLSL, in scope where it puts the sample piece; NULL takes the default in brackets. */
typedef struct halo_pieces_desc {
    const char *position;         /* vec3, volume texture space [0,1]^3 ("halo_position") */
    const char *value;            /* float, normalised to [0,1] ("halo_value") */
    const char *gradient;         /* vec3, the contract's gradient; NULL: derived from volume (or gradient_texture) */
    const char *view;             /* vec3, unit, towards the eye; NULL: derived from the camera uniforms */
    const char *depth;            /* float in [0,1]; NULL: derived from the camera uniforms */
    const char *fragcoord;        /* vec2 ("gl_FragCoord.xy") */
    const char *color;            /* a vec4 lvalue, colour and opacity before compositing, not premultiplied
                            * ("halo_color"): the sample piece reads and writes it */
    const char *volume;           /* a sampler3D expression the engine declares ("in_volume[0]"): derive the
                            * gradient from it (central differences, halved) */
    const char *gradient_texture; /* or a sampler3D with the gradient in RGB, per voxel step */
    int segmented;                /* 1: the composer calls halo_segment_begin/halo_segment_end in its ray
                            * loop (host contract 2); the program then runs its image passes */
    int first_output_location;    /* the extra outputs' first location, 1..HALO_MAX_OUTPUT_LOCATION; 0: 1
                                * (after the engine's colour); another value: USAGE, no program */
} halo_pieces_desc;
#define HALO_MAX_OUTPUT_LOCATION 15

/* The pieces of a program linked from a halo_pieces_desc. */
typedef enum halo_piece {
    HALO_PIECE_WHOLE = -1,       /* halo_program_source, _map_line: the whole linked shader */
    HALO_PIECE_DECLARATIONS = 0, /* global scope, after the engine's samplers, before main */
    HALO_PIECE_SAMPLE,           /* per sample, after classification, before compositing */
    HALO_PIECE_FINISH,           /* once per fragment, before main returns */
    HALO_PIECE_COUNT
} halo_piece;

/* How a linked shader's extra outputs get their locations (halo_output_info.location). */
typedef enum halo_output_locations {
    HALO_LOCATIONS_AUTO = 0,  /* layout(location) where the target has it; GLSL 150 has not: bound by name */
    HALO_LOCATIONS_BY_NAME,   /* no layout(location) under any target: bind them by name
                               * (glBindFragDataLocation; halo_gl_program_build does) */
    HALO_LOCATIONS_EXTENSION, /* layout(location) under GLSL 150 too, the shader enabling
                               * GL_ARB_explicit_attrib_location after its #version (an engine that links the
                               * program itself and cannot bind names, such as VTK) */
    HALO_LOCATIONS_COUNT
} halo_output_locations;

typedef struct halo_link_desc {
    const halo_library *library; /* required */
    const halo_scene *scene;     /* NULL: no stage enabled */
    const char *host_source;     /* required: the host's shader text */
    const char *host_file;       /* name used in diagnostics; default "host" */
    halo_target target;          /* default GLSL 330 core */
    halo_shader_kind kind;       /* default fragment */
    int all_live;                /* every parameter becomes a uniform (the "uniform switches" variant) */
    int image_precision;         /* images of image passes: 32 (float, default), 16 (half), 8 (unorm) */
    int image_scale;             /* pass images at 1/scale of the frame per side: 1 (0: default), 2 or 4
                                  * (outputs, host_color and at=post images stay full size; docs/image-passes.md) */
    int force_segments;          /* host contract 2: a host that calls halo_segment_begin is drawn in segments
                                  * only when the program has passes between slices; 1 links the segment code
                                  * anyway (halo_gl_segments_desc.segments then forces a count) */
    int one_draw;                /* host contract 3: the images that passes between slices make (volumetric
                                  * halos' field and occlusion) are computed by libhalo's own march over the
                                  * host's volume before the host draws, for every depth segment; each sample
                                  * reads its segment's layer. The host is drawn once (halo_gl_frame_draw with
                                  * halo_gl_segments_desc.volume_texture), early ray termination kept; its
                                  * halo_segment_begin/_end calls, if any, do nothing (docs/host-contract.md) */
    /* ---- For shader composers (docs/composers.md) ---- */
    halo_version_mode version;              /* the #version line: the target's (default), the host's own, or none */
    int engine_uniforms;                    /* 1: live parameters are not declared: the engine declares them from the
                                  * reflection (halo_reflection.declarations), bools as int */
    halo_output_locations output_locations; /* how the extra outputs get their locations */
    const halo_pieces_desc *pieces;         /* with host_source NULL: link no host text; the program's pieces
                                  * (halo_program_source) go into the composer's own shader */
} halo_link_desc;

typedef enum halo_uniform_kind { HALO_UNIFORM_PARAM = 0, HALO_UNIFORM_COUNT_OF_ARRAY } halo_uniform_kind;

typedef struct halo_uniform_info {
    const char *name;  /* GLSL name in the linked source: "halo_boundary_k_gs" */
    const char *stage; /* "boundary" */
    const char *param; /* "k_gs" */
    const halo_param_info *info;
    int live;               /* 1: a uniform the host sets; 0: emitted as a constant */
    int count;              /* elements currently set (arrays) */
    const double *value;    /* current value: count * components doubles */
    const char *count_name; /* an array's companion uniform "NAME_count" (int: elements set); else NULL */
} halo_uniform_info;

/* MIN: front-most value (e.g. a feature depth; its image is cleared to 1). FIRST: the
 * first hit along the ray wins: the field is vec4(value, hit), blended front to back by
 * coverage (GL_ONE_MINUS_DST_ALPHA, GL_ONE); docs/image-passes.md. */
typedef enum halo_blend {
    HALO_BLEND_NONE = 0,
    HALO_BLEND_MAX,
    HALO_BLEND_ADD,
    HALO_BLEND_MIN,
    HALO_BLEND_FIRST
} halo_blend;

/* An extra fragment output, fed from a halo_sample field (docs/image-passes.md). */
typedef struct halo_output_info {
    const char *name; /* GLSL name: "halo_output_seed" */
    int location;
    int components;    /* the field's: the program's channel count for a channels field */
    const char *image; /* the image it writes: "seed" */
    halo_blend blend;  /* how the host's blending must combine fragments and slices */
    const char *field; /* the halo_sample field: "seed" */
    int channel;       /* -1; else the column of a per-channel (mat4) field: image FIELD_k */
} halo_output_info;

/* A screen-sized image used by image passes, outputs and samplers. */
/* FRAME: cleared at the start of a frame and of every feature group; GENERATION: also
 * after each generation; FRAME_ONLY: at the start of a frame only (an accumulator over
 * the feature groups of a frame). */
typedef enum halo_image_reset { HALO_RESET_FRAME = 0, HALO_RESET_GENERATION, HALO_RESET_FRAME_ONLY } halo_image_reset;
typedef struct halo_image_info {
    const char *name;
    int channels;           /* components: the program's channel count, or fixed by components=N */
    halo_image_reset reset; /* cleared at frame start; RESET_GENERATION: also after each generation */
    double clear;           /* the value it is cleared to (0; 1 for a min output) */
    int host;               /* 1: host_color, the host's texture (halo_gl_frame_post); never cleared */
    int scale;              /* 1: the frame's size; 2, 4: ceil(width / scale) x ceil(height / scale) */
} halo_image_info;

/* A sampler a per-sample stage reads: bind the image's current texture to it. */
typedef struct halo_sampler_info {
    const char *name;  /* "halo_image_field" */
    const char *image; /* "field" */
} halo_sampler_info;

/* A uniform the host must set every frame (e.g. the image-plane axes). */
typedef struct halo_host_uniform_info {
    const char *name; /* "halo_host_screen_right" */
    const char *type; /* GLSL type */
    const char *meaning;
} halo_host_uniform_info;

#define HALO_MAX_PASS_INPUTS 12
/* When an image pass runs (at= in its module). */
typedef enum halo_pass_at {
    HALO_PASS_AT_GENERATE = 0, /* in halo_gl_frame_generate: between slices or segments (the field) */
    HALO_PASS_AT_POST,         /* at the end of each feature group (halo_gl_frame_end_group, or
                                * halo_gl_frame_post when the frame has one group) */
    HALO_PASS_AT_FINAL,        /* once at the end of the frame (halo_gl_frame_post) */
} halo_pass_at;
typedef struct halo_pass_info {
    const char *name;  /* "spread" */
    const char *stage; /* module: "halo_generate" */
    const char *entry;
    int input_count;
    const char *inputs[HALO_MAX_PASS_INPUTS]; /* image names; "previous" = the output before the pass */
    const char *first;                        /* for "previous" in the first repetition; NULL = the output itself */
    const char *output;
    int repeat;               /* 1..HALO_MAX_PASS_REPEAT: a repeat=PARAM parameter must declare max <= it */
    const char *repeat_param; /* PARAM of repeat=PARAM (a parameter of `stage`, e.g. "passes"); NULL: once */
    const char *vertex_source;
    const char *fragment_source;
    halo_pass_at at;    /* when it runs */
    int channel;        /* -1; else the channel of an each=channel pass (halo_pass_channel) */
    int start;          /* the first repetition drawn (1..repeat): draws start..repeat, each with its
                         * repetition as halo_pass_index (start=K in the module) */
    int reach;          /* -1: undeclared, the pass may write anywhere; else repetition i writes a nonzero
                         * pixel only within halo_pass_reach(pass, i) pixels (per axis) of a nonzero pixel
                         * of its inputs (reach= in the module) */
    int reach_exponent; /* -1: none; else max(0, PARAM) of reach=[M*]B^(PARAM-i)+K (reach holds K): a
                         * negative PARAM gives B^0, as B^(PARAM-i) is 1 for i >= PARAM */
    int reach_factor;   /* M of reach=M*B^(PARAM-i)+K (1 without M*) */
    int reach_base;     /* B of reach=M*B^(PARAM-i)+K: 2 or 4 */
    int running;        /* 1: running=associative: output = (the output of the generation before)
                         * op (input 0), op associative in the image's floats with identity 0
                         * (halo_generate's occlusion: a maximum of non-negative values), so a
                         * runtime may compute it for many generations at once as a prefix scan
                         * (docs/image-passes.md) */
} halo_pass_info;
#define HALO_MAX_PASS_REPEAT 1024

/* Pixels (per axis) repetition i of a pass reaches: reach + reach_factor *
 * reach_base^max(0, reach_exponent - i) when it has an exponent (at most 2^30); -1 when the
 * pass declares no reach. Pixels of the pass's output image, on images at 1/s of the
 * frame too (docs/image-passes.md). */
HALO_API int halo_pass_reach(const halo_pass_info *pass, int repetition);

typedef struct halo_program halo_program;

HALO_API halo_program *halo_link(const halo_link_desc *desc, halo_diagnostics *diag);
HALO_API void halo_program_destroy(halo_program *p);
/* The linked text: HALO_PIECE_WHOLE, the whole fragment shader (for a program linked from
 * pieces, the pieces in a stand-in host); a piece, one piece of a program linked from
 * pieces (NULL for a program linked into host text, or for an unknown piece). */
HALO_API const char *halo_program_source(const halo_program *p, halo_piece piece);
/* Maps a 1-based line of that text (of the whole shader, or within the piece) to its
 * origin, a module or host file and line; returns 0 when it has none (generated code). */
HALO_API int halo_program_map_line(const halo_program *p, halo_piece piece, int line, const char **file,
                                   int *origin_line);
/* What a linked stage is, from its module's `#pragma halo is` annotation (docs/modules.md),
 * so that hosts and adapters ask the stage instead of naming it. */
typedef struct halo_stage_info {
    const char *name;
    halo_hook hook;
    int keeps_empty;           /* `is keeps_empty`: an empty sample (value, colour, opacity and gradient 0)
                              * stays empty, and the stage writes 0 to its outputs, where the images it
                              * reads are 0 (a host may skip such samples: the slice host's clipping) */
    int zero_generation;       /* `is zero_generation`: its generation passes make every image 0 from a
                              * seed image of 0 (a host may skip the generation of an empty slab) */
    const char *labels_when;   /* `is labels_when=PARAM`: it reads halo_host_labels only for the values
                              * of PARAM that are >= 0; NULL: whenever it declares that host uniform */
    const char *interval;      /* `is interval=PARAM`: PARAM (an int) is M, the slices or planes a host
                              * draws between two generations of its passes (the reflection's interval) */
    const char *strip_width;   /* `is strip_width=PARAM` (a line vertex stage): PARAM (a float) is the strip's
                                * whole width, line core and halo together */
    const char *core_fraction; /* `is core_fraction=PARAM` (a line fragment stage): PARAM (a float) is the
                                * fraction of the strip that is the line itself, the rest its halo: a host
                                * drawing plain lines without this stage narrows the strip by it */
} halo_stage_info;
/* A parameter of a linked stage (halo_program_reflection: every one), or NULL. */
HALO_API const halo_uniform_info *halo_program_find_uniform(const halo_program *p, const char *stage,
                                                            const char *param);
/* Changes a parameter's value: a live one is uploaded by halo_gl_program_upload; the
 * emulation always uses the current value. Values are range-checked. */
HALO_API halo_status halo_program_set(halo_program *p, const char *stage, const char *param, const double *values,
                                      int count, halo_diagnostics *diag);
/* A uniform an engine that declares uniforms itself (halo_link_desc.engine_uniforms) must
 * declare and set (halo_reflection.declarations below: every one): a live parameter that a
 * linked stage reads, a bool one as int, an array one with its count companion. */
typedef struct halo_uniform_decl {
    const char *name;       /* "halo_boundary_k_gs" */
    const char *glsl_type;  /* "float", "vec3", "int" (a bool parameter is int), ... */
    int components;         /* per element: 1..4 */
    int array_size;         /* 0: not an array; N: declare name[N] */
    const char *count_name; /* an array's companion "NAME_count" (int, the elements set), or NULL */
    int count;              /* elements set (1 unless an array) */
    const double *value;    /* count * components values */
    const halo_uniform_info *param;
    double storage[4]; /* value's storage where it is converted (a channels parameter) */
} halo_uniform_decl;
/* What a linked program has, as arrays that live as long as the program (halo_program_set
 * and halo_program_select_group change the values they point to): a copy of counts and
 * pointers, cheap to take. A NULL program has none: every count 0 (so a loop over it does
 * nothing), every pointer NULL. */
typedef struct halo_reflection {
    size_t stage_count; /* linked stages, in execution order */
    const halo_stage_info *stages;
    size_t uniform_count; /* every parameter of every linked stage, live or constant */
    const halo_uniform_info *uniforms;
    size_t output_count; /* extra fragment outputs */
    const halo_output_info *outputs;
    size_t pass_count; /* image passes, in schedule order */
    const halo_pass_info *passes;
    size_t image_count; /* screen-sized images */
    const halo_image_info *images;
    size_t sampler_count; /* images the linked shader reads */
    const halo_sampler_info *samplers;
    size_t host_uniform_count; /* uniforms the host sets (halo_gl_set_host_uniform) */
    const halo_host_uniform_info *host_uniforms;
    int channel_count;    /* 1..4: halos (channels) in this program; 1 when it has none */
    int image_precision;  /* halo_link_desc.image_precision as linked: 32, 16 or 8 */
    int image_scale;      /* halo_link_desc.image_scale as linked: 1, 2 or 4 */
    int segment_location; /* host contract 2: > 0 when the host is drawn in depth segments
                           * (halo_gl_frame_draw): the location of the ray-state output
                           * halo_segment_state_out; 0 when it is drawn once */
    int one_draw;         /* host contract 3: 1 when linked with one_draw and the program has a field
                           * (images made by passes between slices): halo_gl_frame_draw computes the
                           * field of every depth segment, then calls the host's draw once */
    halo_target target;   /* the target it was linked for (HALO_TARGET_COUNT for a NULL program) */
    int group_count;      /* feature groups (below): 1 when the program has none, 0 for NULL */
    /* From the current parameter values (take the reflection again after halo_program_set): */
    int interval;     /* M, the slices (planes) between two generations: the value of the first
                       * stage's `is interval=` parameter (e.g. halo_generate.interval), or 0
                       * when no stage states one (a host then takes its own, e.g. the paper's 4) */
    int reads_labels; /* whether the program reads halo_host_labels: a stage declares it and,
                       * with labels_when, a value of that parameter is >= 0, or the parameter
                       * is live (it may change) */
    /* The uniforms an engine that declares uniforms itself (halo_link_desc.engine_uniforms)
     * declares and sets, fixed at link; their count and value follow halo_program_set and
     * halo_program_select_group in place. */
    size_t declaration_count;
    const halo_uniform_decl *declarations;
    /* with one_draw: the program of libhalo's own march over the volume, linked from the
     * same scene (the stages whose outputs are the seeds, e.g. halo_seed), which
     * halo_gl_frame_draw runs before the host's draw; for its emulation (halo_emu_apply)
     * and its reflection. Owned by p. Else NULL. */
    const halo_program *march;
} halo_reflection;
HALO_API halo_reflection halo_program_reflection(const halo_program *p);
/* Feature groups (docs/image-passes.md, "Feature groups"): a stage annotated
 * `#pragma halo groups` (outline_feature, outlines) takes up to HALO_MAX_GROUP_CHANNELS
 * values per channels parameter; the linker splits them into groups of four. The host
 * renders the volume once per group: halo_program_select_group(p, g) makes group g's
 * values current (upload them: halo_gl_program_upload), then halo_gl_frame_begin_group,
 * the volume, halo_gl_frame_end_group; halo_gl_frame_post after the last. */
#define HALO_MAX_GROUP_CHANNELS 16
HALO_API halo_status halo_program_select_group(halo_program *p, int group);
/* Reflection as a JSON document (caller frees with free()). */
HALO_API char *halo_program_reflect_json(const halo_program *p);

/* ---- Validation (glslang, in process) -------------------------------------- */

/* A piece of the composer's own template, to map lines of a composed shader back to it. */
typedef struct halo_composer_piece {
    const char *name; /* "//VTK::Shading::Impl" or a file name */
    const char *text; /* found verbatim in the composed shader */
} halo_composer_piece;
/* What a shader text is, whatever its file's extension: a module (a '#pragma halo module'
 * line), a host (a '#pragma halo declarations' line, also one commented out or in a branch
 * not taken, which halo_validate then reports), or a plain shader. */
typedef enum halo_source_kind { HALO_SOURCE_SHADER = 0, HALO_SOURCE_MODULE, HALO_SOURCE_HOST } halo_source_kind;
HALO_API halo_source_kind halo_source_kind_of(const char *source);

/* What halo_validate checks: set exactly one of program, source and module (more, or
 * none: USAGE). glslang's errors are rewritten to the module's or the host's own
 * file:line:col. */
typedef struct halo_validate_desc {
    /* A linked program: its source and each image pass's fragment program. With composed:
     * instead, a shader an engine composed from the program's pieces (found verbatim in it)
     * and its own template; errors in a libhalo piece map to the module's file:line, in one
     * of composer_pieces to name:line, else to composed_file:line. The composed shader's own
     * #version line selects the language. */
    const halo_program *program;
    const char *composed;
    const char *composed_file;
    const halo_composer_piece *composer_pieces;
    size_t composer_piece_count;
    /* A stand-alone shader (no linking), named file in diagnostics. A plain shader (no
     * libhalo annotation) is checked as it is: for its own #version with HALO_TARGET_DEFAULT
     * (none: GLSL ES 1.00, as GLSL says, and a GLSL_VERSION_IMPLIED note), else for the
     * target's version whatever its #version says. '#include "name"' resolves as
     * glslangValidator resolves it: against the folder of the including file (for the
     * shader itself, file's folder; file is a path as fopen takes it, and a name without '/'
     * is in the working directory), then those of the files including that one. The working
     * directory is not changed. */
    const char *source;
    const char *file;
    halo_shader_kind kind;
    /* A module of library, linked alone into a minimal host of its hook. */
    const halo_module *module;
    const halo_library *library;
    halo_target target; /* for source and module */
} halo_validate_desc;
/* Returns HALO_OK or HALO_ERROR_INPUT. */
HALO_API halo_status halo_validate(const halo_validate_desc *desc, halo_diagnostics *diag);

/* ---- C emulation (double precision) ---------------------------------------- */

/* What a line host fills (docs/lines.md, Everts et al. 2009), in double precision: the
 * fields of the GLSL structs halo_line_vertex and halo_line_fragment. */
typedef struct halo_emu_line_vertex {
    double position[3];  /* the polyline vertex (world space); the stage moves it sideways */
    double direction[3]; /* averaged line direction D at the vertex (any length, or 0) */
    double uv[2];        /* u along the line 0..1, v across the strip: 0 or 1 */
    double eye[3];       /* eye position (world space) */
    double width;        /* the host's length unit for strip widths; the stage writes the strip width */
    double color[3];
    double opacity;
} halo_emu_line_vertex;

typedef struct halo_emu_line_fragment {
    double uv[2]; /* interpolated strip coordinates: v = 0.5 at the line's centre */
    double depth; /* normalized linear depth: 0 front, 1 back of the data; the host writes it */
    double fragcoord[2];
    double color[3]; /* line colour; becomes the background colour in the halo */
    double opacity;
    double background[3];
} halo_emu_line_fragment;

typedef struct halo_emu_sample {
    /* filled by the caller, as a host fills halo_sample */
    double position[3];
    double value;
    double gradient[3];
    double view[3];
    double depth;
    double fragcoord[2];
    double color[3];
    double opacity;
    /* provided by stages */
    double normal[3];
    double gradient_magnitude;
    double seed[4]; /* per-halo seed intensity (volumetric halos) */
    /* extra outputs: accumulated over the halo_emu_apply calls of one fragment;
     * zero them at the start of a fragment (e.g. memset the whole sample) */
    double output_accum[4];
    /* outlines (docs/outlines.md): the front-most feature depth per feature (1: none),
     * the first-hit normal of each feature (xyz, hit), the front-most occluder depth */
    double feature_depth[4];
    double feature_normal[4][4];
    double occluder_depth;
    /* accumulators of outputs 1.. (output 0: output_accum); a min output holds
     * clear - value, so that zero means "nothing yet" here too */
    double output_accum_next[15][4];
    /* A program linked into a line host (docs/lines.md) applies its stages to the struct
     * of its hook instead of the fields above: line_vertex (a vertex host) or
     * line_fragment (a fragment host). */
    halo_emu_line_vertex line_vertex;
    halo_emu_line_fragment line_fragment;
} halo_emu_sample;

/* Screen-sized images of a program with image passes, outputs or samplers, in double
 * precision: the reference for the GL runtime's frame (docs/image-passes.md); and the
 * host uniforms of any program (e.g. a line program's: it has no images). */
typedef struct halo_emu_frame halo_emu_frame;

/* Applies the program's stages, in its order, with its current parameter values, to the
 * sample; a line host's program, to s->line_vertex or s->line_fragment. With a frame
 * (halo_emu_frame_create below; NULL: none), the frame's images and host uniforms are
 * available to the stages and the outputs are folded into s->output_accum. Without one,
 * host uniforms read as zero vectors, as unset GL uniforms: line_strip's depth range is
 * then (0, 0), unset; give it with halo_emu_frame_set_host_uniform(f, "depth_range",
 * range, 2). EMU_MISSING for a stage without emulation. */
HALO_API halo_status halo_emu_apply(const halo_program *p, halo_emu_frame *f, halo_emu_sample *s,
                                    halo_diagnostics *diag);

/* width and height 1..HALO_MAX_FRAME_SIDE (as halo_gl_frame_create); otherwise USAGE and NULL. */
#define HALO_MAX_FRAME_SIDE 16384
HALO_API halo_emu_frame *halo_emu_frame_create(const halo_program *p, int width, int height, halo_diagnostics *diag);
HALO_API void halo_emu_frame_destroy(halo_emu_frame *f);
/* The image's current data: width * height * channels doubles, row 0 at the bottom (GL order);
 * an image of scale s (halo_image_info.scale): ceil(width / s) * ceil(height / s) * channels. */
HALO_API double *halo_emu_frame_image(halo_emu_frame *f, const char *name);
HALO_API halo_status halo_emu_frame_set_host_uniform(halo_emu_frame *f, const char *name, const double *values,
                                                     int count);
/* Clears every image (start of a frame). */
HALO_API void halo_emu_frame_begin(halo_emu_frame *f);
/* As halo_gl_frame_begin_group / _end_group. */
HALO_API void halo_emu_frame_begin_group(halo_emu_frame *f);
HALO_API halo_status halo_emu_frame_end_group(halo_emu_frame *f, halo_diagnostics *diag);
/* Ends a fragment: blends s->output_accum into each output image at s->fragcoord. */
HALO_API void halo_emu_frame_finish(halo_emu_frame *f, const halo_emu_sample *s);
/* Runs the image passes, then clears the reset=generation images. */
HALO_API halo_status halo_emu_frame_generate(halo_emu_frame *f, halo_diagnostics *diag);
/* Runs the at=post passes (end of frame; fill the "host_color" image first). */
HALO_API halo_status halo_emu_frame_post(halo_emu_frame *f, halo_diagnostics *diag);
/* A sampler3D host uniform (e.g. "labels"): nx*ny*nz values, x fastest; read with
 * texelFetch semantics (nearest voxel, 0 outside). The frame keeps the pointer. */
HALO_API halo_status halo_emu_frame_set_volume(halo_emu_frame *f, const char *name, const float *data, int nx, int ny,
                                               int nz);

/* ---- Error budget (libhalo/budget.c) ----------------------------------------- */

/* One measured configuration of a scene (halo-validate bench): its frame time and its
 * error against the exact reference (M = 1, float32 images, the finest sampling). */
typedef struct halo_budget_row {
    double seconds; /* median frame time */
    double error;   /* e.g. the largest absolute colour error; NaN: not measured */
} halo_budget_row;

/* Picks the cheapest row (smallest seconds; ties: the smaller error, then the lower
 * index) whose error is <= max_error and writes its index to *chosen. Rows with a
 * non-finite or negative time or error never qualify. HALO_ERROR_INPUT (USAGE, naming
 * the smallest measured error) when no row fits or the arguments are invalid. */
HALO_API halo_status halo_budget_choose(const halo_budget_row *rows, size_t count, double max_error, size_t *chosen,
                                        halo_diagnostics *diag);

/* ---- GL runtime (in the host's context) ------------------------------------ */

typedef struct halo_gl halo_gl;

/* Whether the frames read their seeds back before a generation to bound its passes
 * (halo_gl_frame_drawn_region): exact for any host, at the cost of a read-back that waits
 * for the host's draws, which a software renderer does between passes anyway. */
typedef enum halo_gl_readback {
    HALO_GL_READBACK_AUTO = 0, /* on for a software renderer (GL_RENDERER: llvmpipe, softpipe, swrast, Software
                                * Rasterizer, SwiftShader), off for a GPU */
    HALO_GL_READBACK_ON,
    HALO_GL_READBACK_OFF
} halo_gl_readback;

typedef struct halo_gl_desc {
    void *(*get_proc_address)(const char *name); /* required: the host's loader */
    halo_gl_readback readback;                   /* the policy of every frame made with this runtime (one frame's:
                                                  * halo_gl_frame_set_readback_bounds) */
    int count_fetches; /* for benchmarks: the image passes of every frame made with this runtime count the
                        * texelFetch calls they make (an atomic counter a call: much slower; desktop OpenGL
                        * 4.2 with GL_ARB_shader_atomic_counters, else halo_gl_create fails with
                        * GL_PROC_MISSING): halo_gl_frame_info.pass_fetches */
} halo_gl_desc;

/* The context current at creation must be OpenGL 3.3 core or later, or OpenGL ES 3.0 or
 * later (the WebGL 2 feature set; docs/host-contract.md, "OpenGL ES"). */
HALO_API halo_gl *halo_gl_create(const halo_gl_desc *desc, halo_diagnostics *diag);
HALO_API void halo_gl_destroy(halo_gl *gl);
/* 30, 31 or 32 when the runtime's context is OpenGL ES 3.0, 3.1 or 3.2 (link its programs
 * with target HALO_TARGET_ES300), 0 for desktop OpenGL; 0 for NULL. */
HALO_API int halo_gl_es_version(const halo_gl *gl);
/* Compiles the linked fragment program with the host's vertex shader (plain text) and
 * links them; driver messages are mapped to file:line. `defines` (NULL or "": none; e.g.
 * "#define HOST_VARIANT 1\n": lines of preprocessor directives) go into the fragment
 * shader after its #version line: a compile-time variant of the host shader without
 * linking again; the driver's messages keep the linked source's line numbers. Returns the
 * GL program name or 0. */
HALO_API unsigned halo_gl_program_build(halo_gl *gl, const halo_program *p, const char *vertex_source,
                                        const char *vertex_file, const char *defines, halo_diagnostics *diag);
/* Uploads the live parameters' current values to the GL program (which must be current). */
HALO_API void halo_gl_program_upload(halo_gl *gl, const halo_program *p, unsigned gl_program);
/* Sets a host uniform (reflection: host_uniforms) of the bound GL program by its short
 * name ("screen_right") or full name. A sampler host uniform takes one value: the
 * texture unit the host bound its texture to. */
HALO_API halo_status halo_gl_set_host_uniform(halo_gl *gl, unsigned gl_program, const char *name, const float *values,
                                              int count);

/* The images, pass programs and schedule of one program at one viewport size. */
typedef struct halo_gl_frame halo_gl_frame;
HALO_API halo_gl_frame *halo_gl_frame_create(halo_gl *gl, const halo_program *p, int width, int height,
                                             halo_diagnostics *diag);
/* From a halo_gl_frame_draw callback it only asks: the frame is destroyed when the draw
 * returns, which then reports USAGE and returns HALO_ERROR_INPUT. */
HALO_API void halo_gl_frame_destroy(halo_gl_frame *f);
/* Clears every image: call at the start of a frame. */
HALO_API void halo_gl_frame_begin(halo_gl_frame *f);
/* Feature groups (the reflection's group_count > 1): before the volume pass of each group,
 * clears every image but the frame's accumulators (reset=frame-only); after it, runs the
 * at=post passes (halo_gl_frame_post then runs only the at=final ones). */
HALO_API void halo_gl_frame_begin_group(halo_gl_frame *f);
HALO_API void halo_gl_frame_end_group(halo_gl_frame *f);
/* Attaches the output images to the host's framebuffer (bound as GL_DRAW_FRAMEBUFFER) at
 * their locations, sets the draw buffers and each output's blend; draw buffer 0 keeps
 * the host's blend state. On OpenGL ES 3.0 and 3.1 (one blend switch for all draw
 * buffers) only a program linked with one_draw has outputs, which a ray caster drawn once
 * writes once a pixel: blending is turned off for every buffer, 0 included, and
 * halo_gl_frame_draw turns it back as it was after the draw (a host calling this itself
 * does so). */
HALO_API void halo_gl_frame_attach(halo_gl_frame *f, unsigned host_framebuffer);
/* Binds the images the stages read to the host program's samplers, from texture unit
 * first_unit on. The host program must be current. */
HALO_API void halo_gl_frame_bind(halo_gl_frame *f, unsigned gl_program, int first_unit);
/* Runs the image passes and clears the reset=generation images; restores the GL state
 * it changes (framebuffer, viewport, program, blend, textures of the units it used, the
 * colour write mask of draw buffer 0: the passes write whatever the host's mask). */
HALO_API void halo_gl_frame_generate(halo_gl_frame *f);
/* End of frame: binds the host's final colour (an RGBA texture of the frame's size, over
 * its background) as the image "host_color" and runs the at=post passes; the result
 * is the image their last pass writes (e.g. "final": halo_gl_frame_read or
 * halo_gl_frame_texture). Restores the GL state it changes. */
HALO_API void halo_gl_frame_post(halo_gl_frame *f, unsigned host_color_texture);
/* The current GL texture of an image (0 if none), e.g. to blit "final". */
HALO_API unsigned halo_gl_frame_texture(const halo_gl_frame *f, const char *image);
/* Reads an image back: width * height * channels floats, row 0 at the bottom (an image of
 * scale s, halo_image_info.scale: ceil(width / s) * ceil(height / s) * channels). */
HALO_API halo_status halo_gl_frame_read(halo_gl_frame *f, const char *image, float *out);
/* The host's promise for its draws since the last halo_gl_frame_generate (or _begin):
 * they changed the frame's images (the program's outputs) only inside the pixels
 * [x0, x1) x [y0, y1) (calls add up; an empty box: nowhere). The next generation then
 * draws each pass only where its result can be nonzero: the inputs' nonzero pixels grown
 * by the pass's reach (reach= in the module), when every generation pass declares one;
 * the images are the same as without. Without a call the host may have drawn anywhere.
 * A texture taken with halo_gl_frame_texture counts as written anywhere. */
HALO_API void halo_gl_frame_drawn_region(halo_gl_frame *f, int x0, int y0, int x1, int y1);
/* on: before each generation that can be scissored (every pass declares its reach), read
 * the program's outputs back and take their nonzero pixels' box (inside the region the
 * host declared, when it did). A frame starts with its runtime's policy
 * (halo_gl_desc.readback); this changes one frame's. */
HALO_API void halo_gl_frame_set_readback_bounds(halo_gl_frame *f, int on);
/* What a frame has done so far: a copy, cheap to take. A NULL frame: every field 0. */
typedef struct halo_gl_frame_info {
    long pass_draws;   /* passes drawn by halo_gl_frame_generate since creation (for benchmarks) */
    int segment_count; /* segments drawn by the last halo_gl_frame_draw (1 when drawn once) */
    /* Where the images the linked shader reads (its samplers, e.g. halo_map's field) can be
     * nonzero now: frame pixels [x0, x1) x [y0, y1) of read_box = {x0, y0, x1, y1}, and
     * read_any 0 when they hold 0 everywhere. Known after scissored generations (see
     * drawn_region); otherwise the whole frame. A host that skips fragments whose sample is
     * empty (e.g. outside the volume's footprint) must still draw this box: halos land
     * outside the volume. */
    int read_box[4];
    int read_any;
    /* The GPU memory the frame holds now, in bytes: its images' textures (two a pass
     * writes), the rays' state between segments (host contract 2) and, drawn once (host
     * contract 3), the halo field: the stacks the host reads, the seeds' stacks, the
     * atlas of the generations, libhalo's derived gradient and its bricks. */
    size_t gpu_bytes;
    /* With halo_gl_desc.count_fetches: the texelFetch calls the image passes' fragments made
     * since creation (a tap outside its image makes none; calls a compiler would otherwise
     * merge count each); else 0. Not the host's draws or libhalo's march. The counter is 32
     * bits, summed a generation at a time (a frame drawn once: all its generations): past
     * 2^32 - 1 calls in one it wraps. */
    long long pass_fetches;
} halo_gl_frame_info;
HALO_API halo_gl_frame_info halo_gl_frame_describe(const halo_gl_frame *f);

/* The draws of one slice of a host that clips its slices to the volume (the slice host):
 * scissor boxes per variant of its shader, which do not overlap, so their order does not
 * matter. */
typedef enum halo_gl_slice_variant {
    HALO_GL_SLICE_SHADER = 0, /* the host shader: the section where the images it reads can be nonzero */
    HALO_GL_SLICE_ZERO,       /* its variant built with #define HALO_IMAGES_ZERO (halo_gl_program_build's
                               * defines): the rest of the section, where those reads are 0 */
    HALO_GL_SLICE_OUTSIDE,    /* its variant for the pixels off the volume: the rest of the read region
                               * (emissive halos land outside the volume) */
    HALO_GL_SLICE_VARIANTS
} halo_gl_slice_variant;
typedef struct halo_gl_slice_plan {
    int count[HALO_GL_SLICE_VARIANTS];     /* boxes per variant, 0..4 */
    int box[HALO_GL_SLICE_VARIANTS][4][4]; /* {x0, y0, x1, y1}: frame pixels [x0, x1) x [y0, y1) */
} halo_gl_slice_plan;
/* Plans a slice whose plane meets the volume in the window box `section` (frame pixels,
 * empty when it misses). variants 0: the shader draws the section. variants 1 (the host
 * built the ZERO and OUTSIDE variants): the section splits at the frame's read region
 * (halo_gl_frame_info.read_box) between the shader and the ZERO variant, and the OUTSIDE
 * variant draws the read region's rest. Returns the number of boxes (0: nothing to draw). */
HALO_API int halo_gl_frame_plan_slice(const halo_gl_frame *f, const int section[4], int variants,
                                      halo_gl_slice_plan *plan);

/* ---- Host contract 2: segmented ray casting (docs/host-contract.md) ---- */

/* How a single-pass ray caster is drawn: its camera, its sampling, and a callback that
 * draws its proxy geometry once. */
/* The most depth segments a frame is drawn in (halo_gl_segments_desc.segments; the
 * automatic count is capped there too). */
#define HALO_SEGMENTS_MAX 65536

/* The most bytes one exchange call of halo_gl_segments_desc carries (256 MiB). */
#define HALO_GL_EXCHANGE_MAX_BYTES ((size_t)256 << 20)
/* The default cap on the stacks of a one-draw frame's halo field (halo_gl_segments_desc.
 * field_max_bytes): 1 GiB. */
#define HALO_GL_FIELD_MAX_BYTES    ((size_t)1 << 30)

typedef struct halo_gl_segments_desc {
    const float *inverse_view_projection; /* required: column-major, clip space -> the space of the host's
                                           * ray positions (the halo_sample position: volume texture space) */
    float step;                           /* required: the host's sample spacing along a ray, in that space; segment
                            * planes are this far apart, as the slice host's slices */
    float box_min[3], box_max[3];         /* the volume's box in that space; all zero: the unit cube */
    int interval;             /* M, planes per segment; 0: the program's (the reflection's interval), or 4 */
    int segments;             /* > 0: exactly this many segments (a program linked with force_segments),
                            * at most HALO_SEGMENTS_MAX (more: USAGE) */
    unsigned framebuffer;     /* the host's framebuffer: its colour attachment 0 gets the host's output */
    int first_unit;           /* libhalo's textures from this unit on; 0: unit 8 */
    void (*draw)(void *user); /* draws the host's proxy geometry once; the host's program is current */
    void *user;
    unsigned volume_texture;   /* host contract 3 (a one_draw program): the host's volume (GL_TEXTURE_3D, the
                              * value halo_make_sample gets in its red channel, at that position) that
                              * libhalo's march samples for the seeds; required there */
    unsigned gradient_texture; /* ... and its gradient (GL_TEXTURE_3D, RGB: the contract's gradient, per voxel
                                * step) if the host has one; 0: libhalo derives one from volume_texture
                                * and keeps it while volume_texture, its size, volume_version and
                                * gradient_precision stay the same */
    int gradient_precision;    /* the derived gradient: 32 (RGBA32F, 16 bytes a voxel: exact to float), 16
                              * (RGBA16F, 8 bytes a voxel: the seeds' error in docs/accuracy.md, rows
                              * ray@one_draw_half), 0: 32 where float textures filter linearly (OpenGL, ES
                              * with OES_texture_float_linear), else 16 */
    int volume_version;        /* change it when the volume texture's contents change */
    int volume_size[3];        /* its voxels per axis; 0: queried (a context without glGetTexLevelParameteriv,
                              * such as OpenGL ES 3.0, needs them) */
    float seed_epsilon;        /* the march skips the 4^3-voxel bricks where no seed can exceed this (0: only
                              * where the gradient is zero: exact; the error it allows: docs/host-contract.md) */
    /* Host contract 3 across the pieces of a distributed volume (docs/distributed.md): this
     * renderer holds one piece, and every piece draws the same frame (camera, box, step) */
    float piece_min[3], piece_max[3]; /* the part of the ray positions' space that volume_texture
                                       * covers (its texels' outer faces); all zero: the whole volume, at
                                       * texture coordinates = positions. Pieces share their boundary
                                       * points (VTK's extents do): the march samples a piece from its
                                       * first point's centre to its last's, out to the box at its faces */
    void (*exchange)(void *user, float *values, size_t count, halo_blend blend);
    /* with a piece: called once a frame with the seeds of every depth segment
                              * (layers x height x width x 4 floats, for each seed image), to combine
                              * in place with the other pieces' by blend (max); then the passes run.
                              * Above exchange_max_bytes the layers come in consecutive calls of at
                              * most that many bytes each (at least one layer), the same calls on
                              * every piece: the host's buffer stays bounded */
    void *exchange_user;
    size_t exchange_max_bytes; /* 0: HALO_GL_EXCHANGE_MAX_BYTES */
    size_t field_max_bytes;    /* host contract 3: the cap on the halo field's stacks (one layer a depth
                                * segment: width x height x bytes a texel of each image the samples read,
                                * at the halo images' scale); 0: HALO_GL_FIELD_MAX_BYTES. Above it
                                * halo_gl_frame_draw draws nothing and reports FIELD_MEMORY with the
                                * bytes needed and what fits (image_scale 2 or 4, a larger M). The
                                * generations' atlas (one draw a pass over every segment) takes at
                                * most a quarter of it beside the stacks; where it does not fit, the
                                * generations run a segment at a time (docs/performance.md) */
} halo_gl_segments_desc;

/* Sets the camera uniforms of halo_view_at and halo_depth_at (the program must be current).
 * halo_gl_frame_draw does it; a host that draws by itself calls this. */
HALO_API halo_status halo_gl_set_camera(halo_gl *gl, unsigned gl_program, const halo_gl_segments_desc *desc,
                                        halo_diagnostics *diag);
/* Draws one frame of a host: halo_gl_frame_begin, the camera, then the proxy geometry
 * once per depth segment (halo_program_reflection(p).segment_location > 0) with the ray state carried
 * between segments and the image passes run between them, or once otherwise. Only the
 * last segment writes the host's colour (draw buffer 0). Then call halo_gl_frame_post
 * if the program has at=post passes. Restores the GL state it changes. */
HALO_API halo_status halo_gl_frame_draw(halo_gl_frame *f, unsigned gl_program, const halo_gl_segments_desc *desc,
                                        halo_diagnostics *diag);

#ifdef __cplusplus
}
#endif
#endif
