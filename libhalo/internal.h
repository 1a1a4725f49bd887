/* Internal structures shared by the parts of the library. */
#ifndef HALO_INTERNAL_H
#define HALO_INTERNAL_H

#include "halo.h"
#include "glsl_lex.h"

#include <stdatomic.h>

typedef struct halo_resource_decl {
    char *name;
    char *type; /* GLSL type of the halo_sample field */
    int line;
} halo_resource_decl;

typedef struct halo_name_list {
    char **items;
    int *lines; /* annotation line of each item */
    size_t count;
} halo_name_list;

/* A top-level function of a library file, emitted only when called. */
typedef struct halo_chunk {
    char *name;
    int first_line, last_line;
    halo_name_list calls; /* halo_* names it references */
} halo_chunk;

typedef struct halo_output_decl {
    char *name;
    halo_blend blend;
    int line;
} halo_output_decl;

typedef struct halo_image_decl {
    char *name; /* without the trailing '*' of a per-channel family */
    halo_image_reset reset;
    int line;
    int family;     /* NAME*: one image per channel, NAME_0 .. NAME_{c-1} */
    int components; /* 0: the program's channel count; else 1..4 */
    double clear;   /* value every component is cleared to (default 0) */
    int clear_set;
    char *read_when; /* read_when=PARAM: the module reads the image only while some channel of
                          * PARAM is >= 0.5 or PARAM is live (NULL: always) */
} halo_image_decl;

typedef struct halo_host_uniform_decl {
    char *name, *type, *meaning;
    int line;
} halo_host_uniform_decl;

/* A pass's when= condition that names no parameter: the program's halo images are at the
 * frame's size (halo_link_desc.image_scale 1). */
#define HALO_WHEN_FULL_SIZE "halo_full_size"

/* The next term [!]NAME of a when= list A,!B,... (all must hold) from *cursor: 1 with the
 * name (truncated to cap) and *negate, *cursor past it; 0 at the end; -1 on an empty term
 * or a name that is not lower_case. */
int halo_when_next(const char **cursor, char *name, size_t cap, int *negate);

typedef struct halo_pass_decl {
    char *name, *entry, *output, *first, *repeat, *when;
    char *inputs[HALO_MAX_PASS_INPUTS]; /* NAME*: one input per channel (expanded by the linker) */
    int input_count;
    int line;
    halo_pass_at at;              /* at=post, final: runs in halo_*_frame_post, not between slices */
    int each_channel;             /* each=channel: one pass per channel; '*' names that channel's image */
    int running;                  /* running=associative (halo_pass_info.running) */
    int start;                    /* start=K: repetitions K..repeat only (0: 1) */
    int reach;                    /* reach=: -1 undeclared; else K of reach=K or reach=[M*]B^(PARAM-i)+K */
    char *reach_param;            /* PARAM of reach=[M*]B^(PARAM-i)[+K]; NULL for reach=K */
    int reach_factor, reach_base; /* M (1) and B (2 or 4) of reach=[M*]B^(PARAM-i)[+K] */
} halo_pass_decl;

struct halo_module {
    char *name, *file, *summary;
    halo_hook hook;
    int is_library;
    int module_line; /* line of the `module` annotation */
    int hook_line;
    halo_name_list needs, after;
    halo_resource_decl *provides;
    size_t provides_count;
    halo_param_info *params;
    size_t param_count;
    int *param_lines;
    char *source;
    char **lines; /* the source split into lines (views into line_storage) */
    char *line_storage;
    int line_count;
    unsigned char *is_annotation; /* per line: 1 = a #pragma halo line (not emitted) */
    halo_token_list tokens;       /* tokens of the code (annotation lines excluded) */
    halo_name_list declared;      /* names declared at global scope: private, renamed */
    halo_name_list calls;         /* halo_* names referenced */
    halo_chunk *chunks;           /* library files only */
    size_t chunk_count;
    int has_entry;
    halo_output_decl *outputs;
    size_t output_count;
    halo_image_decl *images; /* sample hook: images read; image hook: images of the schedule */
    size_t image_count;
    halo_host_uniform_decl *host_uniforms;
    size_t host_uniform_count;
    halo_pass_decl *passes;
    size_t pass_count;
    halo_name_list per_halo;
    halo_stage_info info; /* #pragma halo is: what hosts read (the reflection's stages) */
    int groups;           /* #pragma halo groups: channels parameters take up to HALO_MAX_GROUP_CHANNELS values,
                          * linked four at a time (feature groups, halo_program_select_group) */
};

