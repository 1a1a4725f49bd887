/* Rendering and timing bench configurations (bench_run.h). */
#include "bench_run.h"

#include "progress.h"
#include "render_driver.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

double halo_bench_now(void) { return halo_progress_now(); }

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

const char *halo_bench_host_name(const halo_bench_config *k)
{
    return k->slab == HALO_BENCH_RAYCAST ? "ray" : k->slab ? "slab" : "slice";
}

static void describe(const halo_bench_case *c, char *out, size_t size)
{
    const halo_bench_config *k = &c->config;
    if (!k->halos)
        snprintf(out, size, "%s, no halos, step %g", halo_bench_host_name(k), k->step);
    else if (k->no_generation)
        snprintf(out, size, "%s, seeding and mapping only", halo_bench_host_name(k));
    else
        snprintf(out, size, "%s%s, M = %d, N = %d%s%s, %d-bit, %s resolution, step %g, %s gradients%s",
                 halo_bench_host_name(k),
                 !k->one_draw   ? ""
                 : k->same_view ? " drawn once, the field reused (the same view)"
                                : " drawn once",
                 k->interval, k->passes, k->wide ? " wide" : "", k->fold ? " fold" : "", k->precision,
                 halo_bench_resolution(k), k->step, halo_bench_gradient(k), k->all_live ? ", all live" : "");
}

const char *halo_bench_gradient(const halo_bench_config *k)
{
    const char *name = halo_gradient_format_name((halo_gradient_format)k->gradient);
    return name ? name : halo_gradient_format_name(HALO_GRADIENT_FORMAT_DEFAULT);
}

const char *halo_bench_resolution(const halo_bench_config *k)
{
    return k->scale == 4 ? "1/4" : k->scale == 2 ? "1/2" : "full";
}

/* Applies the case's settings to its freshly read scene. */
static int configure_scene(const halo_bench_env *env, halo_bench_case *c)
{
    halo_scene *scene = c->scene;
    if (!c->config.halos) {
        size_t n = halo_scene_describe(scene).stage_count;
        for (size_t i = 0; i < n; ++i)
            if (halo_scene_enable(scene, halo_scene_describe(scene).stages[i], 0, env->diag) != HALO_OK)
                return 0;
    } else if (c->config.passes > 0) {
        int has_generate = 0;
        for (size_t i = 0; i < halo_scene_describe(scene).stage_count; ++i)
            has_generate |= strcmp(halo_scene_describe(scene).stages[i], "halo_generate") == 0;
        double passes = c->config.passes, on = 1.0;
        if (has_generate && halo_scene_set(scene, "halo_generate", "passes", &passes, 1, 0, env->diag) != HALO_OK)
            return 0;
        if (has_generate && c->config.wide &&
            halo_scene_set(scene, "halo_generate", "wide", &on, 1, 0, env->diag) != HALO_OK)
            return 0;
        if (has_generate && c->config.fold &&
            halo_scene_set(scene, "halo_generate", "fold", &on, 1, 0, env->diag) != HALO_OK)
            return 0;
    }
    if (c->config.step > 0.0) {
        halo_render_settings render = *halo_scene_describe(scene).render;
        render.step = c->config.step;
        halo_scene_set_render(scene, &render);
    }
    return 1;
}

static halo_driver *open_host(const halo_bench_env *env, const halo_bench_case *c, halo_gl *runtime);

static halo_driver_host case_kind(const halo_bench_case *c)
{
    return c->config.slab == HALO_BENCH_RAYCAST ? HALO_DRIVER_RAYCAST
           : c->config.slab                     ? HALO_DRIVER_SLAB
                                                : HALO_DRIVER_SLICE;
}

