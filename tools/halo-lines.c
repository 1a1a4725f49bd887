/* halo-lines: renders dense line data with depth-dependent halos (Everts et al. 2009)
 * through libhalo's line stages and the example line host, offline (headless OpenGL).
 *
 *   halo-lines [--lines FILE | --builtin streamlines|knots] [--scene S] [-o OUT]
 *              [--size WxH] [--no-halos] [--stereo anaglyph] [--azimuth A]
 *              [--elevation E] [--zoom Z] [--write-lines FILE]
 *   halo-lines --bench [--frames N] [--size WxH] [--lines FILE | --builtin ...]
 *   halo-lines --conform [--row NAME] [-v]
 *
 * Exit status: 0 success, 1 the input has errors (diagnostics on stderr), 2 usage or
 * I/O failure. */
#include "halo.h"
#include "conform_lines.h"
#include "halo_gl_loader.h"
#include "gl/headless.h"
#include "hosts/lines.h"
#include "image_write.h"
#include "linegen.h"
#include "progress.h"
#include "tool_options.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The built-in scene, embedded: black lines with white halos (the paper's look). */
#define DEFAULT_SCENE "examples/scenes/lines-default.json"

/* The paper's first data set has 260 836 vertices (11 306 lines). */
#define BENCH_POINTS 260836

static void usage(FILE *out)
{
    fputs(
        "Usage: halo-lines [--lines FILE | --builtin streamlines|knots] [--scene S] [-o OUT]\n"
        "                  [--size WxH] [--no-halos] [--stereo anaglyph] [--azimuth A]\n"
        "                  [--elevation E] [--zoom Z] [--write-lines FILE]\n"
        "       halo-lines --bench [--frames N] [--size WxH] [--lines FILE | --builtin ...]\n"
        "       halo-lines --conform [--row NAME] [-v]\n"
        "Renders lines with depth-dependent halos (Everts et al. 2009) through libhalo's\n"
        "line stages (headless OpenGL: EGL or OSMesa) and writes an image.\n"
        "\n"
        "  --lines FILE       polylines in the text format of docs/polyline-format.md\n"
        "  --builtin NAME     streamlines (ABC flow, default) or knots (a trefoil tube)\n"
        "  --scene S          scene file (JSON); default: black lines with white halos\n"
        "  -o OUT             output image, .png or .exr; default halo-lines.png\n"
        "  --size WxH         image size, 1..16384 each (print: 4096x4096); default 800x800\n"
        "  --no-halos         plain lines: the fragment stages (the halo) off, the strip\n"
        "                     narrowed to the line core\n"
        "  --stereo anaglyph  red (left eye) / cyan (right eye) stereo image\n"
        "  --azimuth A, --elevation E, --zoom Z   camera (default: the scene's)\n"
        "  --write-lines FILE write the line data in the text format and go on\n"
        "  --bench            frame time with and without halos, as a ratio (default data:\n"
        "                     streamlines of 260 836 vertices, as the paper's first data set)\n"
        "  --frames N         frames per variant for --bench, 1..1000; default 10\n"
        "  --conform          the line conformance rows (GPU against the C emulation)\n"
        "  --row NAME         only this conformance row (or all rows of a stage)\n"
        "  -v                 details of failing conformance rows\n"
        "  --backend B        headless OpenGL: egl, osmesa or auto (default: EGL when it\n"
        "                     has a hardware renderer, else OSMesa)\n"
        "  --help             show this help\n"
        "\n"
        "Exit status: 0 success, 1 the input has errors, 2 usage or I/O failure.\n",
        out);
}

typedef struct options {
    const char *lines_path, *builtin, *scene_path, *output, *write_lines, *row;
    int width, height, no_halos, stereo, bench, frames, conform, verbose;
    double azimuth, elevation, zoom;
    int has_azimuth, has_elevation, has_zoom;
} options;