struct halo_library {
    halo_module **modules;
    size_t count;
    /* References (halo.h, "Lifetimes"): the creator's, released by halo_library_destroy,
     * and one per scene and program made from the library; the last release frees it. */
    _Atomic long refs;
};

/* Another reference to lib, for a scene or program that keeps its modules. */
void halo_library_retain(const halo_library *lib);
/* Drops a reference; frees the library with the last. NULL: nothing. */
void halo_library_release(const halo_library *lib);

/* Parses a module or library file. Returns NULL on errors (reported to diag). */
halo_module *halo_module_parse(const char *file, const char *source, halo_diagnostics *diag);
void halo_module_free(halo_module *m);
int halo_name_list_has(const halo_name_list *l, const char *name);
/* As halo_name_list_has for the n bytes at name (a token in the source: no copy, no limit). */
int halo_name_list_has_n(const halo_name_list *l, const char *name, size_t n);
int halo_name_list_add(halo_name_list *l, const char *name, size_t n, int line);
void halo_name_list_free(halo_name_list *l);
/* The fields the host fills; never need a provider. */
int halo_is_host_resource(const char *name);
/* A module's name (halo_module_info.name) without the rest of halo_module_describe. */
const char *halo_module_name_of(const halo_module *m);
/* Library helpers (halo_math.glsl) found in lib. */
const halo_module *halo_library_helpers(const halo_library *lib);
/* Parses a parameter value from JSON text or a jansson value into info's layout. */
const char *halo_param_type_name(halo_param_type t);

/* A parameter's value as set by a scene or a program. */
typedef struct halo_param_value {
    int set; /* given by the scene (else the default) */
    int live;
    int count; /* elements */
    double value[HALO_MAX_COMPONENTS];
} halo_param_value;

typedef struct halo_scene_stage {
    const halo_module *module;
    int enabled;
    halo_param_value *values; /* one per module parameter */
} halo_scene_entry;

struct halo_scene {
    const halo_library *library;
    halo_scene_entry *stages;
    const char **names; /* stages[i]'s module name, for halo_scene_describe */
    size_t count;
    halo_render_settings render;
};

/* Checks values against info; on failure returns a message id and writes a text. */
int halo_param_check(const halo_param_info *info, const double *values, int count, char *why, size_t why_len);

typedef struct halo_line_origin {
    const char *file; /* points into a module, the host name, or "<libhalo>" */
    int line;
    const char *text; /* the original line (before renaming), or NULL */
} halo_line_origin;

extern const char halo_generated_file[];
/* The #version line of a target (HALO_TARGET_DEFAULT: 330 core). */
const char *halo_target_version_line(halo_target t); /* "<libhalo>": lines the linker wrote */

/* Column (1-based) of the directive after "#pragma halo", or 0. */
int halo_annotation_start(const char *line);

typedef struct halo_program_stage {
    const halo_module *module;
    halo_param_value *values;
    size_t first_uniform;           /* index into uniforms */
    halo_param_value *group_values; /* a grouped stage of a program with feature groups: the scene's
                                     * whole lists (values holds the selected group's four) */
    int prepass; /* host contract 3 (field.c): 2, its outputs feed generation passes (halo_seed); 1, it
                  * provides what such a stage needs; 0, neither */
} halo_linked_stage;