static int open_case(const halo_bench_env *env, halo_bench_case *c)
{
    halo_driver_host kind = case_kind(c);
    const char *text = c->scene_text ? c->scene_text : env->scene_text;
    c->scene = text ? halo_scene_load("(bench scene)", text, env->lib, env->diag)
                    : halo_scene_load(env->scene_path, NULL, env->lib, env->diag);
    if (!c->scene || !configure_scene(env, c))
        return 0;
    const halo_link_desc link = {.library = env->lib,
                                 .scene = c->scene,
                                 .all_live = c->config.all_live,
                                 .image_precision = c->config.precision ? c->config.precision : 32,
                                 .image_scale = c->config.scale,
                                 .one_draw = c->config.one_draw};
    c->program = halo_driver_link(&link, kind, 0, env->diag);
    /* no skips: halo_map's mode live (its values kept), so that the occlusion pass is linked */
    const halo_uniform_info *mode = c->program && c->config.no_skip && !c->config.all_live
                                        ? halo_program_find_uniform(c->program, "halo_map", "mode")
                                        : NULL;
    if (mode && mode->value && !mode->live) {
        double values[4] = {0, 0, 0, 0};
        int count = mode->count > 0 && mode->count <= 4 ? mode->count : 1;
        for (int k = 0; k < count; ++k)
            values[k] = mode->value[k];
        halo_program_destroy(c->program);
        c->program = halo_scene_set(c->scene, "halo_map", "mode", values, count, 1, env->diag) == HALO_OK
                         ? halo_driver_link(&link, kind, 0, env->diag)
                         : NULL;
    }
    if (!c->program)
        return 0;
    c->host = open_host(env, c, env->runtime);
    size_t values = (size_t)env->width * (size_t)env->height * 4;
    c->image = c->image ? c->image : malloc(values * sizeof(float));
    c->times = calloc((size_t)env->repeat, sizeof *c->times);
    return c->host && c->image && c->times;
}

/* The case's host (its program, volume, camera and interval) on runtime; NULL after
 * diagnostics. */
static halo_driver *open_host(const halo_bench_env *env, const halo_bench_case *c, halo_gl *runtime)
{
    halo_driver_host kind = case_kind(c);
    halo_host_desc desc = {
        .gl = env->gl, .runtime = runtime, .program = c->program, .width = env->width, .height = env->height};
    halo_driver *host = calloc(1, sizeof *host);
    if (!host || !halo_driver_create(host, kind, &desc, env->diag)) {
        free(host);
        return NULL;
    }
    const halo_render_settings *settings = halo_scene_describe(c->scene).render;
    if (halo_driver_set_volume(host, env->volume, env->dims, settings, (halo_gradient_format)c->config.gradient,
                               env->diag) != HALO_OK) {
        halo_driver_destroy(host);
        free(host);
        return NULL;
    }
    halo_driver_set_camera(host, settings->azimuth, settings->elevation, settings->zoom);
    /* beyond the last slice: the field is never generated */
    halo_driver_set_interval(host, c->config.no_generation ? 1 << 20 : c->config.interval);
    if (host->slice)
        halo_slice_set_generation_skip(host->slice, !c->config.no_skip);
    if (host->raycast)
        halo_raycast_set_seed_epsilon(host->raycast, (float)c->config.seed_epsilon);
    return host;
}

static void close_case(halo_bench_case *c)
{
    halo_driver_release(c->host, &c->program, &c->scene);
    free(c->host);
    free(c->times);
    c->host = NULL;
    c->times = NULL;
}

/* The camera of frame r (-1: the warm-up): the scene's, or 0.001 degrees of azimuth beside
 * it, alternating so that every frame's view differs from the one before and the last
 * timed frame (whose image the error columns read) is the scene's. A frame's cost is thus
 * that of a user turning the volume: a one-draw frame computes its field every frame (drawn
 * again with an unchanged view it reuses it, gl/field.c: config.same_view measures that). */
static void bench_camera(const halo_bench_env *env, halo_bench_case *c, int r)
{
    const halo_render_settings *settings = halo_scene_describe(c->scene).render;
    double nudge = (env->repeat - 1 - r) % 2 && !c->config.same_view ? 1e-3 : 0.0;
    halo_driver_set_camera(c->host, settings->azimuth + nudge, settings->elevation, settings->zoom);
}

