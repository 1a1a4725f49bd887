/* halo-validate bench: rendering configurations of one scene and volume with the slice
 * host or the slab ray caster (examples/hosts/slice.h), timed in interleaved rounds, and
 * their error against a reference image. Shared by the bench subcommand and the error
 * budget (bench_budget.h). The caller's OpenGL context must be current. */
#ifndef HALO_BENCH_RUN_H
#define HALO_BENCH_RUN_H

#include "halo.h"
#include "halo_gl_loader.h"

#include <stdio.h>

/* One approximation of the scene. Zero values take the scene's own (or the default). */
typedef struct halo_bench_config {
    int halos;           /* 0: the same render with every stage off (the reference renderer) */
    int slab;            /* 0: slice host, 1: slab ray caster, HALO_BENCH_RAYCAST: the segmented ray caster */
    int interval;        /* M: slices between generations (slab: samples per draw) */
    int passes;          /* N: spreading passes (halo_generate.passes); 0: the scene's */
    int wide;            /* halo_generate's approximation wide: N passes of 49 taps, reach 4^N - 1 */
    int fold;            /* halo_generate's fold: H_0 computed by the first spreading pass, no gradient pass */
    int one_draw;        /* the ray caster linked with one_draw: the field before one host draw (host contract 3) */
    double seed_epsilon; /* with one_draw: the march's empty-space bound (halo_gl_segments_desc.seed_epsilon) */
    int same_view;       /* with one_draw: every frame at the scene's view, so that each reuses the field of the
                          * warm-up: the host's draw over the field alone (gl/field.c) */
    int precision;       /* halo image precision: 32, 16 or 8 (halo_link_desc.image_precision) */
    int scale;           /* halo image resolution 1/scale of the frame: 1 (0), 2 or 4 (halo_link_desc.image_scale) */
    double step;         /* sampling distance in voxels; 0: the scene's */
    int all_live;        /* every parameter a uniform (halo_link_desc.all_live) */
    int no_generation;   /* seeding and mapping per sample, no image pass */
    int gradient;        /* the slice/slab hosts' gradient texture (halo_gradient_format); 0: the hosts' default */
    int no_skip;         /* the work a frame does not need, done anyway (issue 16, item 1): every generation
                        * and every slice over the whole image (halo_slice_set_generation_skip 0), and the
                        * occlusion pass (halo_map's mode live) */
} halo_bench_config;

typedef struct halo_bench_case {
    halo_bench_config config;
    const char *axis;       /* what the row varies (for the table): "reference", "M", ... */
    const char *scene_text; /* overrides the environment's scene (NULL: the environment's) */
    /* results */
    double seconds;         /* median frame time */
    long draws, pass_draws; /* per frame */
    size_t gpu_bytes;       /* libhalo's GPU memory after the last frame (halo_gl_frame_info.gpu_bytes) */
    double fetches;         /* the image passes' texel fetches a frame pixel in a frame (env.counting), or NAN */
    int slices;
    float *image;                     /* width*height*4, the last frame (caller frees with halo_bench_cases_free) */
    double max_abs, rmse, share_over; /* against the reference image; NaN when not compared */
    double halo_max_abs;     /* against M = 1 of the slice host at the same step (the halo approximations alone) */
    double gradient_max_abs; /* against the same configuration with float gradients; NaN when there is none */
    long nonfinite;          /* NaN or Inf colour values in the image */
    int pareto;              /* 1: no other halo row is both faster and more accurate */
    /* while running */
    halo_scene *scene;
    halo_program *program;
    void *host;
    double *times;
} halo_bench_case;

typedef struct halo_bench_env {
    halo_library *lib;
    halo_gl *runtime;
    const halo_glfuncs *gl;
    halo_diagnostics *diag;
    int width, height;
    const float *volume;
    int dims[3];
    int repeat;             /* timed frames per case (>= 1) */
    const char *scene_text; /* the scene (JSON text), or */
    const char *scene_path; /* a scene file (when scene_text is NULL) */
    FILE *progress;         /* progress lines (stderr), or NULL */
    halo_gl *counting;      /* a runtime with halo_gl_desc.count_fetches (case.fetches), or NULL */
} halo_bench_env;

/* Renders every case: one warm-up frame each, then env->repeat rounds over all cases
 * (interleaved, so that a change of machine load hits every case alike), glFinish
 * around each frame. Fills seconds, draws, pass_draws, slices, image, nonfinite.
 * Returns 1, or 0 with diagnostics in env->diag. */
int halo_bench_run(const halo_bench_env *env, halo_bench_case *cases, size_t count);
/* Fills max_abs, rmse, share_over of every case with an image against cases[reference]. */
void halo_bench_errors(const halo_bench_env *env, halo_bench_case *cases, size_t count, size_t reference);
/* Marks the Pareto front among the halo cases (time against max_abs). */
void halo_bench_pareto(halo_bench_case *cases, size_t count);
void halo_bench_cases_free(halo_bench_case *cases, size_t count);

#define HALO_BENCH_RAYCAST 2
/* "slice", "slab" or "ray". */
const char *halo_bench_host_name(const halo_bench_config *k);
/* "full", "1/2", "1/4": the halo image resolution of a configuration. */
const char *halo_bench_resolution(const halo_bench_config *k);
/* "float", "half", "snorm8": the effective gradient texture format of a configuration. */
const char *halo_bench_gradient(const halo_bench_config *k);

/* The standard sweep around the scene's settings (M 1..16, N 1..6, precision 32/16/8,
 * halo image resolution full, 1/2, 1/4, gradient texture float, half, snorm8,
 * sampling distance finest..1, slab against slices, a few combinations), headed by the
 * exact reference (index 0: M = 1, float32, the finest sampling) and followed by the
 * renders without halos. Returns the number of cases written (at most max). */
size_t halo_bench_sweep(halo_bench_case *out, size_t max, int scene_passes, double finest_step);

/* Image error: largest absolute colour difference, RMSE over colour, share of pixels
 * with a channel off by more than 1/255. */
void halo_bench_image_error(const float *image, const float *base, size_t pixels, double *max_abs, double *rmse,
                            double *share);

double halo_bench_now(void);

#endif
