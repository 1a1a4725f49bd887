/* The render driver: scene + volume + host + camera -> frame, with progress. One
 * interface over the example hosts (the slice host, the slab ray caster, the ray
 * caster), used by halo-render, halo-view, halo-validate bench and the conformance
 * whole-render rows: they keep only what is their own (options, output, the window,
 * the comparison). The caller's OpenGL context must be current. */
#ifndef HALO_RENDER_DRIVER_H
#define HALO_RENDER_DRIVER_H

#include "halo.h"
#include "halo_feature.h"
#include "halo_gl_loader.h"
#include "hosts/raycast.h"
#include "hosts/slice.h"

typedef enum halo_driver_host {
    HALO_DRIVER_AUTO = 0, /* the slice host when the scene has halo stages, else the ray caster */
    HALO_DRIVER_SLICE,
    HALO_DRIVER_SLAB,
    HALO_DRIVER_RAYCAST,
    HALO_DRIVER_HOST_COUNT
} halo_driver_host;

/* "auto", "slice", "slab", "raycast", NULL: indexed by halo_driver_host. */
extern const char *const halo_driver_host_names[];
/* The host's fragment shader (halo_host_load): "slice.frag", "slab.frag", "raycast.frag". */
const char *halo_driver_fragment(halo_driver_host kind);

/* is_halo values of halo_driver_find_halo_stages. */
enum { HALO_DRIVER_HALO = 1, HALO_DRIVER_FEATURE = 2 };

/* Marks the scene's stages in is_halo (one per scene stage): HALO_DRIVER_HALO for a
 * stage with hook image, or one that adds extra outputs, images read per sample or
 * image passes (a stage that does not link alone is judged together with the halo
 * stages found first); HALO_DRIVER_FEATURE for one that reads the halo buffer of feature
 * halos (halo_feature.h: the driver builds it; it goes with any host); else 0. Returns
 * the number of HALO_DRIVER_HALO stages. No stage is known by its name. */
size_t halo_driver_find_halo_stages(const halo_library *lib, const halo_scene *scene, int *is_halo);
/* The host for the scene: the slice host when it has halo stages, else the ray caster. */
halo_driver_host halo_driver_choose_host(const halo_library *lib, const halo_scene *scene);
/* Switches off the marked stages (halos and feature halos). Returns 0 on failure. */
int halo_driver_disable_halo_stages(halo_scene *scene, const int *is_halo, halo_diagnostics *diag);
/* Whether a stage of the scene reads the feature halo buffer (HALO_HOST_FEATURE_BUFFER). */
int halo_driver_has_feature_halos(const halo_library *lib, const halo_scene *scene);

/* The built-in procedural volume (volume.h, values in [0,1]) of side size, mapped
 * through the window to [0,1] (clamped) unless the window is 0:1. NULL when memory
 * runs out; free() the result. */
float *halo_driver_builtin_volume(int size, const double window[2]);

/* Links the scene into the host's fragment shader: desc gives the library, the scene
 * and the link options (its host_source and host_file are the driver's). validate:
 * halo_validate too. NULL on failure (diagnostics in diag). */
halo_program *halo_driver_link(const halo_link_desc *desc, halo_driver_host kind, int validate, halo_diagnostics *diag);

typedef struct halo_driver {
    halo_driver_host kind;
    halo_raycast *raycast; /* the ray caster, or */
    halo_slice *slice;     /* the slice host or the slab caster */
    halo_gl *runtime;
    const halo_glfuncs *gl; /* the GL functions (halo_host_desc.gl) */
    const halo_program *program;
    int width, height;
    const char *tool;             /* notes and progress on stderr under this name; NULL: none */
    int quiet;                    /* with tool: errors only, no notes or progress */
    long pass_draws;              /* the ray caster's image passes in the last frame */
    halo_feature_buffer *feature; /* feature_halo's halo buffer (halo_driver_update_feature) */
    unsigned post_texture;        /* the slice host's colour, read by the post passes */
} halo_driver;

/* desc: the GL functions, runtime, program (or raw fragment source) and image size. */
int halo_driver_create(halo_driver *d, halo_driver_host kind, const halo_host_desc *desc, halo_diagnostics *diag);
/* Destroys the host and the driver's feature buffer; d is empty afterwards (zeroed). */
void halo_driver_destroy(halo_driver *d);
/* At the end of a render: halo_driver_destroy (d may be NULL), then the program and the
 * scene it rendered (each may be NULL), which are set to NULL. */
void halo_driver_release(halo_driver *d, halo_program **program, halo_scene **scene);
/* The volume (x fastest, values in [0,1]) and the scene's render settings; gradient:
 * the slice and slab hosts' gradient texture (0: their default). */
halo_status halo_driver_set_volume(halo_driver *d, const float *volume, const int dims[3],
                                   const halo_render_settings *settings, halo_gradient_format gradient,
                                   halo_diagnostics *diag);
/* Label ids on the volume's grid (the slice and slab hosts only). */
halo_status halo_driver_set_labels(halo_driver *d, const float *labels, const int dims[3], halo_diagnostics *diag);
void halo_driver_set_camera(halo_driver *d, double azimuth, double elevation, double zoom);
/* M: slices between halo generations (slab: samples per draw; ray caster: per segment); 0: the default. */
void halo_driver_set_interval(halo_driver *d, int interval);
/* The cap on a frame's halo field drawn once (halo_gl_segments_desc.field_max_bytes; 0:
 * libhalo's default, 1 GiB). */
void halo_driver_set_field_max_bytes(halo_driver *d, size_t bytes);
/* Builds feature_halo's halo buffer for the current view (from the volume's centre
 * towards the eye) and binds it; again after every camera change. Returns 0 on failure. */
int halo_driver_update_feature(halo_driver *d, const float *volume, const int dims[3], halo_diagnostics *diag);
/* The camera's eye in texture space (the volume is the unit cube). */
void halo_driver_eye(const halo_driver *d, double eye[3]);
/* Binds a feature halo buffer (one built by the caller, or the driver's) to the host's program. */
void halo_driver_bind_feature(halo_driver *d, const halo_feature_buffer *buffer);
/* Renders one frame into rgba (width*height*4, over the background), the post passes
 * included, with progress when tool is set and not quiet. */
halo_status halo_driver_render(halo_driver *d, float *rgba, halo_diagnostics *diag);
/* What the last frame drew: draws (slices, slabs or segments), image passes, slices. */
void halo_driver_counts(const halo_driver *d, long *draws, long *pass_draws, int *slices);
/* The gradient texture's format name, or NULL when the host reads no gradient texture. */
const char *halo_driver_gradient_name(const halo_driver *d);
halo_gl_frame *halo_driver_frame(const halo_driver *d);

#endif