/* Lines of text, each with its origin. */
typedef struct halo_linked_text {
    char *text;
    halo_line_origin *origins;
    int count;
} halo_linked_text;

struct halo_program {
    halo_target target;
    halo_shader_kind kind;
    char *source;
    char *host_file;
    char *host_storage; /* the host's text split into lines (origins point here) */
    char **host_lines;
    halo_line_origin *origins;
    int origin_count;
    /* The linker's product (emit.c): libhalo's block, which replaces the host's marker line,
     * and its tail, after the host's last line, each with its lines' origins as emitted (the
     * host's #line directives are applied to source's origins afterwards). source is the
     * host with them spliced in (then, with engine_uniforms, a composer's declarations added);
     * a composer's declarations piece is the block and the tail together. */
    halo_linked_text block, tail;
    halo_linked_stage *stages;
    halo_stage_info *stage_infos; /* stages[i].module->info, for the reflection */
    size_t stage_count;
    halo_uniform_info *uniforms;
    size_t uniform_count;
    char **uniform_names;
    halo_output_info *outputs;
    size_t output_count;
    halo_pass_info *passes;
    size_t pass_count;
    halo_line_origin **pass_origins; /* per pass: origins of its fragment source */
    int *pass_origin_counts;
    halo_image_info *images;
    size_t image_count;
    halo_sampler_info *samplers;
    size_t sampler_count;
    halo_host_uniform_info *host_uniforms;
    size_t host_uniform_count;
    int channel_count;
    int group_count; /* feature groups: ceil(features / 4) of the grouped stages, at least 1 */
    /* the reflection's interval and reads_labels, from the current values: kept by
     * halo_program_derive (link, halo_program_set, group loads), so that the reflection,
     * which the runtime takes in its loops, stays a copy of fields */
    int derived_interval, derived_reads_labels;
    halo_uniform_decl *declarations; /* the reflection's, kept by halo_program_derive too (room for */
    size_t declaration_count;        /* every uniform: allocated at link) */
    int group;                       /* the selected one */
    int image_precision;
    int image_scale;
    /* host contract 2 (libhalo/segment.c) */
    int v2_host;          /* the host calls halo_segment_begin, halo_view_at or halo_depth_at, or names a volume */
    int segment_location; /* > 0: drawn in segments; the location of the ray state output */
    /* host contract 3 (gl/field.c): one_draw, the images of generation passes are computed by
     * libhalo's own march before the host draws (prepass: that march, linked from the same
     * scene) and read per sample from a stack of depth-segment layers; prepass_only: this is
     * such a march (only the stages with prepass != 0 run) */
    int one_draw;
    /* the host writes each pixel once a frame: linked with one_draw (host contract 3: the host
     * says so), not a slice host (gl/frame.c: unblended outputs on ES 3.0) */
    int single_pass;
    int prepass_only;
    struct halo_program *prepass;
    char *volume_sampler;   /* #pragma halo volume NAME: the gradient is derived from this sampler3D */
    char *gradient_sampler; /* #pragma halo gradient NAME: ... or read from this one (RGB, per voxel step) */
    /* for shader composers (compose.c) */
    halo_version_mode version;
    int engine_uniforms;   /* live parameters are declared by the engine; bools as int */
    int unlocated_outputs; /* outputs without layout(location) */
    int first_location;    /* > 0: the first location of the extra outputs (else after the host's) */
    char *pieces[HALO_PIECE_COUNT];
    halo_line_origin *piece_origins[HALO_PIECE_COUNT];
    int piece_origin_counts[HALO_PIECE_COUNT];
    char **strings; /* owned strings the reflection points to */
    size_t string_count;
    const halo_library *library; /* a reference (halo_library_retain) */
    /* The creator's reference, released by halo_program_destroy, and one per frame
     * (halo_gl_frame, halo_emu_frame) made from the program; the last frees it. */
    _Atomic long refs;
};
void halo_program_retain(const halo_program *p);

