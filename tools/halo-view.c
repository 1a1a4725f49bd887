/* halo-view: the interactive viewer. A GLFW window (OpenGL 3.3 core or later) that
 * renders a volume with a libhalo scene through the same example hosts and GL runtime
 * as halo-render (the slice host when the scene has halo stages, else the ray caster),
 * with mouse orbit and zoom, keys that relink the scene with stages or halo parameters
 * changed, live reloading of the scene file, and screenshots. The manual is
 * docs/halo-view.md and halo-view(1).
 *
 * Every frame the host renders into its own RGBA32F framebuffer and reads the image
 * back (as for halo-render); the viewer uploads it to a texture and blits it to the
 * window. A screenshot is that read-back image, so it is what halo-render writes for
 * the same scene, volume, camera and size.
 *
 * Exit status: 0 success, 1 the scene, shaders or volume contents have errors (at
 * start; later errors are shown and the last good scene stays), 2 usage, I/O, window
 * or OpenGL failure. */
#define _POSIX_C_SOURCE 200809L
#include "view.h"
#include "halo.h"
#include "halo_gl_loader.h"
#include "hosts/host_common.h"
#include "image_write.h"
#include "json_file.h"
#include "progress.h"
#include "render_driver.h"
#include "tool_options.h"
#include "volume.h"
#include "volume_io.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <jansson.h>

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>


#define WAIT_TIMEOUT_SECONDS    60.0 /* --keys "@reload" gives up after this long */
#define ORBIT_DEGREES_PER_PIXEL 0.4
#define KEY_ORBIT_DEGREES       5.0
#define ZOOM_FACTOR             1.1

static void usage(FILE *out)
{
    fputs(
        "Usage: halo-view [OPTION]...\n"
        "Opens a window that renders a volume with a libhalo scene through the example\n"
        "GPU hosts (as halo-render does), with mouse orbit and zoom, keys that change the\n"
        "scene, and live reloading of the scene file. Needs an X display (or xvfb-run).\n"
        "\n"
        "  --scene S          scene file (JSON); default: examples/scenes/default.json\n"
        "                     (built in: no reloading, no scene cycling)\n"
        "  --volume FILE      NIfTI volume (.nii, .nii.gz, .hdr/.img); default: the\n"
        "                     built-in procedural volume\n"
        "  --volume-size N    side of the cube the volume is resampled to (8..512); default:\n"
        "                     96 for the built-in volume, a file's own resolution up to 512\n"
        "  --size WxH         render (and initial window) size, 1..8192 each; default 512x512\n"
        "  --save-prefix P    the S key writes P001.png and P001.json, P002...; default\n"
        "                     halo-view-\n"
        "Automation (tests):\n"
        "  --keys \"K ...\"     presses these keys, one per frame, before anything else: a\n"
        "                     character (\"1\", \"e\", \"D\" = shift+d, \"+\"), or left, right, up,\n"
        "                     down, tab, shift+tab, pageup, pagedown, f1, esc; \"@reload\"\n"
        "                     waits until the scene file was reloaded (or failed to) since\n"
        "                     the previous key\n"
        "  --frames N         render at least N frames (default 1)\n"
        "  --screenshot FILE  after N frames and the keys, save the image: .png (8-bit,\n"
        "                     clamped) or .exr (float), as halo-render -o writes it\n"
        "  --quit             exit after that\n"
        "  --help             show this help\n"
        "\n"
        "Keys: mouse left drag orbit, wheel zoom; 1-9 toggle the scene's stages; e\n"
        "emissive/occlusive; d/D delta -/+0.05; m/M interval M halve/double; n/N passes\n"
        "-/+1; arrows orbit; +/- zoom; r camera of the scene; tab/shift+tab (pagedown/\n"
        "pageup) next/previous scene in its folder; s save screenshot and scene; h or F1\n"
        "this help; q or esc quit.\n"
        "\n"
        "Exit status: 0 success, 1 the scene, shaders or volume contents have errors at\n"
        "start, 2 usage, I/O, window or OpenGL failure.\n",
        out);
}

