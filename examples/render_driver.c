/* The render driver (render_driver.h). */
#include "render_driver.h"

#include "hosts/host_common.h"
#include "hosts/slab.h"
#include "progress.h"
#include "volume.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The texture unit the feature halo buffer is bound to: the hosts use 0..2, the slice
 * host's halo images 3 on. */
#define FEATURE_BUFFER_UNIT 15

const char *const halo_driver_host_names[] = {"auto", "slice", "slab", "raycast", NULL};

const char *halo_driver_fragment(halo_driver_host kind)
{
    return kind == HALO_DRIVER_RAYCAST ? "raycast.frag" : kind == HALO_DRIVER_SLAB ? "slab.frag" : "slice.frag";
}

/* ---- Halo stages -------------------------------------------------------------------- */

/* A host for probing what a stage links to: calls halo_finish, as the slice host does. */
static const char probe_host[] =
    "#version 330 core\n"
    "#pragma halo declarations\n"
    "layout(location = 0) out vec4 frag_color;\n"
    "void main()\n"
    "{\n"
    "    vec4 color = vec4(0.0);\n"
    "#ifdef HALO_LINKED\n"
    "    halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.0, 0.1, 0.0), vec3(0.0, 0.0, 1.0), 0.5,\n"
    "                                     gl_FragCoord.xy, vec3(1.0), 0.5);\n"
    "    halo_apply(s);\n"
    "    color = vec4(s.color, s.opacity);\n"
    "    halo_finish();\n"
    "#endif\n"
    "    frag_color = color;\n"
    "}\n";

typedef struct link_shape {
    int ok;
    size_t outputs, samplers, passes;
    int feature_buffer; /* reads the halo buffer of feature halos (halo_feature.h) */
} link_shape;

static link_shape probe_link(const halo_library *lib, const char *const *stages, size_t count)
{
    link_shape shape = {0};
    halo_scene *scene = halo_scene_create(lib);
    int ok = scene != NULL;
    for (size_t i = 0; ok && i < count; ++i)
        ok = halo_scene_enable(scene, stages[i], 1, NULL) == HALO_OK;
    halo_program *p =
        ok ? halo_link(
                 &(halo_link_desc){.library = lib, .scene = scene, .host_source = probe_host, .host_file = "probe"},
                 NULL)
           : NULL;
    if (p) {
        shape.ok = 1;
        shape.outputs = halo_program_reflection(p).output_count;
        shape.samplers = halo_program_reflection(p).sampler_count;
        shape.passes = halo_program_reflection(p).pass_count;
        for (size_t i = 0; i < halo_program_reflection(p).host_uniform_count; ++i)
            shape.feature_buffer |= !strcmp(halo_program_reflection(p).host_uniforms[i].name, HALO_HOST_FEATURE_BUFFER);
    }
    halo_program_destroy(p);
    halo_scene_destroy(scene);
    return shape;
}

size_t halo_driver_find_halo_stages(const halo_library *lib, const halo_scene *scene, int *is_halo)
{
    halo_scene_info info = halo_scene_describe(scene);
    size_t n = info.stage_count, found = 0;
    const char **base = calloc(n + 1, sizeof *base);
    int *pending = calloc(n + 1, sizeof *pending);
    if (!base || !pending) {
        free(base);
        free(pending);
        return 0;
    }
    for (size_t i = 0; i < n; ++i) {
        const char *name = info.stages[i];
        const halo_module *m = halo_library_find(lib, name);
        is_halo[i] = 0;
        if (m && halo_module_describe(m).hook == HALO_HOOK_IMAGE) {
            is_halo[i] = 1;
            continue;
        }
        link_shape alone = probe_link(lib, &name, 1);
        if (alone.ok && alone.feature_buffer) { /* feature halos go with any host */
            is_halo[i] = HALO_DRIVER_FEATURE;
            continue;
        }
        if (alone.ok)
            is_halo[i] = alone.outputs || alone.samplers || alone.passes;
        else
            pending[i] = 1;
    }
    size_t base_count = 0;
    for (size_t i = 0; i < n; ++i)
        if (is_halo[i] == HALO_DRIVER_HALO)
            base[base_count++] = info.stages[i];
    link_shape without = probe_link(lib, base, base_count);
    for (size_t i = 0; i < n; ++i) {
        if (!pending[i] || !without.ok)
            continue;
        base[base_count] = info.stages[i];
        link_shape with = probe_link(lib, base, base_count + 1);
        is_halo[i] = with.ok && (with.outputs > without.outputs || with.samplers > without.samplers ||
                                 with.passes > without.passes);
    }
    for (size_t i = 0; i < n; ++i)
        found += is_halo[i] == HALO_DRIVER_HALO;
    free(base);
    free(pending);
    return found;
}