/* Host contract 2 (segment.c): segmented ray casting and derived inputs. */
struct halo_strbuf;
int halo_host_uses(const char *host, const char *name);
void halo_segment_emit(struct halo_strbuf *b, const halo_program *p);
void halo_segment_emit_tail(struct halo_strbuf *b, const halo_program *p);
int halo_program_has_generation_passes(const halo_program *p);
/* The uniforms the segment code declares (the camera, the segment): set by the runtime
 * (set_by names the function), or by a host that draws itself; the reflection lists
 * those a program declares among its host_uniforms. */
typedef struct halo_runtime_uniform {
    const char *name, *type, *meaning, *set_by;
    int segmented; /* 1: declared only when the program is drawn in segments; 2: only with one_draw */
} halo_runtime_uniform;
extern const halo_runtime_uniform halo_runtime_uniforms[];
extern const size_t halo_runtime_uniform_count;
int halo_program_declares_runtime_uniform(const halo_program *p, const halo_runtime_uniform *u);
/* gl/segments.c: a 4x4 column-major inverse; 0 if m is singular. */
int halo_mat4_invert(const double m[16], double out[16]);
/* gl/segments.c: how halo_gl_frame_draw draws a host (the emulation of a segmented host
 * follows the same plan). Segment j takes the samples with start + j length <= phi <
 * start + (j + 1) length, phi(P) = dot(plane.xyz, P) + plane.w. */
typedef struct halo_segment_plan {
    double eye[4];      /* the eye (w = 1), or the unit direction towards the viewer (w = 0) */
    double plane[4];    /* |xyz| = 1, phi growing away from the eye */
    double front, back; /* phi at the front and back of the box's bounding sphere */
    int segments;       /* 1: drawn once */
    double start, length;
} halo_segment_plan;
/* 0 (USAGE in diag) when the desc cannot be drawn. */
int halo_segment_plan_make(const halo_gl_segments_desc *d, const halo_program *p, halo_segment_plan *plan,
                           halo_diagnostics *diag);

/* contract.c: the structs a host fills per hook (docs/host-contract.md). */
typedef struct halo_hook_struct {
    halo_hook hook;
    const char *type, *make, *var;
    int field_count;
    const char *fields[8][2];
} halo_hook_struct;
extern const halo_hook_struct halo_hook_structs[];
extern const size_t halo_hook_struct_count;

/* compose.c: a program linked from pieces (halo_link_desc.pieces, host_source NULL). */
halo_program *halo_link_pieces(const halo_link_desc *desc, halo_diagnostics *diag);
/* The origin of the lines libhalo writes into the pieces itself (program.c): they map to
 * no module line. */
extern const char halo_pieces_file[];
/* piece_expression.c: each expression of d is one GLSL expression of its field's kind
 * (PIECE_EXPRESSION at "NAME=EXPR":1:column otherwise); returns the error count. */
int halo_pieces_check_expressions(const halo_pieces_desc *d, halo_target target, halo_diagnostics *diag);
/* link.c: halo_link of host text (desc->pieces, if set, gives only first_output_location). */
halo_program *halo_link_host(const halo_link_desc *desc, halo_diagnostics *diag);
/* Host contract 3 (prepass.c): the march of a one_draw program, linked from desc's scene. */
halo_program *halo_link_prepass(const halo_link_desc *desc, halo_diagnostics *diag);
extern const char halo_march_file[];
/* Marks the stages whose outputs feed generation passes (prepass 2) and what they need
 * (1); returns whether there is one. */
int halo_prepass_mark(halo_program *p);
/* Drops the outputs that feed generation passes (seeds 1: the host's program, whose
 * seeds the march writes), or the others (seeds 0: the march, which writes only those). */
void halo_prepass_drop_outputs(halo_program *p, int seeds);
/* Whether the march reads only the host uniforms gl/field.c sets (the image-plane axes);
 * USAGE in diag otherwise. */