/* The image passes' texelFetch calls a frame pixel in the case's last timed frame, on a
 * host of its own over env->counting (halo_gl_desc.count_fetches): the frame before it
 * drawn too, so that a frame that reuses the field (same_view) counts as the timed ones
 * do; 0 for a host without image passes (no frame). NAN without a counting runtime, or
 * when it fails (its diagnostics printed on stderr). */
static double count_fetches(const halo_bench_env *env, halo_bench_case *c)
{
    if (!env->counting)
        return NAN;
    halo_driver *host = open_host(env, c, env->counting);
    halo_driver *timed = c->host;
    c->host = host;                                                                      /* bench_camera's */
    float *image = malloc((size_t)env->width * (size_t)env->height * 4 * sizeof *image); /* not the case's */
    long long fetched[2] = {-1, -1};
    for (int k = 0; k < 2 && host && image; ++k) {
        bench_camera(env, c, env->repeat - 2 + k);
        if (halo_driver_render(host, image, env->diag) != HALO_OK)
            break;
        fetched[k] = halo_driver_frame(host) ? halo_gl_frame_describe(halo_driver_frame(host)).pass_fetches : 0;
    }
    if (host)
        halo_driver_destroy(host);
    free(host);
    free(image);
    c->host = timed;
    if (fetched[1] < 0) {
        fprintf(stderr, "halo-validate: bench: the fetches of a row are not counted (nan):\n");
        halo_diagnostics_print(env->diag, stderr);
        halo_diagnostics_clear(env->diag);
        return NAN;
    }
    return (double)(fetched[1] - fetched[0]) / ((double)env->width * (double)env->height);
}

int halo_bench_run(const halo_bench_env *env, halo_bench_case *cases, size_t count)
{
    int ok = 1;
    char name[160];
    size_t values = (size_t)env->width * (size_t)env->height * 4;
    for (size_t i = 0; i < count && ok; ++i) {
        describe(&cases[i], name, sizeof name);
        if (env->progress)
            fprintf(env->progress, "bench: preparing %zu of %zu: %s\n", i + 1, count, name);
        /* one frame to warm up: shader compilation on the first draw, texture residency */
        ok = open_case(env, &cases[i]);
        if (ok)
            bench_camera(env, &cases[i], -1);
        ok = ok && halo_driver_render(cases[i].host, cases[i].image, env->diag) == HALO_OK;
    }
    for (int r = 0; r < env->repeat && ok; ++r) {
        double round_start = halo_bench_now();
        for (size_t i = 0; i < count && ok; ++i) {
            halo_bench_case *c = &cases[i];
            bench_camera(env, c, r);
            env->gl->Finish();
            double start = halo_bench_now();
            ok = halo_driver_render(c->host, c->image, env->diag) == HALO_OK;
            env->gl->Finish();
            c->times[r] = halo_bench_now() - start;
        }
        if (env->progress)
            fprintf(env->progress, "bench: round %d of %d done (%.1f s)\n", r + 1, env->repeat,
                    halo_bench_now() - round_start);
    }
    for (size_t i = 0; i < count; ++i) {
        halo_bench_case *c = &cases[i];
        if (ok) {
            int n = env->repeat;
            qsort(c->times, (size_t)n, sizeof *c->times, compare_doubles);
            c->seconds = n % 2 ? c->times[n / 2] : 0.5 * (c->times[n / 2 - 1] + c->times[n / 2]);
            halo_driver_counts(c->host, &c->draws, &c->pass_draws, &c->slices);
            c->gpu_bytes =
                halo_driver_frame(c->host) ? halo_gl_frame_describe(halo_driver_frame(c->host)).gpu_bytes : 0;
            c->fetches = count_fetches(env, c);
            c->nonfinite = 0;
            for (size_t v = 0; v < values; ++v)
                c->nonfinite += !isfinite(c->image[v]);
            c->max_abs = c->rmse = c->share_over = NAN;
        }
        close_case(c);
    }
    return ok;
}