/* ---- Options -------------------------------------------------------------------------- */


enum {
    OPT_QUIT,
    OPT_SCENE,
    OPT_VOLUME,
    OPT_VOLUME_SIZE,
    OPT_SIZE,
    OPT_SAVE_PREFIX,
    OPT_KEYS,
    OPT_FRAMES,
    OPT_SCREENSHOT
};
static const halo_tool_option option_table[] = {[OPT_QUIT] = {"--quit", NULL, 0},
                                                [OPT_SCENE] = {"--scene", NULL, 1},
                                                [OPT_VOLUME] = {"--volume", NULL, 1},
                                                [OPT_VOLUME_SIZE] = {"--volume-size", NULL, 1},
                                                [OPT_SIZE] = {"--size", NULL, 1},
                                                [OPT_SAVE_PREFIX] = {"--save-prefix", NULL, 1},
                                                [OPT_KEYS] = {"--keys", NULL, 1},
                                                [OPT_FRAMES] = {"--frames", NULL, 1},
                                                [OPT_SCREENSHOT] = {"--screenshot", NULL, 1},
                                                {NULL, NULL, 0}};

/* Returns 0 to go on, -1 to exit 0 (help), or an exit status. */
static int parse_options(int argc, char **argv, options *o)
{
    *o = (options){
        .width = 512, .height = 512, .volume_size = HALO_VOLUME_DEFAULT_SIZE, .frames = 1, .save_prefix = "halo-view-"};
    halo_tool_args args = {.tool = "halo-view", .usage = usage, .argc = argc, .argv = argv, .next = 1};
    for (int k; (k = halo_tool_args_next(&args, option_table)) != HALO_TOOL_ARGS_END;) {
        if (k == HALO_TOOL_ARGS_HELP)
            return -1;
        if (k == HALO_TOOL_ARGS_ERROR)
            return 2;
        const char *a = args.option, *value = args.value;
        int ok = 1;
        switch (k) {
        case OPT_QUIT:
            o->quit = 1;
            break;
        case OPT_SCENE:
            o->scene_path = value;
            break;
        case OPT_VOLUME:
            o->volume_path = value;
            break;
        case OPT_VOLUME_SIZE:
            ok = o->have_volume_size =
                halo_tool_int("halo-view", a, value, HALO_VOLUME_MIN_SIZE, HALO_VOLUME_MAX_SIZE, &o->volume_size);
            break;
        case OPT_SIZE:
            ok = halo_tool_size("halo-view", a, value, 8192, &o->width, &o->height);
            break;
        case OPT_SAVE_PREFIX:
            o->save_prefix = value;
            break;
        case OPT_KEYS:
            o->keys = value;
            break;
        case OPT_FRAMES:
            ok = halo_tool_int("halo-view", a, value, 1, 1000000, &o->frames);
            break;
        case OPT_SCREENSHOT:
            o->screenshot = value;
            break;
        }
        if (!ok)
            return 2;
    }
    if (o->screenshot && !o->screenshot[0]) {
        fprintf(stderr, "halo-view: error: --screenshot: empty file name\n");
        return 2;
    }
    return 0;
}

/* ---- Keys ------------------------------------------------------------------------------ */

/* A key is a character (what was typed, shift included) or one of these. */
enum {
    KEY_LEFT = 0x110000,
    KEY_RIGHT,
    KEY_UP,
    KEY_DOWN,
    KEY_NEXT_SCENE,
    KEY_PREVIOUS_SCENE,
    KEY_HELP,
    KEY_QUIT,
    KEY_WAIT_RELOAD /* --keys only */
};

