/* The C side of libhalo's JavaScript package (adapters/web/libhalo.mjs): the linker, the
 * modules (embedded), scenes, reflection, live parameters and the line map, built by
 * emscripten from the same sources as the native library, behind a few functions that
 * take and return strings (JSON) and handles. glslang is not in this build: the
 * browser's WebGL compiler checks the shaders, and libhalo maps its log (halo_web_map_line).
 *
 * Every function that can fail leaves its diagnostics for halo_web_diagnostics (a JSON
 * array of {severity, id, file, line, column, message, source}), cleared by the next call. */
#include <halo.h>
#include <halo_feature.h>

#include <jansson.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef __EMSCRIPTEN__
#include <emscripten.h>
#define WEB_API EMSCRIPTEN_KEEPALIVE
#else
#define WEB_API
#endif

static halo_diagnostics *diagnostics;
static halo_library *library;
static char *last_text; /* the string the last call returned, kept until the next */

static const char *keep(char *text)
{
    free(last_text);
    last_text = text;
    return text ? text : "";
}

static void usage(halo_diagnostics *d, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void usage(halo_diagnostics *d, const char *fmt, ...)
{
    char text[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    halo_diagnostics_report(d, HALO_SEVERITY_ERROR, HALO_MSG_USAGE, "", 0, 0, NULL, "%s", text);
}

static halo_diagnostics *fresh(void)
{
    if (!diagnostics)
        diagnostics = halo_diagnostics_create();
    halo_diagnostics_clear(diagnostics);
    return diagnostics;
}

/* The library of the embedded modules, made once; 0 after a diagnostic. */
WEB_API int halo_web_init(void)
{
    halo_diagnostics *d = fresh();
    if (!library)
        library = halo_library_create(d);
    return library != NULL;
}

WEB_API const char *halo_web_version(void) { return halo_version(); }

WEB_API const char *halo_web_diagnostics(void)
{
    json_t *list = json_array();
    size_t n = diagnostics ? halo_diagnostics_describe(diagnostics).count : 0;
    for (size_t i = 0; i < n && list; ++i) {
        const halo_diagnostic *g = halo_diagnostics_get(diagnostics, i);
        json_array_append_new(list, json_pack("{s:s, s:s, s:s, s:i, s:i, s:s, s:s?}", "severity",
                                              g->severity == HALO_SEVERITY_ERROR ? "error" : "warning", "id",
                                              halo_message_name(g->id), "file", g->file ? g->file : "", "line", g->line,
                                              "column", g->column, "message", g->text ? g->text : "", "source",
                                              g->source_line));
    }
    char *text = list ? json_dumps(list, JSON_COMPACT) : NULL;
    json_decref(list);
    return keep(text);
}

/* The modules and their parameters, as halo-validate list prints them, in JSON. */
WEB_API const char *halo_web_modules(void)
{
    if (!halo_web_init())
        return "[]";
    json_t *list = json_array();
    for (size_t i = 0; i < halo_library_describe(library).module_count && list; ++i) {
        const halo_module *m = halo_library_describe(library).modules[i];
        json_array_append_new(list,
                              json_pack("{s:s, s:s, s:s}", "name", halo_module_describe(m).name, "file",
                                        halo_module_describe(m).file, "summary", halo_module_describe(m).summary));
    }
    char *text = list ? json_dumps(list, JSON_COMPACT) : NULL;
    json_decref(list);
    return keep(text);
}

static const char *string_field(json_t *o, const char *key)
{
    json_t *v = json_object_get(o, key);
    return json_is_string(v) ? json_string_value(v) : NULL;
}

static int int_field(json_t *o, const char *key, int fallback)
{
    json_t *v = json_object_get(o, key);
    return json_is_integer(v) ? (int)json_integer_value(v) : json_is_true(v) ? 1 : json_is_false(v) ? 0 : fallback;
}

/* Links a scene (JSON text) into a host shader or, with pieces, into pieces for an
 * engine's composer. options (JSON): {scene, scene_file, host, host_file, target ("330",
 * "450", "es300", "150"), kind ("fragment", "vertex"), one_draw, all_live,
 * image_precision, image_scale, version ("target", "keep", "none"), engine_uniforms,
 * pieces: {position, value, gradient, view, depth, fragcoord, color, volume,
 * gradient_texture, segmented, first_output_location}}. Returns the program, or NULL
 * after diagnostics. */
WEB_API halo_program *halo_web_link(const char *options_text)
{
    if (!halo_web_init())
        return NULL;
    halo_diagnostics *d = fresh();
    json_error_t error;
    json_t *o = json_loads(options_text ? options_text : "", 0, &error);
    if (!json_is_object(o)) {
        usage(d, "link: the options are not a JSON object (%s)", error.text);
        json_decref(o);
        return NULL;
    }
    halo_program *p = NULL;
    halo_scene *scene = NULL;
    const char *scene_text = string_field(o, "scene"), *target_name = string_field(o, "target");
    const char *version = string_field(o, "version"), *kind = string_field(o, "kind");
    halo_target target = target_name ? halo_target_from_name(target_name) : HALO_TARGET_ES300;
    if (target == HALO_TARGET_COUNT) {
        usage(d, "link: target '%s' is not 330, 450, es300 or 150", target_name);
        goto done;
    }
    if (version && strcmp(version, "target") && strcmp(version, "keep") && strcmp(version, "none")) {
        usage(d, "link: version '%s' is not target, keep or none", version);
        goto done;
    }
    if (kind && strcmp(kind, "fragment") && strcmp(kind, "vertex")) {
        usage(d, "link: kind '%s' is not fragment or vertex", kind);
        goto done;
    }
    if (scene_text) {
        const char *file = string_field(o, "scene_file");
        scene = halo_scene_load(file ? file : "scene.json", scene_text, library, d);
        if (!scene)
            goto done;
    }
    json_t *pieces = json_object_get(o, "pieces");
    halo_pieces_desc pd = {0};
    if (json_is_object(pieces)) {
        pd = (halo_pieces_desc){
            .position = string_field(pieces, "position"),
            .value = string_field(pieces, "value"),
            .gradient = string_field(pieces, "gradient"),
            .view = string_field(pieces, "view"),
            .depth = string_field(pieces, "depth"),
            .fragcoord = string_field(pieces, "fragcoord"),
            .color = string_field(pieces, "color"),
            .volume = string_field(pieces, "volume"),
            .gradient_texture = string_field(pieces, "gradient_texture"),
            .segmented = int_field(pieces, "segmented", 0),
            .first_output_location = int_field(pieces, "first_output_location", 0),
        };
    }
    const char *host = string_field(o, "host"), *host_file = string_field(o, "host_file");
    p = halo_link(
        &(halo_link_desc){
            .library = library,
            .scene = scene,
            .host_source = json_is_object(pieces) ? NULL : host,
            .host_file = host_file,
            .target = target,
            .kind = kind && !strcmp(kind, "vertex") ? HALO_SHADER_VERTEX : HALO_SHADER_FRAGMENT,
            .all_live = int_field(o, "all_live", 0),
            .image_precision = int_field(o, "image_precision", 0),
            .image_scale = int_field(o, "image_scale", 0),
            .one_draw = int_field(o, "one_draw", 0),
            .version = !version || !strcmp(version, "target") ? HALO_VERSION_TARGET
                       : !strcmp(version, "keep")             ? HALO_VERSION_KEEP
                                                              : HALO_VERSION_NONE,
            .engine_uniforms = int_field(o, "engine_uniforms", 0),
            .pieces = json_is_object(pieces) ? &pd : NULL,
        },
        d);
done:
    halo_scene_destroy(scene);
    json_decref(o);
    return p;
}

WEB_API void halo_web_program_destroy(halo_program *p) { halo_program_destroy(p); }

WEB_API const char *halo_web_program_source(const halo_program *p)
{
    const char *s = halo_program_source(p, HALO_PIECE_WHOLE);
    return s ? s : "";
}

/* piece: 0 declarations, 1 sample, 2 finish ("" when the program has none). */
WEB_API const char *halo_web_program_piece(const halo_program *p, int piece)
{
    const char *s = piece >= 0 && piece < HALO_PIECE_COUNT ? halo_program_source(p, (halo_piece)piece) : NULL;
    return s ? s : "";
}

WEB_API const char *halo_web_program_reflect(const halo_program *p) { return keep(halo_program_reflect_json(p)); }

/* Sets a live parameter (count values from values); 1, or 0 after diagnostics. */
WEB_API int halo_web_program_set(halo_program *p, const char *stage, const char *param, const double *values, int count)
{
    return halo_program_set(p, stage, param, values, count, fresh()) == HALO_OK;
}

/* Line `line` of the linked source (piece: -1; or of a piece) as {"file", "line"}: the
 * module, host or "<libhalo>" text it came from. */
WEB_API const char *halo_web_map_line(const halo_program *p, int piece, int line)
{
    const char *file = NULL;
    int origin = 0;
    int ok = halo_program_map_line(p, piece < 0 ? HALO_PIECE_WHOLE : (halo_piece)piece, line, &file, &origin);
    json_t *o = json_pack("{s:s, s:i}", "file", ok && file ? file : "", "line", ok ? origin : 0);
    char *text = o ? json_dumps(o, JSON_COMPACT) : NULL;
    json_decref(o);
    return keep(text);
}

/* ---- The GL runtime over WebGL 2 (host contract 3: the halo field before the host draws) ----
 *
 * The page's WebGL 2 context is registered with emscripten's GL layer by libhalo.mjs
 * (GL.registerContext, then made current), and the page's WebGL objects that libhalo is
 * handed (the host's program, volume texture, framebuffer) get names in its tables; these
 * functions then run libhalo's C runtime on that context, as on OpenGL ES 3.0. */
#ifdef __EMSCRIPTEN__
#include <emscripten/html5_webgl.h>

/* The host's proxy geometry, drawn by the page: libhalo.mjs's frame.draw sets Module.haloDraw. */
EM_JS(void, web_draw_proxy, (void), { Module.haloDraw(); });

static void draw_proxy(void *user)
{
    (void)user;
    web_draw_proxy();
}

static void *get_proc_address(const char *name) { return emscripten_webgl_get_proc_address(name); }
#endif

/* libhalo's GL runtime on the current context (a registered WebGL 2 context), or NULL
 * after diagnostics. */
WEB_API halo_gl *halo_web_gl_create(void)
{
    halo_diagnostics *d = fresh();
#ifdef __EMSCRIPTEN__
    return halo_gl_create(&(halo_gl_desc){.get_proc_address = get_proc_address}, d);
#else
    usage(d, "the GL runtime needs the WebAssembly build");
    return NULL;
#endif
}

WEB_API void halo_web_gl_destroy(halo_gl *gl) { halo_gl_destroy(gl); }

/* A frame of width x height for a linked program (with one_draw: its halo field), or NULL
 * after diagnostics. readback 1: the passes' bounds read back (a software renderer: WebGL
 * masks GL_RENDERER, so the page says so), 0: not, -1: the runtime's choice. */
WEB_API halo_gl_frame *halo_web_frame_create(halo_gl *gl, const halo_program *p, int width, int height, int readback)
{
    halo_gl_frame *f = halo_gl_frame_create(gl, p, width, height, fresh());
    if (f && readback >= 0)
        halo_gl_frame_set_readback_bounds(f, readback);
    return f;
}

WEB_API void halo_web_frame_destroy(halo_gl_frame *f) { halo_gl_frame_destroy(f); }

static int float_array(json_t *o, const char *key, float *out, size_t count, int required, halo_diagnostics *d)
{
    json_t *a = json_object_get(o, key);
    if (!a && !required)
        return 1;
    if (!json_is_array(a) || json_array_size(a) != count) {
        usage(d, "frame.draw: %s must be an array of %zu numbers", key, count);
        return 0;
    }
    for (size_t i = 0; i < count; ++i) {
        json_t *v = json_array_get(a, i);
        if (!json_is_number(v)) {
            usage(d, "frame.draw: %s[%zu] is not a number", key, i);
            return 0;
        }
        out[i] = (float)json_number_value(v);
    }
    return 1;
}

/* Draws one frame of the host's program (a GL name) through halo_gl_frame_draw: for a
 * one_draw program the halo field of every depth segment, then the host's proxy once
 * (Module.haloDraw). options (JSON): {inverse_view_projection: 16 numbers, step,
 * box_min, box_max, interval, segments, framebuffer, first_unit, volume_texture,
 * gradient_texture, gradient_precision, volume_version, volume_size: 3 numbers,
 * seed_epsilon, field_max_bytes}. 1, or 0 after diagnostics. */
WEB_API int halo_web_frame_draw(halo_gl_frame *f, unsigned gl_program, const char *options_text)
{
    halo_diagnostics *d = fresh();
#ifdef __EMSCRIPTEN__
    json_error_t error;
    json_t *o = json_loads(options_text ? options_text : "", 0, &error);
    float inverse[16], box_min[3] = {0}, box_max[3] = {0}, size[3] = {0};
    int ok = 0;
    if (!json_is_object(o)) {
        usage(d, "frame.draw: the options are not a JSON object (%s)", error.text);
        goto done;
    }
    json_t *step = json_object_get(o, "step"), *epsilon = json_object_get(o, "seed_epsilon");
    if (!json_is_number(step)) {
        usage(d, "frame.draw: step (the host's sample spacing) is required");
        goto done;
    }
    if (!float_array(o, "inverse_view_projection", inverse, 16, 1, d) || !float_array(o, "box_min", box_min, 3, 0, d) ||
        !float_array(o, "box_max", box_max, 3, 0, d) || !float_array(o, "volume_size", size, 3, 0, d))
        goto done;
    json_t *max_bytes = json_object_get(o, "field_max_bytes");
    halo_gl_segments_desc desc = {
        .inverse_view_projection = inverse,
        .step = (float)json_number_value(step),
        .box_min = {box_min[0], box_min[1], box_min[2]},
        .box_max = {box_max[0], box_max[1], box_max[2]},
        .interval = int_field(o, "interval", 0),
        .segments = int_field(o, "segments", 0),
        .framebuffer = (unsigned)int_field(o, "framebuffer", 0),
        .first_unit = int_field(o, "first_unit", 0),
        .draw = draw_proxy,
        .volume_texture = (unsigned)int_field(o, "volume_texture", 0),
        .gradient_texture = (unsigned)int_field(o, "gradient_texture", 0),
        .gradient_precision = int_field(o, "gradient_precision", 0),
        .volume_version = int_field(o, "volume_version", 0),
        .volume_size = {(int)size[0], (int)size[1], (int)size[2]},
        .seed_epsilon = json_is_number(epsilon) ? (float)json_number_value(epsilon) : 0.0f,
        .field_max_bytes = json_is_number(max_bytes) ? (size_t)json_number_value(max_bytes) : 0,
    };
    ok = halo_gl_frame_draw(f, gl_program, &desc, d) == HALO_OK;
done:
    json_decref(o);
    return ok;
#else
    usage(d, "the GL runtime needs the WebAssembly build");
    return 0;
#endif
}

/* The passes after the host's draw (at=post and final: outlines) over the host's colour
 * texture of this frame (a GL name), through halo_gl_frame_post (p: the frame's program). The GL name of the image
 * the last of them writes (RGBA, the frame's size), or 0 when the program has no such pass. */
WEB_API unsigned halo_web_frame_post(halo_gl_frame *f, const halo_program *p, unsigned color_texture)
{
    fresh();
    const halo_reflection r = halo_program_reflection(p);
    const char *name = NULL; /* the at=post passes run first, then the at=final ones */
    for (int at = HALO_PASS_AT_POST; at <= HALO_PASS_AT_FINAL; ++at)
        for (size_t i = 0; i < r.pass_count; ++i)
            if ((int)r.passes[i].at == at)
                name = r.passes[i].output;
    if (!name)
        return 0;
    halo_gl_frame_post(f, color_texture);
    return halo_gl_frame_texture(f, name);
}

/* Reads image (the frame's size, its channels a pixel, rows from the bottom) into out as
 * floats. 1, or 0 after diagnostics. */
WEB_API int halo_web_frame_read(halo_gl_frame *f, const char *image, float *out)
{
    halo_diagnostics *d = fresh();
    if (halo_gl_frame_read(f, image, out) == HALO_OK)
        return 1;
    usage(d, "frame.read: the frame has no image '%s', or it could not be read", image ? image : "(null)");
    return 0;
}

/* The host's draws in the last frame.draw (halo_gl_frame_info.segment_count): 1 for a one_draw
 * program, whose field's depth segments are libhalo's own draws. */
WEB_API int halo_web_frame_segment_count(const halo_gl_frame *f) { return halo_gl_frame_describe(f).segment_count; }
/* The frame's GPU memory in bytes (halo_gl_frame_info.gpu_bytes), as a double: exact below 2^53. */
WEB_API double halo_web_frame_gpu_bytes(const halo_gl_frame *f) { return (double)halo_gl_frame_describe(f).gpu_bytes; }

/* Feature halos (docs/feature-halos.md): the halo buffer of the program's feature_halo
 * stage (its parameters), splatted by the GL runtime from values (nx*ny*nz floats in
 * [0, 1], x fastest: the volume as the stages read it). NULL after diagnostics. */
WEB_API halo_feature_buffer *halo_web_feature_create(halo_gl *gl, const halo_program *p, const float *values, int nx,
                                                     int ny, int nz)
{
    halo_diagnostics *d = fresh();
    halo_feature_desc desc;
    if (halo_feature_desc_from_program(p, &desc) != HALO_OK) {
        usage(d, "featureBuffer: the program has no feature_halo stage");
        return NULL;
    }
    const int dims[3] = {nx, ny, nz};
    return halo_feature_buffer_create(gl, values, dims, &desc, d);
}

/* Splats the buffer for the unit view vector (sample -> eye, the volume's voxel space,
 * one direction for the volume). 1, or 0 after diagnostics. */
WEB_API int halo_web_feature_build(halo_feature_buffer *b, double x, double y, double z)
{
    fresh();
    const double view[3] = {x, y, z};
    return halo_feature_buffer_build(b, view) == HALO_OK;
}

/* The buffer's GL texture (a name in emscripten's tables: GL.textures). */
WEB_API unsigned halo_web_feature_texture(const halo_feature_buffer *b)
{
    return halo_feature_buffer_describe(b).texture;
}

WEB_API void halo_web_feature_destroy(halo_feature_buffer *b) { halo_feature_buffer_destroy(b); }