int halo_prepass_host_uniforms_known(const halo_program *march, halo_diagnostics *diag);
/* Whether a march may draw eight segments at once (gl/field.c's batches): one output at
 * location 1, into an image that every generation starts from the blend's identity, and
 * no discard in its stages; else it draws one segment at a time. */
int halo_prepass_batchable(const halo_program *march);
/* The desc of p's march (halo_link_prepass): desc's scene over libhalo's march host. */
halo_link_desc halo_prepass_desc(const halo_program *p, const halo_link_desc *desc);
/* Is image written by generation passes of a one_draw program (read from the stack)? */
int halo_prepass_image(const halo_program *p, const char *image);
/* program.c: a string the program owns (freed with it), printf-style. */
char *halo_program_own(halo_program *p, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* program.c: the uniforms of the linked stages' parameters (all_live: every one a
 * uniform); feature groups (the channels lists longer than four) and loading group g.
 * 0, or -1 when memory runs out. */
int halo_program_build_uniforms(halo_program *p, int all_live);
int halo_program_set_groups(halo_program *p);
void halo_program_load_group(halo_program *p, int g);
/* Computes the program's derived_* fields from its current values. */
void halo_program_derive(halo_program *p);
/* program.c: the program's image of that name, or NULL. */
halo_image_info *halo_program_image_named(halo_program *p, const char *name);
/* Does no sample stage read image, and no pass of another image? (Its readers all declare
 * `image NAME read_when=PARAM` with the parameter off: e.g. the occlusion image of a scene
 * without occlusive halos.) Its passes are not built and its reads are zero. */
int halo_program_image_unread(const halo_program *p, const char *image);
/* Whether the host's samples read a 1/scale image (im: scale > 1) through the texture
 * unit's bilinear filter, one fetch, rather than four texel fetches (emit.c); the runtime
 * gives those images' textures and stacks GL_LINEAR (gl/frame.c, gl/field.c). */
int halo_program_image_filtered(const halo_program *p, const halo_image_info *im);
/* emit.c: is name used (as an identifier, not a field) in the module's code? */
int halo_module_uses(const halo_module *m, const char *name);
/* segment.c: "layout(location = N) " or "" for a program whose outputs carry none. */
const char *halo_output_layout(const halo_program *p, int location, char *buf, size_t len);

/* Holds glslang initialized while a public function validates (setup.c): returns 0
 * after a USAGE diagnostic naming function when halo_setup was never called (glslang
 * would crash), else 1 and the caller passes its status through
 * halo_glslang_release_with. A concurrent halo_shutdown then cannot finalize glslang
 * under the compile. */
int halo_glslang_acquire(halo_diagnostics *diag, const char *function);
halo_status halo_glslang_release_with(halo_status st);
#define HALO_WITH_GLSLANG(diag, call) \
    (halo_glslang_acquire((diag), __func__) ? halo_glslang_release_with(call) : HALO_ERROR_INPUT)

/* halo_validate's cases (libhalo/check.c): a program, a stand-alone shader and a module
 * (validate.c), a composed shader (compose.c). */
halo_status halo_validate_program(const halo_program *p, halo_diagnostics *diag);
halo_status halo_validate_source(const char *source, const char *file, halo_shader_kind kind, halo_target target,
                                 halo_diagnostics *diag);
halo_status halo_validate_module(const halo_library *lib, const halo_module *m, halo_target target,
                                 halo_diagnostics *diag);
halo_status halo_validate_composed(const halo_program *p, const char *composed, const char *composed_file,
                                   const halo_composer_piece *pieces, size_t piece_count, halo_diagnostics *diag);
/* glslang validation of one source with origins for mapping; the caller holds
 * halo_glslang_acquire. */
halo_status halo_glslang_validate(const char *source, halo_shader_kind kind, halo_target target,
                                  const halo_line_origin *origins, int origin_count, const char *fallback_file,
                                  halo_diagnostics *diag);

#endif