static const struct {
    const char *name;
    int key;
} key_names[] = {{"left", KEY_LEFT},
                 {"right", KEY_RIGHT},
                 {"up", KEY_UP},
                 {"down", KEY_DOWN},
                 {"tab", KEY_NEXT_SCENE},
                 {"pagedown", KEY_NEXT_SCENE},
                 {"shift+tab", KEY_PREVIOUS_SCENE},
                 {"pageup", KEY_PREVIOUS_SCENE},
                 {"f1", KEY_HELP},
                 {"esc", KEY_QUIT},
                 {"escape", KEY_QUIT},
                 {"@reload", KEY_WAIT_RELOAD}};

/* Parses --keys into an array of keys; returns the count, or -1 after a message. */
static int parse_keys(const char *text, int **out)
{
    size_t n = 0, cap = 16;
    int *keys = malloc(cap * sizeof *keys);
    if (!keys)
        return -1;
    const char *p = text;
    for (;;) {
        while (*p == ' ' || *p == '\t' || *p == '\n')
            ++p;
        if (!*p)
            break;
        const char *end = p;
        while (*end && *end != ' ' && *end != '\t' && *end != '\n')
            ++end;
        size_t len = (size_t)(end - p);
        int key = -1;
        if (len == 1 && (unsigned char)*p > ' ' && (unsigned char)*p < 127)
            key = (unsigned char)*p;
        for (size_t k = 0; key < 0 && k < sizeof key_names / sizeof key_names[0]; ++k)
            if (strlen(key_names[k].name) == len && !strncmp(key_names[k].name, p, len))
                key = key_names[k].key;
        if (key < 0) {
            fprintf(stderr, "halo-view: error: --keys: unknown key '%.*s'\n", (int)len, p);
            free(keys);
            return -1;
        }
        if (n == cap) {
            int *grown = realloc(keys, 2 * cap * sizeof *keys);
            if (!grown) {
                free(keys);
                return -1;
            }
            keys = grown;
            cap *= 2;
        }
        keys[n++] = key;
        p = end;
    }
    *out = keys;
    return (int)n;
}

/* ---- Input ------------------------------------------------------------------------------------------- */

static void print_keys(void)
{
    fputs(
        "halo-view keys:\n"
        "  mouse: left drag orbit, wheel zoom; arrows orbit, + and - zoom, r the scene's camera\n"
        "  1-9    toggle the scene's stages (in scene order)\n"
        "  p / P  select the next / previous parameter of the linked stages (in the title)\n"
        "  [ / ]  the selected parameter down / up: a bool flips; else by the module's step=;\n"
        "         else an int by 1 (a stage's interval M halves / doubles), a bounded float by\n"
        "         a twentieth of its range\n"
        "  tab / shift+tab (pagedown / pageup)  next / previous scene in the scene's folder\n"
        "  s      save the image and the scene (--save-prefix)\n"
        "  h, F1  this help;  q, esc  quit\n",
        stdout);
}

static double wrap_degrees(double a)
{
    a = fmod(a, 360.0);
    if (a > 180.0)
        a -= 360.0;
    if (a <= -180.0)
        a += 360.0;
    return a;
}

/* Camera values are kept to 6 decimals, so that a saved scene (written with 15
 * significant digits) holds exactly the camera of the screenshot saved with it. */
static double snap(double x) { return round(x * 1e6) / 1e6; }

static void orbit(viewer *v, double d_azimuth, double d_elevation)
{
    v->azimuth = snap(wrap_degrees(v->azimuth + d_azimuth));
    v->elevation = snap(fmin(90.0, fmax(-90.0, v->elevation + d_elevation)));
    view_set_camera(v);
}

static void zoom_by(viewer *v, double factor)
{
    v->zoom = snap(fmin(20.0, fmax(0.05, v->zoom * factor)));
    view_set_camera(v);
}