halo_driver_host halo_driver_choose_host(const halo_library *lib, const halo_scene *scene)
{
    int *is_halo = calloc(halo_scene_describe(scene).stage_count + 1, sizeof *is_halo);
    size_t found = is_halo ? halo_driver_find_halo_stages(lib, scene, is_halo) : 0;
    free(is_halo);
    return found ? HALO_DRIVER_SLICE : HALO_DRIVER_RAYCAST;
}

int halo_driver_has_feature_halos(const halo_library *lib, const halo_scene *scene)
{
    halo_scene_info info = halo_scene_describe(scene);
    for (size_t i = 0; i < info.stage_count; ++i) {
        const char *name = info.stages[i];
        if (probe_link(lib, &name, 1).feature_buffer)
            return 1;
    }
    return 0;
}

int halo_driver_disable_halo_stages(halo_scene *scene, const int *is_halo, halo_diagnostics *diag)
{
    /* Collect the names first: disabling changes the scene's stage list. */
    halo_scene_info info = halo_scene_describe(scene);
    size_t n = info.stage_count, count = 0;
    char **names = calloc(n + 1, sizeof *names);
    int ok = names != NULL;
    for (size_t i = 0; ok && i < n; ++i)
        if (is_halo[i])
            ok = (names[count++] = strdup(info.stages[i])) != NULL;
    for (size_t i = 0; ok && i < count; ++i)
        ok = halo_scene_enable(scene, names[i], 0, diag) == HALO_OK;
    for (size_t i = 0; names && i < count; ++i)
        free(names[i]);
    free(names);
    return ok;
}

float *halo_driver_builtin_volume(int size, const double window[2])
{
    float *v = halo_volume_create(size);
    if (v && (window[0] != 0.0 || window[1] != 1.0)) {
        size_t n = (size_t)size * (size_t)size * (size_t)size;
        for (size_t i = 0; i < n; ++i) {
            double x = (v[i] - window[0]) / (window[1] - window[0]);
            v[i] = (float)(x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x);
        }
    }
    return v;
}

halo_program *halo_driver_link(const halo_link_desc *desc, halo_driver_host kind, int validate, halo_diagnostics *diag)
{
    const char *file = halo_driver_fragment(kind);
    char *source = halo_host_load(file, NULL, diag);
    if (!source)
        return NULL;
    halo_link_desc d = *desc;
    d.host_source = source;
    d.host_file = file;
    halo_program *p = halo_link(&d, diag);
    free(source);
    if (p && validate && halo_validate(&(halo_validate_desc){.program = p}, diag) != HALO_OK) {
        halo_program_destroy(p);
        p = NULL;
    }
    return p;
}

/* ---- The host ------------------------------------------------------------------------- */

int halo_driver_create(halo_driver *d, halo_driver_host kind, const halo_host_desc *desc, halo_diagnostics *diag)
{
    memset(d, 0, sizeof *d);
    d->kind = kind == HALO_DRIVER_AUTO ? HALO_DRIVER_SLICE : kind;
    d->runtime = desc->runtime;
    d->gl = desc->gl;
    d->program = desc->program;
    d->width = desc->width;
    d->height = desc->height;
    if (d->kind == HALO_DRIVER_RAYCAST)
        d->raycast = halo_raycast_create(desc, diag);
    else if (d->kind == HALO_DRIVER_SLAB)
        d->slice = halo_slab_create(desc, diag);
    else
        d->slice = halo_slice_create(desc, diag);
    return d->raycast || d->slice;
}

void halo_driver_destroy(halo_driver *d)
{
    if (d->post_texture)
        d->gl->DeleteTextures(1, &d->post_texture);
    halo_feature_buffer_destroy(d->feature);
    halo_raycast_destroy(d->raycast);
    halo_slice_destroy(d->slice);
    memset(d, 0, sizeof *d);
}

void halo_driver_release(halo_driver *d, halo_program **program, halo_scene **scene)
{
    if (d)
        halo_driver_destroy(d);
    halo_program_destroy(*program);
    halo_scene_destroy(*scene);
    *program = NULL;
    *scene = NULL;
}