/* Loads the scene (file or built-in) once per use: each host keeps the stages of its hook. */
static halo_scene *load_scene(const options *o, const halo_library *lib, halo_diagnostics *diag)
{
    if (o->scene_path)
        return halo_scene_load(o->scene_path, NULL, lib, diag);
    const char *text = halo_tool_embedded_scene(DEFAULT_SCENE);
    if (!text) {
        fprintf(stderr, "halo-lines: error: %s is not embedded\n", DEFAULT_SCENE);
        return NULL;
    }
    return halo_scene_load(DEFAULT_SCENE " (built in)", text, lib, diag);
}

/* The parameter a linked stage names with `is KEY=PARAM` (strip_width, core_fraction). */
static const halo_uniform_info *stage_property(const halo_program *p, int core_fraction)
{
    for (size_t i = 0; p && i < halo_program_reflection(p).stage_count; ++i) {
        const halo_stage_info *s = &halo_program_reflection(p).stages[i];
        const char *param = core_fraction ? s->core_fraction : s->strip_width;
        const halo_uniform_info *u = param ? halo_program_find_uniform(p, s->name, param) : NULL;
        if (u && u->count > 0)
            return u;
    }
    return NULL;
}

/* Links both hosts. Without halos: every fragment stage off, and the strip (the vertex
 * stage's `is strip_width=`) narrowed to the line core (the fragment stage's `is
 * core_fraction=`), so the lines keep their visible width. */
static int link_programs(const options *o, const halo_library *lib, int halos, halo_program **vp, halo_program **fp,
                         halo_diagnostics *diag)
{
    halo_scene *vs = load_scene(o, lib, diag), *fs = load_scene(o, lib, NULL);
    int ok = vs && fs;
    if (ok) {
        halo_lines_scene_keep_hook(vs, lib, HALO_HOOK_LINE_VERTEX);
        halo_lines_scene_keep_hook(fs, lib, HALO_HOOK_LINE_FRAGMENT);
        ok = halo_lines_link_scenes(lib, vs, fs, NULL, NULL, vp, fp, diag) == HALO_OK;
    }
    if (ok && !halos) {
        const halo_uniform_info *width = stage_property(*vp, 0), *core = stage_property(*fp, 1);
        double narrowed = width && core ? width->value[0] * core->value[0] : 0.0;
        char stage[128] = "", param[128] = "";
        if (width && core) {
            snprintf(stage, sizeof stage, "%s", width->stage);
            snprintf(param, sizeof param, "%s", width->param);
        }
        halo_program_destroy(*vp);
        halo_program_destroy(*fp);
        *vp = *fp = NULL;
        halo_scene_destroy(fs);
        fs = halo_scene_create(lib);
        if (stage[0])
            halo_scene_set(vs, stage, param, &narrowed, 1, 0, diag);
        ok = fs && halo_lines_link_scenes(lib, vs, fs, NULL, NULL, vp, fp, diag) == HALO_OK;
    }
    halo_scene_destroy(vs);
    halo_scene_destroy(fs);
    return ok;
}

static halo_status make_lines(const options *o, size_t bench_points, halo_polylines *lines, halo_diagnostics *diag)
{
    if (o->lines_path)
        return halo_polylines_load(o->lines_path, lines, diag);
    if (o->builtin && strcmp(o->builtin, "knots") == 0)
        return halo_linegen_knot(2, 3, 32, 800, 0.35, lines, diag);
    return halo_linegen_streamlines(bench_points ? bench_points : 120000, 800, 2009, lines, diag);
}

static void view_from(const options *o, const halo_render_settings *rs, halo_lines_view *view)
{
    memset(view, 0, sizeof *view);
    view->azimuth = o->has_azimuth ? o->azimuth : rs->azimuth;
    view->elevation = o->has_elevation ? o->elevation : rs->elevation;
    view->zoom = o->has_zoom ? o->zoom : rs->zoom;
    for (int c = 0; c < 3; ++c)
        view->background[c] = rs->background[c];
}