static void handle_key(viewer *v, int key)
{
    if (key >= '1' && key <= '9') {
        view_toggle_stage(v, (size_t)(key - '1'));
        return;
    }
    switch (key) {
    case 'p':
        view_select_param(v, 1);
        break;
    case 'P':
        view_select_param(v, -1);
        break;
    case '[':
        view_step_param(v, -1);
        break;
    case ']':
        view_step_param(v, 1);
        break;
    case '+':
    case '=':
        zoom_by(v, ZOOM_FACTOR);
        break;
    case '-':
    case '_':
        zoom_by(v, 1.0 / ZOOM_FACTOR);
        break;
    case KEY_LEFT:
        orbit(v, -KEY_ORBIT_DEGREES, 0);
        break;
    case KEY_RIGHT:
        orbit(v, KEY_ORBIT_DEGREES, 0);
        break;
    case KEY_UP:
        orbit(v, 0, KEY_ORBIT_DEGREES);
        break;
    case KEY_DOWN:
        orbit(v, 0, -KEY_ORBIT_DEGREES);
        break;
    case 'r':
    case 'R': {
        const halo_render_settings *r = halo_scene_describe(v->scene).render;
        v->azimuth = r->azimuth;
        v->elevation = r->elevation;
        v->zoom = r->zoom;
        view_set_camera(v);
        break;
    }
    case KEY_NEXT_SCENE:
        view_cycle_scene(v, 1);
        break;
    case KEY_PREVIOUS_SCENE:
        view_cycle_scene(v, -1);
        break;
    case 's':
    case 'S':
        v->save_requested++;
        break;
    case 'h':
    case 'H':
    case '?':
    case KEY_HELP:
        print_keys();
        break;
    case 'q':
    case 'Q':
    case KEY_QUIT:
        v->quit = 1;
        break;
    default:
        break;
    }
    view_update_title(v);
}

static void on_char(GLFWwindow *w, unsigned int codepoint)
{
    viewer *v = glfwGetWindowUserPointer(w);
    if (codepoint < 127)
        handle_key(v, (int)codepoint);
}

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    (void)scancode;
    viewer *v = glfwGetWindowUserPointer(w);
    if (action == GLFW_RELEASE)
        return;
    switch (key) {
    case GLFW_KEY_LEFT:
        handle_key(v, KEY_LEFT);
        break;
    case GLFW_KEY_RIGHT:
        handle_key(v, KEY_RIGHT);
        break;
    case GLFW_KEY_UP:
        handle_key(v, KEY_UP);
        break;
    case GLFW_KEY_DOWN:
        handle_key(v, KEY_DOWN);
        break;
    case GLFW_KEY_TAB:
        handle_key(v, mods & GLFW_MOD_SHIFT ? KEY_PREVIOUS_SCENE : KEY_NEXT_SCENE);
        break;
    case GLFW_KEY_PAGE_DOWN:
        handle_key(v, KEY_NEXT_SCENE);
        break;
    case GLFW_KEY_PAGE_UP:
        handle_key(v, KEY_PREVIOUS_SCENE);
        break;
    case GLFW_KEY_F1:
        handle_key(v, KEY_HELP);
        break;
    case GLFW_KEY_ESCAPE:
        handle_key(v, KEY_QUIT);
        break;
    default:
        break;
    }
}

static void on_mouse_button(GLFWwindow *w, int button, int action, int mods)
{
    (void)mods;
    viewer *v = glfwGetWindowUserPointer(w);
    if (button != GLFW_MOUSE_BUTTON_LEFT)
        return;
    v->dragging = action == GLFW_PRESS;
    glfwGetCursorPos(w, &v->drag_x, &v->drag_y);
}

static void on_cursor(GLFWwindow *w, double x, double y)
{
    viewer *v = glfwGetWindowUserPointer(w);
    if (!v->dragging)
        return;
    double dx = x - v->drag_x, dy = y - v->drag_y;
    v->drag_x = x;
    v->drag_y = y;
    orbit(v, -ORBIT_DEGREES_PER_PIXEL * dx, ORBIT_DEGREES_PER_PIXEL * dy);
}