halo_status halo_driver_set_volume(halo_driver *d, const float *volume, const int dims[3],
                                   const halo_render_settings *settings, halo_gradient_format gradient,
                                   halo_diagnostics *diag)
{
    halo_status status;
    if (d->raycast) {
        status = halo_raycast_set_volume(d->raycast, volume, dims[0], dims[1], dims[2], diag);
        return status != HALO_OK ? status : halo_raycast_set_render(d->raycast, settings, diag);
    }
    halo_slice_set_gradient_format(d->slice, gradient);
    status = halo_slice_set_volume(d->slice, volume, dims[0], dims[1], dims[2], diag);
    return status != HALO_OK ? status : halo_slice_set_render(d->slice, settings, diag);
}

halo_status halo_driver_set_labels(halo_driver *d, const float *labels, const int dims[3], halo_diagnostics *diag)
{
    if (!d->slice) /* the ray caster has no label texture */
        return HALO_ERROR_INPUT;
    return halo_slice_set_labels(d->slice, labels, dims[0], dims[1], dims[2], diag);
}

void halo_driver_set_camera(halo_driver *d, double azimuth, double elevation, double zoom)
{
    if (d->raycast)
        halo_raycast_set_camera(d->raycast, azimuth, elevation, zoom);
    if (d->slice)
        halo_slice_set_camera(d->slice, azimuth, elevation, zoom);
}

void halo_driver_set_interval(halo_driver *d, int interval)
{
    if (d->raycast)
        halo_raycast_set_segments(d->raycast, interval, 0);
    if (d->slice)
        halo_slice_set_interval(d->slice, interval);
}

void halo_driver_set_field_max_bytes(halo_driver *d, size_t bytes)
{
    if (d->raycast)
        halo_raycast_set_field_max_bytes(d->raycast, bytes);
    if (d->slice)
        halo_slice_set_field_max_bytes(d->slice, bytes);
}

const char *halo_driver_gradient_name(const halo_driver *d)
{
    if (!d->slice || !halo_slice_reads_gradients(d->slice))
        return NULL;
    return halo_gradient_format_name(halo_slice_gradient_format(d->slice));
}

halo_gl_frame *halo_driver_frame(const halo_driver *d)
{
    return d->slice ? halo_slice_frame(d->slice) : halo_raycast_frame(d->raycast);
}

void halo_driver_eye(const halo_driver *d, double eye[3])
{
    if (d->raycast) {
        halo_raycast_state state;
        halo_raycast_get_state(d->raycast, &state);
        memcpy(eye, state.eye, 3 * sizeof *eye);
    } else {
        halo_slice_state state;
        halo_slice_get_state(d->slice, &state);
        memcpy(eye, state.eye, 3 * sizeof *eye);
    }
}

void halo_driver_bind_feature(halo_driver *d, const halo_feature_buffer *buffer)
{
    const halo_glfuncs *f = d->gl;
    unsigned gl_program = d->raycast ? halo_raycast_gl_program(d->raycast) : halo_slice_gl_program(d->slice);
    f->UseProgram(gl_program);
    f->Uniform1i(f->GetUniformLocation(gl_program, HALO_HOST_FEATURE_BUFFER), FEATURE_BUFFER_UNIT);
    f->UseProgram(0);
    f->ActiveTexture(GL_TEXTURE0 + FEATURE_BUFFER_UNIT);
    f->BindTexture(GL_TEXTURE_3D, halo_feature_buffer_describe(buffer).texture);
    f->ActiveTexture(GL_TEXTURE0);
}

int halo_driver_update_feature(halo_driver *d, const float *volume, const int dims[3], halo_diagnostics *diag)
{
    double start = halo_progress_now();
    if (!d->feature) {
        halo_feature_desc fd;
        if (halo_feature_desc_from_program(d->program, &fd) != HALO_OK)
            return 0;
        d->feature = halo_feature_buffer_create(d->runtime, volume, dims, &fd, diag);
        if (!d->feature)
            return 0;
    }
    double eye[3];
    halo_driver_eye(d, eye);
    /* texture space = voxel space up to the scale for the cube the hosts render */
    double view[3] = {eye[0] - 0.5, eye[1] - 0.5, eye[2] - 0.5};
    double length = sqrt(view[0] * view[0] + view[1] * view[1] + view[2] * view[2]);
    for (int k = 0; k < 3 && length > 0.0; ++k)
        view[k] /= length;
    if (halo_feature_buffer_build(d->feature, view) != HALO_OK) {
        if (d->tool)
            fprintf(stderr, "%s: error: building the feature halo buffer failed\n", d->tool);
        return 0;
    }
    halo_driver_bind_feature(d, d->feature);
    d->gl->Finish();
    if (d->tool && !d->quiet)
        fprintf(stderr, "%s: feature halo buffer: %zu qualified voxels, built in %.2f s\n", d->tool,
                halo_feature_buffer_describe(d->feature).qualified, halo_progress_now() - start);
    return 1;
}