/* measured: the backend and renderer the frames ran on */
static int run_bench(const options *o, const halo_glfuncs *gl, const halo_library *lib, const halo_polylines *lines,
                     const halo_render_settings *rs, const char *measured, halo_diagnostics *diag)
{
    halo_program *vp[2] = {NULL, NULL}, *fp[2] = {NULL, NULL};
    halo_lines *l[2] = {NULL, NULL};
    int ok = 1;
    for (int halos = 0; halos < 2 && ok; ++halos) {
        ok = link_programs(o, lib, halos, &vp[halos], &fp[halos], diag);
        if (ok)
            l[halos] = halo_lines_create(&(halo_lines_desc){.gl = gl,
                                                            .vertex_program = vp[halos],
                                                            .fragment_program = fp[halos],
                                                            .width = o->width,
                                                            .height = o->height},
                                         diag);
        ok = ok && l[halos] && halo_lines_set_data(l[halos], lines, diag) == HALO_OK;
    }
    halo_lines_view view;
    view_from(o, rs, &view);
    double total[2] = {0.0, 0.0}, best[2] = {INFINITY, INFINITY};
    /* one warm-up frame each (shader compilation in the driver), then interleaved frames */
    for (int frame = -1; frame < o->frames && ok; ++frame)
        for (int halos = 0; halos < 2 && ok; ++halos) {
            halo_lines_finish(l[halos]);
            double start = halo_progress_now();
            ok = halo_lines_draw(l[halos], &view, diag) == HALO_OK;
            halo_lines_finish(l[halos]);
            double elapsed = halo_progress_now() - start;
            if (frame >= 0) {
                total[halos] += elapsed;
                best[halos] = fmin(best[halos], elapsed);
            }
        }
    if (ok) {
        double with = total[1] / o->frames, without = total[0] / o->frames;
        printf("halo-lines bench: %zu lines, %zu vertices (%zu strip vertices), %dx%d, %d frames each, %s; %s\n",
               lines->line_count, lines->point_count, halo_lines_vertex_count(l[1]), o->width, o->height, o->frames,
               "interleaved", measured);
        printf("  without halos: %8.2f ms/frame (best %8.2f ms), %7.2f fps\n", 1e3 * without, 1e3 * best[0],
               1.0 / without);
        printf("  with halos:    %8.2f ms/frame (best %8.2f ms), %7.2f fps\n", 1e3 * with, 1e3 * best[1], 1.0 / with);
        printf("  ratio with/without: %.3f (mean), %.3f (best)\n", with / without, best[1] / best[0]);
    }
    for (int i = 0; i < 2; ++i) {
        halo_lines_destroy(l[i]);
        halo_program_destroy(vp[i]);
        halo_program_destroy(fp[i]);
    }
    return ok ? 0 : 1;
}