static void on_scroll(GLFWwindow *w, double dx, double dy)
{
    (void)dx;
    viewer *v = glfwGetWindowUserPointer(w);
    zoom_by(v, pow(ZOOM_FACTOR, dy));
}

static void present(viewer *v);

static void on_refresh(GLFWwindow *w)
{
    viewer *v = glfwGetWindowUserPointer(w);
    if (v->rendered)
        present(v);
}

static void on_glfw_error(int code, const char *text)
{
    fprintf(stderr, "halo-view: GLFW error 0x%x: %s\n", code, text);
}

/* ---- Rendering -------------------------------------------------------------------------------------------- */

static void *get_proc_address(const char *name)
{
    GLFWglproc proc = glfwGetProcAddress(name);
    void *p;
    memcpy(&p, &proc, sizeof p);
    return p;
}

static int render(viewer *v)
{
    double start = halo_progress_now();
    halo_diagnostics_clear(v->diag);
    halo_status status = halo_driver_render(&v->host, v->image, v->diag);
    v->frame_ms = 1e3 * (halo_progress_now() - start);
    if (status != HALO_OK) {
        view_report_diagnostics(v, "rendering failed");
        return 0;
    }
    v->rendered = 1;
    v->frames++;
    v->dirty = 0;
    return 1;
}

/* Shows the last image, letterboxed in the window; a red bar along the top while the
 * scene on disk has errors (the image itself stays as rendered, for screenshots). */
static void present(viewer *v)
{
    const halo_glfuncs *f = v->f;
    size_t pixels = (size_t)v->width * (size_t)v->height;
    memcpy(v->display, v->image, pixels * 4 * sizeof *v->display);
    if (v->error[0]) {
        int bar = v->height / 40 + 2;
        for (int y = v->height - bar < 0 ? 0 : v->height - bar; y < v->height; ++y)
            for (int x = 0; x < v->width; ++x) {
                float *px = &v->display[((size_t)y * (size_t)v->width + (size_t)x) * 4];
                px[0] = 0.9f, px[1] = 0.1f, px[2] = 0.1f, px[3] = 1.0f;
            }
    }
    f->BindTexture(GL_TEXTURE_2D, v->display_texture);
    f->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    f->TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, v->width, v->height, GL_RGBA, GL_FLOAT, v->display);
    f->BindTexture(GL_TEXTURE_2D, 0);
    int fw, fh;
    glfwGetFramebufferSize(v->window, &fw, &fh);
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    f->Disable(GL_SCISSOR_TEST);
    f->Viewport(0, 0, fw, fh);
    f->ClearColor(0.12f, 0.12f, 0.12f, 1.0f);
    f->Clear(GL_COLOR_BUFFER_BIT);
    double scale = fmin((double)fw / v->width, (double)fh / v->height);
    int w = (int)lround(v->width * scale), h = (int)lround(v->height * scale);
    int x0 = (fw - w) / 2, y0 = (fh - h) / 2;
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, v->display_framebuffer);
    f->BlitFramebuffer(0, 0, v->width, v->height, x0, y0, x0 + w, y0 + h, GL_COLOR_BUFFER_BIT,
                       w == v->width && h == v->height ? GL_NEAREST : GL_LINEAR);
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glfwSwapBuffers(v->window);
}

static int create_display(viewer *v)
{
    const halo_glfuncs *f = v->f;
    f->GenTextures(1, &v->display_texture);
    f->BindTexture(GL_TEXTURE_2D, v->display_texture);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, v->width, v->height, 0, GL_RGBA, GL_FLOAT, NULL);
    f->BindTexture(GL_TEXTURE_2D, 0);
    return halo_host_framebuffer(f, &v->display_framebuffer, v->display_texture, v->width, v->height, NULL);
}

/* ---- Main ------------------------------------------------------------------------------------------------- */

