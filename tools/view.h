/* halo-view's parts: tools/halo-view.c (the window, input and main loop) and
 * tools/view_scene.c (the scene on screen, its volume, host and program, the keys'
 * changes to it, reloading and saving). */
#ifndef HALO_VIEW_H
#define HALO_VIEW_H

#include "halo.h"
#include "render_driver.h"
#include "tool_options.h"
#include "volume_io.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <jansson.h>

#include <sys/stat.h>
#include <time.h>

#define DEFAULT_SCENE       "examples/scenes/default.json"
#define WINDOW_LOW_PERCENT  1.0 /* as halo-render: a file volume's default window */
#define WINDOW_HIGH_PERCENT 99.0
#define POLL_SECONDS        0.25 /* how often the scene file's signature is checked */
#define PARAM_STEPS         20   /* [ and ] move a bounded float parameter by its range / this */
#define VIEW_NAME_MAX       128
#define MAX_TOGGLE_STAGES   9

typedef struct options {
    const char *scene_path, *volume_path, *screenshot, *save_prefix, *keys;
    int width, height, volume_size, have_volume_size, frames, quit;
} options;

/* What identifies a version of a file: replaced (rename), rewritten or touched. */
typedef struct file_signature {
    int exists;
    dev_t device;
    ino_t inode;
    off_t size;
    struct timespec mtime;
} file_signature;

/* One change the keys made to a parameter, written into a saved scene. */
typedef struct touched_param {
    char stage[VIEW_NAME_MAX], param[VIEW_NAME_MAX];
} touched_param;

#define MAX_TOUCHED 8

typedef struct viewer {
    options o;
    halo_diagnostics *diag;
    halo_library *lib;

    /* The scene on screen (the last good one), with the keys' changes. */
    halo_scene *scene;
    json_t *scene_json; /* its text, for saving */
    char *scene_file;   /* its path, NULL for the built-in scene */
    halo_driver_host kind;
    halo_program *program;
    halo_driver host;
    size_t toggle_count;
    char *toggle_names[MAX_TOGGLE_STAGES];
    int toggle_on[MAX_TOGGLE_STAGES];
    touched_param touched[MAX_TOUCHED];
    int touched_count;
    touched_param selected; /* the parameter [ and ] change ("" until p or P selects one) */

    /* The file watched for changes (the scene asked for last, good or not). */
    char *watch_path;
    file_signature watch_signature;
    double next_poll;
    long loads;       /* reload attempts of the watched file, good or not */
    char error[1024]; /* the first error of the last failed load or change, "" when none */

    /* Volume */
    halo_volume_file file;
    int have_file;
    float *volume;
    int volume_size;
    double volume_window[2];

    /* Camera */
    double azimuth, elevation, zoom;
    int dragging;
    double drag_x, drag_y;

    /* Window and GL */
    GLFWwindow *window;
    halo_gl *runtime;
    const halo_glfuncs *f; /* &functions */
    halo_glfuncs functions;
    unsigned display_texture, display_framebuffer;
    int width, height;
    float *image, *display;
    int dirty;    /* the image is out of date: render */
    int rendered; /* an image has been rendered */
    double frame_ms;
    long frames;
    int save_count;
    int save_requested;
    int quit;
    int error_printed; /* error's diagnostics are on stderr already */
} viewer;

file_signature view_signature_of(const char *path);
void view_report_diagnostics(viewer *v, const char *fallback);
void view_update_title(viewer *v);
void view_set_camera(viewer *v);
void view_free_toggles(viewer *v);
int view_load_scene(viewer *v, const char *path, int keep_camera);
void view_poll_scene_file(viewer *v, double now);
void view_cycle_scene(viewer *v, int step);
void view_select_param(viewer *v, int step);
void view_step_param(viewer *v, int direction);
void view_toggle_stage(viewer *v, size_t index);
int view_save_image(viewer *v, const char *path, const char *name);
void view_save_screenshot_and_scene(viewer *v);

#endif