/* ---- The frame ------------------------------------------------------------------------- */

/* Runs the post passes on the slice host's image (rgba, over its background) and
 * replaces rgba with their result; the ray caster runs them itself. The colour
 * texture stays until the driver is destroyed: the frame's inputs can be read back
 * after the frame (halo-outline --check). */
static halo_status run_post_passes(halo_driver *d, halo_gl_frame *frame, float *rgba, halo_diagnostics *diag)
{
    const halo_glfuncs *f = d->gl;
    if (!d->post_texture) {
        f->GenTextures(1, &d->post_texture);
        halo_host_image_texture(f, d->post_texture, GL_RGBA32F, d->width, d->height, GL_RGBA, GL_FLOAT);
    } else {
        f->BindTexture(GL_TEXTURE_2D, d->post_texture);
    }
    f->TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, d->width, d->height, GL_RGBA, GL_FLOAT, rgba);
    f->BindTexture(GL_TEXTURE_2D, 0);
    halo_status status = halo_host_post_passes(frame, d->program, d->post_texture, d->width, d->height, rgba, diag);
    if (status == HALO_OK && f->GetError() != GL_NO_ERROR)
        status = HALO_ERROR_IO;
    return status;
}

halo_status halo_driver_render(halo_driver *d, float *rgba, halo_diagnostics *diag)
{
    const char *progress = d->quiet ? NULL : d->tool;
    char what[160];
    snprintf(what, sizeof what, "rendering %dx%d with the %s host", d->width, d->height,
             halo_driver_host_names[d->kind]);
    halo_progress step;
    halo_status rendered;
    halo_gl_frame *frame = halo_driver_frame(d);
    if (d->raycast) {
        halo_progress_begin(&step, progress, what, 1);
        long before = frame ? halo_gl_frame_describe(frame).pass_draws : 0;
        rendered = halo_raycast_render(d->raycast, rgba, diag);
        d->pass_draws = frame ? halo_gl_frame_describe(frame).pass_draws - before : 0;
    } else {
        /* progress per slice (slab) from the host; no timer thread */
        halo_progress_begin(&step, progress, what, 0);
        step.gl = d->gl;
        step.unit = d->kind == HALO_DRIVER_SLAB ? "slab" : "slice";
        halo_slice_set_progress(d->slice, progress ? halo_progress_count : NULL, progress ? &step : NULL);
        rendered = halo_slice_render(d->slice, rgba, diag);
        halo_slice_set_progress(d->slice, NULL, NULL);
    }
    const halo_image_info *post = frame ? halo_host_post_image(d->program) : NULL;
    if (rendered == HALO_OK && post && d->slice)
        rendered = run_post_passes(d, frame, rgba, diag);
    long draws, pass_draws;
    halo_driver_counts(d, &draws, &pass_draws, NULL);
    if (d->slice)
        snprintf(what, sizeof what, "rendered %ld %s and %ld image passes%s", draws,
                 d->kind == HALO_DRIVER_SLAB ? "slabs" : "slices", pass_draws, post ? " (and the post passes)" : "");
    else if (frame)
        snprintf(what, sizeof what, "rendered %ld segment%s and %ld image passes%s", draws, draws == 1 ? "" : "s",
                 pass_draws, post ? " (and the post passes)" : "");
    else
        snprintf(what, sizeof what, "rendered");
    halo_progress_end(&step, rendered != HALO_OK, what);
    return rendered;
}

void halo_driver_counts(const halo_driver *d, long *draws, long *pass_draws, int *slices)
{
    if (d->slice) {
        halo_slice_state state;
        halo_slice_get_state(d->slice, &state);
        if (slices)
            *slices = state.slice_count;
        *draws = halo_slice_draws(d->slice);
        *pass_draws = halo_slice_pass_draws(d->slice);
        return;
    }
    halo_gl_frame *frame = halo_raycast_frame(d->raycast);
    if (slices)
        *slices = 0;
    *draws = frame ? halo_gl_frame_describe(frame).segment_count : 1;
    *pass_draws = d->pass_draws;
}