int main(int argc, char **argv)
{
    viewer view = {0}, *v = &view;
    int status = parse_options(argc, argv, &v->o);
    if (status)
        return status < 0 ? 0 : status;
    int *keys = NULL, key_count = 0, key_next = 0;
    if (v->o.keys && (key_count = parse_keys(v->o.keys, &keys)) < 0)
        return 2;
    setvbuf(stdout, NULL, _IOLBF, 0);
    v->width = v->o.width;
    v->height = v->o.height;
    status = 2;

    v->diag = halo_diagnostics_create();
    if (!v->diag || halo_setup(NULL) != HALO_OK) {
        fprintf(stderr, "halo-view: error: cannot initialize libhalo\n");
        halo_diagnostics_destroy(v->diag);
        free(keys);
        return 2;
    }
    v->lib = halo_library_create(v->diag);
    if (!v->lib) {
        halo_diagnostics_print(v->diag, stderr);
        goto done;
    }
    if (v->o.volume_path) {
        char err[512];
        halo_volume_status read = halo_volume_read_nifti(v->o.volume_path, &v->file, err, sizeof err);
        if (read != HALO_VOLUME_OK) {
            fprintf(stderr, "halo-view: error: %s\n", err);
            status = (int)read;
            goto done;
        }
        v->have_file = 1;
        fprintf(stderr, "halo-view: %s: %s\n", v->o.volume_path, v->file.description);
    }

    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
        fprintf(stderr, "halo-view: error: cannot initialize GLFW (no display? DISPLAY=%s; try xvfb-run -a)\n",
                getenv("DISPLAY") ? getenv("DISPLAY") : "");
        goto done;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_FALSE);
    v->window = glfwCreateWindow(v->width, v->height, "halo-view", NULL, NULL);
    if (!v->window) {
        fprintf(stderr, "halo-view: error: cannot open a %dx%d window with an OpenGL 3.3 core context\n", v->width,
                v->height);
        goto done;
    }
    glfwMakeContextCurrent(v->window);
    glfwSwapInterval(0);
    glfwSetWindowUserPointer(v->window, v);
    glfwSetCharCallback(v->window, on_char);
    glfwSetKeyCallback(v->window, on_key);
    glfwSetMouseButtonCallback(v->window, on_mouse_button);
    glfwSetCursorPosCallback(v->window, on_cursor);
    glfwSetScrollCallback(v->window, on_scroll);
    glfwSetWindowRefreshCallback(v->window, on_refresh);

    v->runtime = halo_gl_create(&(halo_gl_desc){.get_proc_address = get_proc_address}, v->diag);
    if (!v->runtime) {
        halo_diagnostics_print(v->diag, stderr);
        goto done;
    }
    const char *missing = NULL;
    if (!halo_glfuncs_load(&v->functions, sizeof v->functions, get_proc_address, &missing)) {
        fprintf(stderr, "halo-view: error: the window's OpenGL context lacks %s\n", missing);
        goto done;
    }
    v->f = &v->functions;
    fprintf(stderr, "halo-view: OpenGL %s, %s\n", (const char *)v->f->GetString(GL_VERSION),
            (const char *)v->f->GetString(GL_RENDERER));
    size_t pixels = (size_t)v->width * (size_t)v->height;
    v->image = calloc(pixels * 4, sizeof *v->image);
    v->display = malloc(pixels * 4 * sizeof *v->display);
    if (!v->image || !v->display || !create_display(v)) {
        fprintf(stderr, "halo-view: error: cannot create a %dx%d image\n", v->width, v->height);
        goto done;
    }

    if (v->o.scene_path) {
        v->watch_path = strdup(v->o.scene_path);
        v->watch_signature = view_signature_of(v->watch_path);
    }
    status = view_load_scene(v, v->watch_path, 0);
    if (status) {
        if (!v->error_printed) /* each error once */
            fprintf(stderr, "halo-view: error: %s\n", v->error);
        goto done;
    }
    view_update_title(v);
    if (!v->o.quit)
        print_keys();

    status = 0;
    double wait_since = 0;
    long loads_before_key = v->loads;
    int screenshot_done = 0;
    double last_title = 0;
    while (!glfwWindowShouldClose(v->window) && !v->quit) {
        int waiting = key_next < key_count && keys[key_next] == KEY_WAIT_RELOAD;
        int automated = (key_next < key_count && !waiting) || (long)v->frames < v->o.frames;
        if (automated || v->dirty || v->save_requested)
            glfwPollEvents();
        else
            glfwWaitEventsTimeout(waiting ? 0.05 : POLL_SECONDS);
        double now = halo_progress_now();
        view_poll_scene_file(v, now);

        /* one injected key per frame; "@reload" holds the rest until a (re)load */
        if (key_next < key_count) {
            if (keys[key_next] == KEY_WAIT_RELOAD) {
                if (wait_since == 0)
                    wait_since = now;
                if (v->loads > loads_before_key) {
                    key_next++;
                    wait_since = 0;
                    loads_before_key = v->loads;
                } else if (now - wait_since > WAIT_TIMEOUT_SECONDS) {
                    fprintf(stderr, "halo-view: error: --keys @reload: %s did not change in %.0f s\n",
                            v->watch_path ? v->watch_path : "the built-in scene", WAIT_TIMEOUT_SECONDS);
                    status = 1;
                    break;
                }
            } else {
                handle_key(v, keys[key_next++]);
                loads_before_key = v->loads;
            }
        }

        int force = (long)v->frames < v->o.frames;
        if (v->dirty || force || !v->rendered) {
            if (!render(v)) {
                status = 2;
                break;
            }
            present(v);
            if (now - last_title > 0.25) {
                view_update_title(v);
                last_title = now;
            }
        } else if (v->error[0] || now - last_title > 1.0) {
            present(v); /* the error bar, or a window that was uncovered */
            view_update_title(v);
            last_title = now;
        }
        for (; v->save_requested > 0; v->save_requested--)
            view_save_screenshot_and_scene(v);

        if (key_next >= key_count && (long)v->frames >= v->o.frames && !screenshot_done) {
            screenshot_done = 1;
            if (v->o.screenshot && !view_save_image(v, v->o.screenshot, v->o.screenshot)) {
                status = 2;
                break;
            }
            if (v->o.quit)
                break;
        }
    }
    if (status == 0)
        printf("halo-view: %ld frame%s, last %.1f ms\n", v->frames, v->frames == 1 ? "" : "s", v->frame_ms);