void halo_bench_image_error(const float *image, const float *base, size_t pixels, double *max_abs, double *rmse,
                            double *share)
{
    double m = 0.0, sum = 0.0;
    size_t over = 0;
    for (size_t i = 0; i < pixels; ++i) {
        int off = 0;
        for (int c = 0; c < 3; ++c) {
            double e = fabs((double)image[i * 4 + (size_t)c] - (double)base[i * 4 + (size_t)c]);
            if (!(e <= 1e30)) /* NaN or Inf: the largest possible error */
                e = INFINITY;
            m = e > m ? e : m;
            sum += e * e;
            off |= e > 1.0 / 255.0;
        }
        over += (size_t)off;
    }
    *max_abs = m;
    *rmse = pixels ? sqrt(sum / (double)(pixels * 3)) : 0.0;
    *share = pixels ? (double)over / (double)pixels : 0.0;
}

void halo_bench_errors(const halo_bench_env *env, halo_bench_case *cases, size_t count, size_t reference)
{
    size_t pixels = (size_t)env->width * (size_t)env->height;
    for (size_t i = 0; i < count; ++i)
        if (cases[i].image && cases[reference].image)
            halo_bench_image_error(cases[i].image, cases[reference].image, pixels, &cases[i].max_abs, &cases[i].rmse,
                                   &cases[i].share_over);
    const halo_bench_config *r = &cases[reference].config;
    for (size_t i = 0; i < count; ++i) {
        cases[i].halo_max_abs = NAN;
        for (size_t j = 0; j < count && cases[i].image && cases[i].config.halos; ++j) {
            const halo_bench_config *k = &cases[j].config;
            if (k->halos && !k->slab && k->interval == 1 && k->passes == r->passes && k->precision == r->precision &&
                k->scale <= 1 && !k->wide && k->step == cases[i].config.step && !k->all_live && !k->no_generation &&
                cases[j].image) {
                double rmse, share;
                halo_bench_image_error(cases[i].image, cases[j].image, pixels, &cases[i].halo_max_abs, &rmse, &share);
                break;
            }
        }
    }
    /* the gradient format's own error: against the same configuration with float gradients */
    for (size_t i = 0; i < count; ++i) {
        cases[i].gradient_max_abs = NAN;
        const halo_bench_config *a = &cases[i].config;
        for (size_t j = 0; j < count && cases[i].image && a->halos; ++j) {
            const halo_bench_config *b = &cases[j].config;
            if (cases[j].image && b->gradient == HALO_GRADIENT_FLOAT && b->halos && b->slab == a->slab &&
                b->interval == a->interval && b->passes == a->passes && b->wide == a->wide && b->fold == a->fold &&
                b->precision == a->precision && b->scale == a->scale && b->step == a->step &&
                b->all_live == a->all_live && b->no_generation == a->no_generation) {
                double rmse, share;
                halo_bench_image_error(cases[i].image, cases[j].image, pixels, &cases[i].gradient_max_abs, &rmse,
                                       &share);
                break;
            }
        }
    }
}

void halo_bench_pareto(halo_bench_case *cases, size_t count)
{
    for (size_t i = 0; i < count; ++i) {
        halo_bench_case *a = &cases[i];
        a->pareto = 0;
        if (!a->config.halos || a->config.no_generation || !isfinite(a->max_abs))
            continue;
        int dominated = 0;
        for (size_t j = 0; j < count && !dominated; ++j) {
            const halo_bench_case *b = &cases[j];
            if (j == i || !b->config.halos || b->config.no_generation || !isfinite(b->max_abs))
                continue;
            dominated = b->seconds <= a->seconds && b->max_abs <= a->max_abs &&
                        (b->seconds < a->seconds || b->max_abs < a->max_abs);
        }
        a->pareto = !dominated;
    }
}