int main(int argc, char **argv)
{
    options o = {.width = 800, .height = 800, .frames = 10, .output = "halo-lines.png"};
    if (!halo_headless_take_backend_option(&argc, argv, "halo-lines"))
        return 2;
    enum {
        OPT_NO_HALOS,
        OPT_BENCH,
        OPT_CONFORM,
        OPT_VERBOSE,
        OPT_LINES,
        OPT_BUILTIN,
        OPT_SCENE,
        OPT_OUTPUT,
        OPT_WRITE_LINES,
        OPT_ROW,
        OPT_SIZE,
        OPT_STEREO,
        OPT_FRAMES,
        OPT_AZIMUTH,
        OPT_ELEVATION,
        OPT_ZOOM
    };
    static const halo_tool_option table[] = {[OPT_NO_HALOS] = {"--no-halos", NULL, 0},
                                             [OPT_BENCH] = {"--bench", NULL, 0},
                                             [OPT_CONFORM] = {"--conform", NULL, 0},
                                             [OPT_VERBOSE] = {"-v", NULL, 0},
                                             [OPT_LINES] = {"--lines", NULL, 1},
                                             [OPT_BUILTIN] = {"--builtin", NULL, 1},
                                             [OPT_SCENE] = {"--scene", NULL, 1},
                                             [OPT_OUTPUT] = {"-o", NULL, 1},
                                             [OPT_WRITE_LINES] = {"--write-lines", NULL, 1},
                                             [OPT_ROW] = {"--row", NULL, 1},
                                             [OPT_SIZE] = {"--size", NULL, 1},
                                             [OPT_STEREO] = {"--stereo", NULL, 1},
                                             [OPT_FRAMES] = {"--frames", NULL, 1},
                                             [OPT_AZIMUTH] = {"--azimuth", NULL, 1},
                                             [OPT_ELEVATION] = {"--elevation", NULL, 1},
                                             [OPT_ZOOM] = {"--zoom", NULL, 1},
                                             {NULL, NULL, 0}};
    static const char *const builtins[] = {"streamlines", "knots", NULL}, *const stereo[] = {"anaglyph", NULL};
    halo_tool_args args = {.tool = "halo-lines", .usage = usage, .argc = argc, .argv = argv, .next = 1};
    for (int k; (k = halo_tool_args_next(&args, table)) != HALO_TOOL_ARGS_END;) {
        if (k == HALO_TOOL_ARGS_HELP)
            return 0;
        const char *a = args.option, *value = args.value;
        int ok = k != HALO_TOOL_ARGS_ERROR, choice;
        switch (k) {
        case OPT_NO_HALOS:
            o.no_halos = 1;
            break;
        case OPT_BENCH:
            o.bench = 1;
            break;
        case OPT_CONFORM:
            o.conform = 1;
            break;
        case OPT_VERBOSE:
            o.verbose = 1;
            break;
        case OPT_LINES:
            o.lines_path = value;
            break;
        case OPT_BUILTIN:
            ok = halo_tool_choice("halo-lines", a, value, builtins, &choice);
            o.builtin = value;
            break;
        case OPT_SCENE:
            o.scene_path = value;
            break;
        case OPT_OUTPUT:
            o.output = value;
            break;
        case OPT_WRITE_LINES:
            o.write_lines = value;
            break;
        case OPT_ROW:
            o.row = value;
            break;
        case OPT_SIZE:
            ok = halo_tool_size("halo-lines", a, value, 16384, &o.width, &o.height);
            break;
        case OPT_STEREO:
            ok = o.stereo = halo_tool_choice("halo-lines", a, value, stereo, &choice);
            break;
        case OPT_FRAMES:
            ok = halo_tool_int("halo-lines", a, value, 1, 1000, &o.frames);
            break;
        case OPT_AZIMUTH:
            ok = o.has_azimuth = halo_tool_number("halo-lines", a, value, -360, 360, &o.azimuth);
            break;
        case OPT_ELEVATION:
            ok = o.has_elevation = halo_tool_number("halo-lines", a, value, -90, 90, &o.elevation);
            break;
        case OPT_ZOOM:
            ok = o.has_zoom = halo_tool_number("halo-lines", a, value, 0.05, 20, &o.zoom);
            break;
        }
        if (!ok)
            return 2;
    }
    if (o.lines_path && o.builtin) {
        fprintf(stderr, "halo-lines: error: --lines and --builtin exclude each other\n");
        return 2;
    }

    char err[256] = "";
    halo_headless *context = halo_headless_create(o.width, o.height, err, sizeof err);
    if (!context) {
        fprintf(stderr, "halo-lines: error: no OpenGL context: %s\n", err);
        return 2;
    }
    if (o.conform) {
        int failed = 0;
        printf("%-26s %10s %10s %8s %9s %17s %s\n", "stage", "max_abs", "rmse", "over_tol", "nonfinite", "tolerance",
               "result");
        int count = halo_conform_line_rows_select(o.row, o.verbose, &failed);
        printf("%d rows, %d failed\n", count, failed);
        halo_headless_destroy(context);
        return count == 0 ? 2 : failed ? 1 : 0;
    }

    int status = 0;
    halo_diagnostics *diag = halo_diagnostics_create();
    halo_library *lib = halo_library_create(diag);
    halo_polylines lines = {0};
    halo_glfuncs gl;
    const char *missing = NULL;
    halo_scene *scene = NULL;
    halo_program *vp = NULL, *fp = NULL;
    halo_lines *renderer = NULL;
    float *rgba = NULL;
    if (!halo_glfuncs_load(&gl, sizeof gl, halo_headless_get_proc_address, &missing)) {
        fprintf(stderr, "halo-lines: error: OpenGL entry point %s missing\n", missing ? missing : "?");
        status = 2;
        goto done;
    }
    if (!lib || !(scene = load_scene(&o, lib, diag))) {
        status = 1;
        goto done;
    }
    halo_status made = make_lines(&o, o.bench && !o.lines_path ? BENCH_POINTS : 0, &lines, diag);
    if (made != HALO_OK) {
        status = made == HALO_ERROR_IO ? 2 : 1;
        goto done;
    }
    if (o.write_lines && halo_polylines_write(o.write_lines, &lines) != 0) {
        fprintf(stderr, "halo-lines: error: cannot write '%s'\n", o.write_lines);
        status = 2;
        goto done;
    }
    const halo_render_settings *rs = halo_scene_describe(scene).render;
    if (o.bench) {
        char measured[320];
        snprintf(measured, sizeof measured, "%s backend, %s", halo_headless_backend(context),
                 halo_headless_renderer(context));
        status = run_bench(&o, &gl, lib, &lines, rs, measured, diag);
        goto done;
    }
    if (!link_programs(&o, lib, !o.no_halos, &vp, &fp, diag)) {
        status = 1;
        goto done;
    }
    renderer = halo_lines_create(
        &(halo_lines_desc){
            .gl = &gl, .vertex_program = vp, .fragment_program = fp, .width = o.width, .height = o.height},
        diag);
    rgba = malloc((size_t)o.width * (size_t)o.height * 4 * sizeof *rgba);
    if (!renderer || !rgba || halo_lines_set_data(renderer, &lines, diag) != HALO_OK) {
        status = renderer && rgba ? 1 : 2;
        goto done;
    }
    halo_lines_view view;
    view_from(&o, rs, &view);
    int ok;
    if (o.stereo) {
        /* left eye into red, right eye into green and blue; eyes 6% of the distance apart */
        view.eye_shift = -0.03;
        view.mask_channels = 1;
        ok = halo_lines_draw(renderer, &view, diag) == HALO_OK;
        view.eye_shift = 0.03;
        view.mask_channels = 6;
        view.keep_color = 1;
        ok = ok && halo_lines_draw(renderer, &view, diag) == HALO_OK;
    } else {
        ok = halo_lines_draw(renderer, &view, diag) == HALO_OK;
    }
    if (!ok || halo_lines_read(renderer, rgba, diag) != HALO_OK) {
        status = 2;
        goto done;
    }
    if (halo_image_write(o.output, o.width, o.height, rgba, err, sizeof err) != 0) {
        fprintf(stderr, "halo-lines: error: %s\n", err);
        status = 2;
        goto done;
    }
    fprintf(stderr, "halo-lines: %zu lines, %zu vertices, %dx%d%s%s -> %s\n", lines.line_count, lines.point_count,
            o.width, o.height, o.no_halos ? ", no halos" : "", o.stereo ? ", anaglyph" : "", o.output);
done:
    halo_diagnostics_print(diag, stderr);
    free(rgba);
    halo_lines_destroy(renderer);
    halo_program_destroy(vp);
    halo_program_destroy(fp);
    halo_scene_destroy(scene);
    halo_polylines_free(&lines);
    halo_library_destroy(lib);
    halo_diagnostics_destroy(diag);
    halo_headless_destroy(context);
    return status;
}