done:
    if (v->window) {
        glfwMakeContextCurrent(v->window);
        halo_driver_destroy(&v->host);
        if (v->f && v->display_framebuffer)
            v->f->DeleteFramebuffers(1, &v->display_framebuffer);
        if (v->f && v->display_texture)
            v->f->DeleteTextures(1, &v->display_texture);
        halo_gl_destroy(v->runtime);
        glfwDestroyWindow(v->window);
    }
#if !defined(__SANITIZE_ADDRESS__)
    /* Under AddressSanitizer the X connection is left to the process exit: glfwTerminate
     * unloads Mesa's GLX driver, whose few process-wide allocations LeakSanitizer then
     * reports from an unknown module (no suppression can name it); loaded, they are
     * still reachable and nothing is reported. */
    glfwTerminate();
#endif
    halo_program_destroy(v->program);
    halo_scene_destroy(v->scene);
    json_decref(v->scene_json);
    view_free_toggles(v);
    free(v->scene_file);
    free(v->watch_path);
    halo_library_destroy(v->lib);
    if (v->have_file)
        halo_volume_file_free(&v->file);
    free(v->volume);
    free(v->image);
    free(v->display);
    free(keys);
    halo_diagnostics_destroy(v->diag);
    halo_shutdown();
    return status;
}