void halo_bench_cases_free(halo_bench_case *cases, size_t count)
{
    for (size_t i = 0; i < count; ++i) {
        close_case(&cases[i]);
        free(cases[i].image);
        cases[i].image = NULL;
    }
}

size_t halo_bench_sweep(halo_bench_case *out, size_t max, int scene_passes, double finest_step)
{
    int n = scene_passes > 0 ? scene_passes : 4;
    double fine = finest_step > 0.0 ? finest_step : 0.25;
    /* the base of every axis: slice host, M = 4 (the paper's choice), float32, step 0.5,
     * the hosts' default gradient texture; the reference's gradients are float */
    const halo_bench_config base = {.halos = 1, .interval = 4, .passes = n, .precision = 32, .step = 0.5};
    struct {
        const char *axis;
        halo_bench_config k;
    } list[48];
    size_t count = 0;
#define ADD(AXIS, ...)               \
    do {                             \
        halo_bench_config k_ = base; \
        __VA_ARGS__;                 \
        list[count].axis = (AXIS);   \
        list[count++].k = k_;        \
    } while (0)
    ADD("reference", k_.interval = 1; k_.step = fine; k_.gradient = HALO_GRADIENT_FLOAT);
    static const int intervals[] = {1, 2, 4, 8, 16};
    for (int i = 0; i < 5; ++i)
        ADD("M", k_.interval = intervals[i]);
    for (int p = 1; p <= 6; ++p)
        if (p != n)
            ADD("N", k_.passes = p);
    for (int p = 1; p <= 2; ++p) /* wide N = p reaches as far as exact N = 2p */
        ADD("wide", k_.passes = p; k_.wide = 1);
    ADD("precision", k_.precision = 16);
    ADD("precision", k_.precision = 8);
    for (int g = HALO_GRADIENT_FLOAT; g < HALO_GRADIENT_FORMAT_COUNT; ++g)
        ADD("gradient", k_.gradient = g);
    ADD("skips", k_.no_skip = 1); /* the same image as M = 4 */
    ADD("resolution", k_.scale = 2);
    ADD("resolution", k_.scale = 4);
    ADD("resolution", k_.interval = 1; k_.scale = 2);
    ADD("resolution", k_.interval = 2; k_.scale = 2);
    double steps[3] = {fine, 0.5, 1.0};
    for (int i = 0; i < 3; ++i)
        if (steps[i] != 0.5 && (i == 0 || steps[i] != steps[i - 1]))
            ADD("step", k_.step = steps[i]);
    ADD("step", k_.interval = 1; k_.step = 1.0); /* M = 1 at the coarsest step: the halo error alone there */
    static const int slab_intervals[] = {4, 8, 16};
    for (int i = 0; i < 3; ++i)
        ADD("slab", k_.slab = 1; k_.interval = slab_intervals[i]);
    ADD("combined", k_.interval = 8; k_.precision = 16);
    ADD("combined", k_.interval = 16; k_.precision = 16; k_.step = 1.0);
    ADD("combined", k_.slab = 1; k_.interval = 16; k_.precision = 16; k_.step = 1.0);
    ADD("combined", k_.slab = 1; k_.interval = 8; k_.scale = 2);
    for (int slab = 0; slab <= 1; ++slab)
        for (int i = 0; i < 3; ++i)
            if (i == 0 || steps[i] != steps[i - 1])
                ADD("no halos", k_.halos = 0; k_.slab = slab; k_.interval = slab ? 16 : 1; k_.step = steps[i]);
#undef ADD
    size_t written = 0;
    for (size_t i = 0; i < count && written < max; ++i) {
        memset(&out[written], 0, sizeof out[written]);
        out[written].axis = list[i].axis;
        out[written++].config = list[i].k;
    }
    return written;
}
