/* The registry of conformance rows: every row halo-validate conform runs, in the order
 * it prints them, with what it renders, its tolerance and the reason for it, and the
 * family function that runs it (docs/accuracy.md). `halo-validate conform --list`
 * prints this table.
 *
 * Adding a row is one entry here. A per-sample stage is SAMPLE_ROW(stage, abs, rel, why)
 * (its @exp0, @exp64 and @live variants follow from its parameters). Rows of a new kind
 * (a new host, e.g. segmented ray casting) are a family file, conform_<family>.c, with
 * its run function and a params struct in its header and conform_harness.h as its only
 * dependency in validate/, and their entries here. */
#include "conform_rows.h"

#include "conform_feature.h"
#include "conform_frame.h"
#include "conform_lines.h"
#include "conform_outline.h"
#include "conform_passes.h"
#include "conform_render.h"
#include "conform_sample.h"
#include "conform_segment.h"
#include "conform_slice.h"
#include "figure3.h"

/* Per-sample rows: |gpu - emu| <= abs + rel |emu| + condition for colour and opacity
 * (conform_sample.c explains the conditioning term). */
#define SAMPLE_ROW(stage, abs, rel, why)                                                                          \
    {                                                                                                             \
        stage, "sample", "the stage (defaults, exponents 0 and 64, live) on the probe's hard and random samples", \
            "%.0e+%.0er+cond", abs, rel, why, conform_sample_rows, NULL                                           \
    }
#define FRAME_ROW(name, renders, abs, rel, why, scene, live)                                                       \
    {                                                                                                              \
        name, "frame", renders, "%.0e+%.0er+cond", abs, rel, why, conform_frame_row, &(const conform_frame_params) \
        {                                                                                                          \
            scene, live                                                                                            \
        }                                                                                                          \
    }
#define PASS_ROW(name, renders, tolerance, why, generate, compare, generations, scale)                     \
    {                                                                                                      \
        name, "pass", renders, "%.0e", tolerance, 0.0, why, conform_pass_row, &(const conform_pass_params) \
        {                                                                                                  \
            generate, compare, generations, scale                                                          \
        }                                                                                                  \
    }

#define SEED_ABS 1e-5
#define SEED_REL 1e-5
#define SEED_WHY                                                                                              \
    "pow of |grad f| and smooth windows of value, direction and focus in float32: a few ulps, scaled by the " \
    "gradient scale; the seed image is compared as well"
#define SEED_RENDERS "halo_seed through a GL frame: colour, opacity and the seed image"
#define MAP_ABS      2e-6
#define MAP_REL      4e-6
#define MAP_WHY \
    "the profile's pow and colour mixes on the GPU's own halo images (copied into the emulation): a few ulps"
#define MAP_RENDERS "halo_map after halo_generate on the GPU, through a GL frame"
/* Whole renders of the slice host and the slab ray caster (conform_slice.c: the
 * measured errors behind these tolerances). */
#define SLICE_ROW(name, renders, tolerance, why, halos, slab, interval, scale)                                \
    {                                                                                                         \
        name, "slice", renders, "%.0e", tolerance, 0.0, why, conform_slice_row, &(const conform_slice_params) \
        {                                                                                                     \
            halos, slab, interval, scale, 0                                                                   \
        }                                                                                                     \
    }
#define SLICE_HALOS_TOL 5e-4
#define SLICE_HALOS_WHY                                                                                         \
    "float32 sampling, seeds (|grad f|^alpha amplifies its relative error), image passes and blending of ~110 " \
    "slices against double"
/* The line stages (conform_lines.c); tolerances are plain text: the numbers scale with
 * each vertex's magnitude. */
#define LINES_ROW(name, renders, tolerance, why)                                  \
    {                                                                             \
        name, "lines", renders, tolerance, 0.0, 0.0, why, conform_lines_row, NULL \
    }
#define LINES_VERTEX_WHY \
    "float32 positions and widths: 4e-6 relative to the magnitudes of the point and the eye; colours 1e-6"
#define LINES_HALO_WHY "float32 profile of the distance across the strip, colour, opacity and depth: 1e-6"
/* The outline passes (at=post) on synthetic feature buffers (conform_outline.c). */
#define OUTLINE_ROW(name, shape, occluder_band, outlines, abs, rel, why)                                           \
    {                                                                                                              \
        name, "outline", "the outline passes (at=post) on synthetic feature buffers", "%.0e+%.0er", abs, rel, why, \
            conform_outline_row, &(const conform_outline_params)                                                   \
        {                                                                                                          \
            shape, occluder_band, outlines                                                                         \
        }                                                                                                          \
    }
/* Blurs: float sums of up to 2r+1 taps (r <= size) of exp() weights, renormalized:
 * a few ulps of the depth (<= 1) per tap, 1e-6 relative at most; importance is lambda
 * (<= 4) times a difference of blurred depths: 4e-6; the final colour a mix of colours
 * <= 1 by that importance. Measured: 1.2e-6 at most (64 x 64, llvmpipe); 1e-5 leaves a
 * margin of about 8. */
#define DEPTH_TOL  1e-5
/* Normals: the GPU's normal is normalize(gradient) in float (1e-7 relative), 1 - n.n'
 * of nearly parallel normals loses the leading digits (cancellation: 1e-7 absolute on
 * dN), and the window (dN - n_min) / (n_max - n_min) multiplies it by up to 1 / 0.2;
 * normal blurs add a few ulps per tap as above. Measured: 2e-6 at most (64 x 64). */
#define NORMAL_TOL 2e-5
/* Feature halos (conform_feature.c): the halo buffer, its reference, the stage. */
#define FEATURE_SPLAT(name, renders)                                                                                 \
    {                                                                                                                \
        name, "feature", renders, "%.0e", FEATURE_SPLAT_TOLERANCE, 0.0, FEATURE_SPLAT_WHY, conform_feature_row, NULL \
    }
#define FEATURE_APPLY(name, renders)                                                                                 \
    {                                                                                                                \
        name, "feature", renders, "%.0e", FEATURE_APPLY_TOLERANCE, 0.0, FEATURE_APPLY_WHY, conform_feature_row, NULL \
    }
#define PASS_SPREAD_WHY "float32 sums of 9 taps and a mix per pass (~1e-7 each), gain <= 1 from pass to pass"


/* Scenes of the frame rows (halo_seed's named ones, halo_map's). */
#define SEED_HALOS2                                                                                              \
    "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {\"alpha\": [32, 4], \"beta\": [0.125, 1],"                \
    " \"gradient_scale\": [2, 5], \"value_0\": [[0.2, 0], [0.5, 1], [0.8, 0]], \"value_1\": [[0, 1], [1, 0.2]]," \
    " \"direction_center\": [0, 90], \"direction_width\": [360, 120], \"direction_softness\": [30, 0],"          \
    " \"focus\": [[0.5, 0.5, 0.5], [0.3, 0.6, 0.5]], \"focus_radius\": [10, 0.3],"                               \
    " \"focus_transition\": [0, 0.2]}}]}"
#define SEED_HALOS4                                                                                             \
    "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {\"alpha\": [1, 2, 8, 32], \"beta\": [0, 0.5, 2, 0.125]," \
    " \"direction_center\": [-135, 180, 45, 0], \"direction_width\": [180, 90, 0, 359],"                        \
    " \"direction_softness\": [30, 180, 10, 0], \"focus_radius\": [0.4, 0, 10, 0.5],"                           \
    " \"focus_transition\": [0, 0.5, 0, 10], \"value_2\": [[0.5, 0.3]], \"value_3\": [[0.1, 0], [0.1, 1]]}}]}"
#define MAP_DEFAULT                                                                             \
    "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {\"alpha\": 1, \"gradient_scale\": 20}}," \
    " {\"halo_generate\": {\"delta\": 0.9}}, {\"halo_map\": {\"color_near\": [[1, 0.5, 0]],"    \
    " \"color_far\": [[0, 0, 1]], \"full_at\": 0.5, \"profile_exponent\": 2, \"opacity\": 0.8}}]}"
#define MAP_HALOS2                                                                                         \
    "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {\"alpha\": [1, 2], \"gradient_scale\": [20, 10]}}," \
    " {\"halo_generate\": {\"delta\": [0.9, 0.7]}}, {\"halo_map\": {\"mode\": [0, 1],"                     \
    " \"color_near\": [[1, 0.5, 0], [0, 0, 0]], \"color_far\": [[0, 0, 1], [0.2, 0.2, 0.2]],"              \
    " \"full_at\": [0.5, 0.01], \"profile_exponent\": [2, 0], \"opacity\": [0.8, 1]}}]}"
#define MAP_HALOS4                                                                                                      \
    "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {\"alpha\": 1, \"gradient_scale\": [20, 10, 5, 50]}},"            \
    " {\"halo_generate\": {\"delta\": [0.9, 0.7, 0.5, 1], \"passes\": 3}}, {\"halo_map\": {\"mode\": [1, 0, 0.5, 0.2]," \
    " \"color_near\": [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], \"color_far\": [[0, 0, 0]],"                        \
    " \"full_at\": [1, 0.2, 0.05, 0.5], \"profile_exponent\": [1, 64, 0.5, 3], \"opacity\": [1, 0.5, 0.25, 0.9]}}]}"
#define PASS_COMPARE(...) \
    {                     \
        __VA_ARGS__       \
    }
/* Segmented ray casting (host contract 2, conform_segment.c). */
#define SEGMENT_ROW(name, renders, tolerance, why, scene, segments, orthographic)                                    \
    {                                                                                                                \
        name, "segments", renders, "%.0e", tolerance, 0.0, why, conform_segment_row, &(const conform_segment_params) \
        {                                                                                                            \
            scene, segments, orthographic, NULL, 0.0f, 0, 1                                                          \
        }                                                                                                            \
    }
/* Host contract 3: the one-draw ray caster (the field computed before it) against its emulation. */
/* the one-draw ray caster; scale: its halo images and libhalo's march at 1/scale of the frame */
#define ONE_DRAW_ROW(name, renders, tolerance, why, scene, orthographic, precision, scale)                           \
    {                                                                                                                \
        name, "segments", renders, "%.0e", tolerance, 0.0, why, conform_segment_row, &(const conform_segment_params) \
        {                                                                                                            \
            scene, 0, orthographic, NULL, 0.0f, precision, scale                                                     \
        }                                                                                                            \
    }
#define ONE_DRAW_SCALED_WHY                                                                                  \
    "as ray@one_draw; the march's rays through the centres of the 1/scale pixels, the seeds written there, " \
    "the spreading at the low size, the host's bilinear read of the stack layer"
#define ONE_DRAW_WHY                                                                                             \
    "as ray (float32 sampling, seeds, passes, blending against double), the march's seeds on its planes from "   \
    "the float gradient it derives; the stack layer a sample reads (a decision on phi), the 0.99 threshold and " \
    "the exits bracketed"
#define SEGMENT_SAME_WHY                                                                                \
    "the same samples composited in the same order: a sample belongs to one segment by the same float " \
    "expression in both; only the ended-ray flag (opacity + 2) may round the opacity of ended rays by 1.2e-7"
#define SEGMENT_HALOS_WHY                                                                                  \
    "as the slice rows (float32 sampling, seeds, passes, blending against double); decisions on the 0.99 " \
    "opacity threshold, the rays' exits and the segment a sample falls in bracketed"
#define SEGMENT_RENDER                                                               \
    "\"render\": {\"azimuth\": 30, \"elevation\": 20, \"zoom\": 1.3, \"step\": 0.5," \
    " \"transfer\": [[0, 0, 0, 0, 0], [0.25, 0.6, 0.8, 1, 0.6], [0.5, 1, 0.85, 0.55, 1], [1, 1, 1, 0.8, 1]]}"
#define SEGMENT_SAMPLE_SCENE                                                                             \
    "{\"halo_scene\": 1, \"stages\": [{\"boundary\": {}}, {\"silhouette\": {\"k_ss\": 4, \"k_se\": 1}}," \
    " {\"tone_shading\": {}}, {\"distance_blend\": {}}], " SEGMENT_RENDER "}"
#define SEGMENT_HALOS_SCENE                                                          \
    "{\"halo_scene\": 1, \"stages\": ["                                              \
    " {\"halo_seed\": {\"alpha\": [1, 2], \"beta\": 0.125, \"gradient_scale\": 4}}," \
    " {\"halo_generate\": {\"passes\": 3, \"delta\": [0.8, 0.9], \"interval\": 4}}," \
    " {\"halo_map\": {\"mode\": [0, 1], \"color_near\": [[1, 0.9, 0.4], [0, 0, 0]]," \
    "   \"color_far\": [[1, 0.3, 0.1], [0, 0, 0]], \"opacity\": [0.8, 0.7]}}], " SEGMENT_RENDER "}"
/* the same with the seeds' 3x3 median (a pass that writes the image it reads) */
#define SEGMENT_MEDIAN_SCENE                                                                           \
    "{\"halo_scene\": 1, \"stages\": ["                                                                \
    " {\"halo_seed\": {\"alpha\": [1, 2], \"beta\": 0.125, \"gradient_scale\": 4}},"                   \
    " {\"halo_generate\": {\"passes\": 3, \"delta\": [0.8, 0.9], \"interval\": 4, \"median\": true}}," \
    " {\"halo_map\": {\"mode\": [0, 1], \"color_near\": [[1, 0.9, 0.4], [0, 0, 0]],"                   \
    "   \"color_far\": [[1, 0.3, 0.1], [0, 0, 0]], \"opacity\": [0.8, 0.7]}}], " SEGMENT_RENDER "}"
#define SEGMENT_OUTLINES_SCENE                                                                       \
    "{\"halo_scene\": 1, \"stages\": ["                                                              \
    " {\"halo_seed\": {\"alpha\": 2, \"gradient_scale\": 4}}, {\"halo_generate\": {\"passes\": 3}}," \
    " {\"halo_map\": {\"mode\": 0, \"opacity\": 0.8}},"                                              \
    " {\"outline_feature\": {\"value_min\": 0.55, \"value_max\": 1}},"                               \
    " {\"outlines\": {\"sigma\": 6, \"lambda\": 4, \"depth_power\": 1}}], " SEGMENT_RENDER "}"

/* The hosts in the styles of the wild (examples/hosts/) against the emulation of each
 * (conform_segment.c models what each does otherwise than raycast.frag). */
#define HOST_ROW(name, renders, why, scene, host, jitter)                                  \
    {                                                                                      \
        name, "segments", renders, "%.0e", SLICE_HALOS_TOL, 0.0, why, conform_segment_row, \
            &(const conform_segment_params)                                                \
        {                                                                                  \
            scene, 0, 0, &host, jitter, 0, 1                                               \
        }                                                                                  \
    }
/* ... drawn once over the field libhalo computes first (host contract 3) */
#define HOST_ONE_DRAW_ROW(name, renders, why, scene, host, jitter)                         \
    {                                                                                      \
        name, "segments", renders, "%.0e", SLICE_HALOS_TOL, 0.0, why, conform_segment_row, \
            &(const conform_segment_params)                                                \
        {                                                                                  \
            scene, 0, 0, &host, jitter, 32, 1                                              \
        }                                                                                  \
    }
#define HOST_WHY_DERIVED "libhalo's gradient, view and (planar) depth, emulated from the frame's camera"
/* the ray row's two halos, and distance_blend: the host's depth convention shows */
#define SEGMENT_HOST_SCENE                                                           \
    "{\"halo_scene\": 1, \"stages\": ["                                              \
    " {\"halo_seed\": {\"alpha\": [1, 2], \"beta\": 0.125, \"gradient_scale\": 4}}," \
    " {\"halo_generate\": {\"passes\": 3, \"delta\": [0.8, 0.9], \"interval\": 4}}," \
    " {\"halo_map\": {\"mode\": [0, 1], \"color_near\": [[1, 0.9, 0.4], [0, 0, 0]]," \
    "   \"color_far\": [[1, 0.3, 0.1], [0, 0, 0]], \"opacity\": [0.8, 0.7]}},"       \
    " {\"distance_blend\": {\"k_ds\": 0.8, \"k_de\": 1}}], " SEGMENT_RENDER "}"
#define SEGMENT_EMPTY_SCENE "{\"halo_scene\": 1, \"stages\": [], " SEGMENT_RENDER "}"

const conform_row conform_rows[] = {
    {"empty", "render", "the ray caster linked with no stage against the unlinked one", "0 (bits)", 0.0, 0.0,
     "halo_apply is empty: the linked host must render exactly as before", conform_empty_row, NULL},

    SAMPLE_ROW("gradient", 0.0, 0.0, "writes only normal and |grad f|: colour and opacity pass through bit for bit"),
    SAMPLE_ROW(
        "opacity_power", 2e-6, 8e-6,
        "one pow: llvmpipe's exp2/log2 give ~1e-6 relative for exponents up to 64 (error in the argument e*log2 x)"),
    SAMPLE_ROW(
        "boundary", 2e-6, 8e-6,
        "opacity * (k_gc + k_gs |g|^k_ge): pow as above, scaled by k_gs <= 10 on an opacity <= 1, then saturated"),
    SAMPLE_ROW("silhouette", 4e-6, 8e-6,
               "opacity * (k_sc + k_ss (1-|n.V|)^k_se): k_ss = 50 multiplies pow's ~1e-7 absolute error"),
    SAMPLE_ROW("orientation_fade", 2e-6, 4e-6, "RGB->HSV->RGB in float: a division by chroma and max, a few ulps each"),
    SAMPLE_ROW("sketch", 4e-6, 8e-6, "pow of 1-|n.V| with exponent 8 and a colour mix: a few ulps"),
    SAMPLE_ROW("tone_shading", 2e-6, 4e-6, "sums of up to four lights' dot products and mixes, no pow: a few ulps"),
    SAMPLE_ROW("distance_blend", 2e-6, 4e-6, "one pow of the depth and a mix: a few ulps"),
    SAMPLE_ROW("distance_cue", 2e-6, 4e-6, "a piecewise linear colour map of depth and a mix: a few ulps"),
    /* Stages without a row (added from files): a pow and a few operations. */
    {"*", "sample", "every other per-sample stage of the library, as a per-sample row", "%.0e+%.0er+cond", 1e-5, 1e-5,
     "a stage not in the table", conform_sample_other_rows, NULL},

    FRAME_ROW("halo_seed", SEED_RENDERS, SEED_ABS, SEED_REL, SEED_WHY, NULL, 0),
    FRAME_ROW("halo_seed@halos2", SEED_RENDERS ", two halos", SEED_ABS, SEED_REL, SEED_WHY, SEED_HALOS2, 0),
    FRAME_ROW("halo_seed@halos4", SEED_RENDERS ", four halos", SEED_ABS, SEED_REL, SEED_WHY, SEED_HALOS4, 0),
    FRAME_ROW("halo_seed@live", SEED_RENDERS ", every parameter live", SEED_ABS, SEED_REL, SEED_WHY, NULL, 1),
    FRAME_ROW("halo_map", MAP_RENDERS, MAP_ABS, MAP_REL, MAP_WHY, MAP_DEFAULT, 0),
    FRAME_ROW("halo_map@halos2", MAP_RENDERS ", two halos", MAP_ABS, MAP_REL, MAP_WHY, MAP_HALOS2, 0),
    FRAME_ROW("halo_map@halos4", MAP_RENDERS ", four halos", MAP_ABS, MAP_REL, MAP_WHY, MAP_HALOS4, 0),
    FRAME_ROW("halo_map@live", MAP_RENDERS ", every parameter live", MAP_ABS, MAP_REL, MAP_WHY, NULL, 1),
    FRAME_ROW("outline_feature", "outline_feature's feature buffers (its output images) through a GL frame", SEED_ABS,
              SEED_REL,
              "labels, value windows and depths in float32; a label that flips within the inputs' rounding is the "
              "conditioning term",
              NULL, 0),
    FRAME_ROW("outline_feature@live", "outline_feature, every parameter live, through a GL frame", SEED_ABS, SEED_REL,
              "as outline_feature", NULL, 1),
    {"*", "frame", "every other stage with outputs, images or host uniforms: defaults and @live", "%.0e+%.0er+cond",
     SEED_ABS, SEED_REL, "a stage not in the table", conform_frame_other_rows, NULL},

    {"pass:*", "pass", "every other image-pass stage alone, its inputs noise: every image its passes write",
     "%.0e+%.0er", 1e-5, 1e-5, "a stage not in the table: a few float32 operations a texel", conform_image_other_rows,
     (const char *const[]){"halo_generate", "outlines", NULL}},

    /* with delta 0 the field is H_0; @fold: at the frame's size H_0 not stored, the
     * spreading passes read it from the seed image (halo_generate's fold) */
    PASS_ROW("pass:median", "halo_generate's median pass and H_0 (delta 0: the field is H_0)", 3e-7,
             "the median selects an input value (exact); the gradient after it: one sqrt of a sum of squares, ~1 ulp",
             "{\"median\": true, \"passes\": 1, \"delta\": 0}", {"field"}, 1, 1),
    PASS_ROW("pass:gradient", "H_0 from the seed image (delta 0: the field is H_0)", 3e-7,
             "differences of exact seeds, sqrt of a sum of two squares: ~1 ulp of a value <= 1",
             "{\"passes\": 1, \"delta\": 0}", {"field"}, 1, 1),
    PASS_ROW("pass:gradient@half", "halo_generate's gradient pass on halo images at 1/2 of the frame", 3e-7,
             "as pass:gradient, after an exact max-downsampling", "{\"passes\": 1}", {"initial"}, 1, 2),
    PASS_ROW("pass:spread@N1", "one spreading pass", 2e-6, PASS_SPREAD_WHY, "{\"passes\": 1}", {"field"}, 1, 1),
    PASS_ROW("pass:spread@N2", "two spreading passes", 2e-6, "as N1, over 2 passes", "{\"passes\": 2}", {"field"}, 1,
             1),
    PASS_ROW("pass:spread@N3", "three spreading passes", 2e-6, "as N1, over 3 passes", "{\"passes\": 3}", {"field"}, 1,
             1),
    PASS_ROW("pass:spread@N4", "four spreading passes", 2e-6, "as N1, over 4 passes", "{\"passes\": 4}", {"field"}, 1,
             1),
    PASS_ROW("pass:spread@delta0", "four spreading passes with delta 0", 3e-7, "delta 0: H_N = H_0 exactly",
             "{\"passes\": 4, \"delta\": 0}", {"field"}, 1, 1),
    PASS_ROW("pass:spread@delta1", "four spreading passes with delta 1", 2e-6, "as N4", "{\"passes\": 4, \"delta\": 1}",
             {"field"}, 1, 1),
    PASS_ROW("pass:spread@fold", "four spreading passes, H_0 folded into them (fold: no gradient pass)", 2e-6, "as N4",
             "{\"passes\": 4, \"fold\": true}", {"field"}, 1, 1),
    PASS_ROW("pass:halos4@fold", "four halos, median on, H_0 folded into the spreading (fold)", 2e-6, "as halos4",
             "{\"passes\": 3, \"delta\": [0, 0.5, 0.8, 1], \"median\": true, \"fold\": true}",
             PASS_COMPARE("field", "occlusion"), 2, 1),
    PASS_ROW("pass:spread@wide2", "the approximation wide: two passes of 49 taps (spacing 4 and 1)", 2e-6,
             "as N1: 49 products per pass in float, values <= 1", "{\"passes\": 2, \"wide\": true}",
             PASS_COMPARE("initial", "field"), 1, 1),
    PASS_ROW("pass:occlude", "the occlusion image over two generations in one frame", 2e-6,
             "max of two fields (exact) over 2 generations in one frame: the spreading's error", "{\"passes\": 4}",
             PASS_COMPARE("occlusion", "field"), 2, 1),
    PASS_ROW("pass:halos2", "two halos (vec2 images)", 2e-6, "two halos (vec2 images): as N4 per channel",
             "{\"passes\": 4, \"delta\": [0.7, 0.95]}", PASS_COMPARE("field", "occlusion"), 1, 1),
    PASS_ROW("pass:halos4", "four halos (vec4 images), median on", 2e-6,
             "four halos (vec4 images), median on: as N4 per channel",
             "{\"passes\": 3, \"delta\": [0, 0.5, 0.8, 1], \"median\": true}", PASS_COMPARE("field", "occlusion"), 2,
             1),
    /* halo images at 1/2 and 1/4 of the frame (an odd frame size gives partial blocks):
     * the first pass max-downsamples the full-size seed (exact), the rest as above */
    PASS_ROW("pass:spread@half", "spreading on halo images at 1/2 of the frame", 2e-6, "as N4 on the 1/2 images",
             "{\"passes\": 4}", PASS_COMPARE("initial", "field"), 1, 2),
    PASS_ROW("pass:wide@half", "the approximation wide on halo images at 1/2 of the frame", 2e-6,
             "as wide2 on the 1/2 images (spacing max(1, 4^(N-i) / 2))", "{\"passes\": 3, \"wide\": true}",
             PASS_COMPARE("initial", "field"), 1, 2),
    PASS_ROW("pass:halos4@quarter", "four halos on halo images at 1/4 of the frame", 2e-6,
             "as halos4 on the 1/4 images", "{\"passes\": 3, \"delta\": [0, 0.5, 0.8, 1], \"median\": true}",
             PASS_COMPARE("initial", "field", "occlusion"), 2, 4),

    OUTLINE_ROW("outline:discs", OUTLINE_DISCS, 0, "\"sigma\": 12, \"lambda\": 4", DEPTH_TOL, DEPTH_TOL,
                "blurred depth, lambda 4"),
    OUTLINE_ROW("outline:power0.6", OUTLINE_DISCS, 0, "\"sigma\": 12, \"lambda\": 2, \"depth_power\": 0.6", 1e-4,
                DEPTH_TOL,
                "x^0.6 near x = 0 magnifies the blur's float error: d(x^0.6)/dx = 0.6 x^-0.4, 2.5e3 at x = 1e-8"),
    OUTLINE_ROW("outline:flat", OUTLINE_FLAT, 0, "\"sigma\": 12, \"lambda\": 1000", DEPTH_TOL, DEPTH_TOL,
                "a constant depth blurs to itself (renormalized weights): no outline even at lambda 1000"),
    OUTLINE_ROW("outline:depth1", OUTLINE_DEPTH_ONE, 0,
                "\"sigma\": 12, \"lambda\": 1000, \"depth_start\": 0.5, \"depth_cue\": true", DEPTH_TOL, DEPTH_TOL,
                "features at depth exactly 1 are the background: no outline, gamma 1"),
    OUTLINE_ROW("outline:pixel", OUTLINE_PIXEL, 0, "\"sigma\": 12, \"lambda\": 4", DEPTH_TOL, DEPTH_TOL,
                "a one-pixel feature: its ring of outline"),
    OUTLINE_ROW("outline:border", OUTLINE_BORDER, 0, "\"sigma\": 18, \"lambda\": 4", DEPTH_TOL, DEPTH_TOL,
                "features touching the border: taps outside the image are left out, weights renormalized"),
    OUTLINE_ROW(
        "outline:sigma>image", OUTLINE_DISCS, 0,
        "\"sigma\": 600, \"lambda\": 4, \"normal_unsharp\": true, \"normal_sigma\": 600", NORMAL_TOL, NORMAL_TOL,
        "kernel size 600 % of the diagonal (standard deviation 100 %): radius clamped to the image side, 2 size + 1 taps"),
    OUTLINE_ROW(
        "outline:normals", OUTLINE_DISCS, 0,
        "\"sigma\": 12, \"lambda\": 2, \"normal_difference\": true, \"normal_unsharp\": true, \"normal_sigma\": 12,"
        " \"normal_min\": 0.05, \"normal_max\": 0.6",
        NORMAL_TOL, NORMAL_TOL, "normals zero (no hit) outside the discs: halo_normalize of 0, 1 - dot"),
    OUTLINE_ROW("outline:hidden", OUTLINE_DISCS, 1, "\"sigma\": 12, \"lambda\": 4, \"occluded\": 0", DEPTH_TOL,
                DEPTH_TOL, "occlusion: hidden"),
    OUTLINE_ROW("outline:dashed", OUTLINE_DISCS, 1, "\"sigma\": 12, \"lambda\": 4, \"occluded\": 1, \"dash_length\": 3",
                DEPTH_TOL, DEPTH_TOL, "occlusion: dashed (integer dash arithmetic)"),
    OUTLINE_ROW("outline:front", OUTLINE_DISCS, 1, "\"sigma\": 12, \"lambda\": 4, \"occluded\": 2", DEPTH_TOL,
                DEPTH_TOL, "occlusion: forced to the front"),
    OUTLINE_ROW("outline:colors", OUTLINE_DISCS, 0, "\"sigma\": 12, \"lambda\": 4, \"line_color_mode\": 2", DEPTH_TOL,
                DEPTH_TOL, "line colour by the brightness behind"),
    OUTLINE_ROW(
        "outline:depth", OUTLINE_DISCS, 0,
        "\"sigma\": 12, \"lambda\": 4, \"depth_start\": 0.3, \"depth_color_blend\": true, \"depth_color\": [0.9, 0.9, 1],"
        " \"depth_cue\": true, \"cue_gray\": 0.6, \"depth_blur\": true, \"blur_max\": 8, \"line_fading\": true,"
        " \"line_color_mode\": 1",
        DEPTH_TOL, DEPTH_TOL, "depth colour blending, cueing, blurring (kernel per pixel), line fading"),
    OUTLINE_ROW("outline:features4", OUTLINE_FOUR, 1,
                "\"sigma\": 12, \"lambda\": [4, 2, 8, 1], \"occluded\": [0, 1, 2, 2], \"normal_difference\": true,"
                " \"normal_min\": [0.1, 0.2, 0.3, 2], \"normal_max\": [0.5, 0.5, 0.3, 3]",
                NORMAL_TOL, NORMAL_TOL, "four features, per-feature parameters"),
    OUTLINE_ROW("outline:features6", OUTLINE_SIX, 1,
                "\"sigma\": 12, \"lambda\": [4, 2, 8, 1, 4, 6], \"occluded\": [0, 1, 2, 2, 1, 2], \"depth_start\": 0.3,"
                " \"depth_cue\": true, \"line_fading\": true",
                DEPTH_TOL, DEPTH_TOL, "six features in two feature groups (two volume passes), depth cueing over both"),
    SLICE_ROW("slice", "the slice host with two halos", SLICE_HALOS_TOL, SLICE_HALOS_WHY, 1, 0, 0, 1),
    SLICE_ROW("slice@nohalo", "the slice host without stages", 1e-4,
              "float32 trilinear sampling, opacity correction and blending of ~110 slices against double", 0, 0, 0, 1),
    SLICE_ROW("slab", "the slab ray caster with two halos, M = 1", SLICE_HALOS_TOL, SLICE_HALOS_WHY, 1, 1, 1, 1),
    SLICE_ROW("slab@M4", "the slab ray caster with two halos, M = 4", SLICE_HALOS_TOL, SLICE_HALOS_WHY, 1, 1, 4, 1),
    /* halo images at 1/2 and 1/4 of the frame (halo_link_desc.image_scale): the
     * max-downsampled seed, the spreading at the low size, the bilinear read */
    {"slice@one_draw", "slice",
     "the slice host with two halos, M = 4, its slices drawn at once over the field "
     "(host contract 3)",
     "%.0e", SLICE_HALOS_TOL, 0.0,
     SLICE_HALOS_WHY " (the field from libhalo's march on the "
                     "slices' planes)",
     conform_slice_row, &(const conform_slice_params){1, 0, 4, 0, 1}},
    SLICE_ROW("slice@half", "the slice host, halo images at 1/2", SLICE_HALOS_TOL, SLICE_HALOS_WHY, 1, 0, 0, 2),
    SLICE_ROW("slab@quarter", "the slab ray caster, M = 4, halo images at 1/4", SLICE_HALOS_TOL, SLICE_HALOS_WHY, 1, 1,
              4, 4),
    /* Host contract 2: the single-pass ray caster drawn in depth segments (conform_segment.c) */
    SEGMENT_ROW("segments@K4", "the ray caster with per-sample stages in 4 forced segments against one draw", 1e-6,
                SEGMENT_SAME_WHY, SEGMENT_SAMPLE_SCENE, 4, 0),
    SEGMENT_ROW("segments@K16", "16 forced segments against one draw, early ray termination on most rays", 1e-6,
                SEGMENT_SAME_WHY, SEGMENT_SAMPLE_SCENE, 16, 0),
    SEGMENT_ROW("segments@K16_ortho", "16 forced segments, orthographic camera", 1e-6, SEGMENT_SAME_WHY,
                SEGMENT_SAMPLE_SCENE, 16, 1),
    SEGMENT_ROW("ray", "the segmented ray caster with two halos, M = 4", SLICE_HALOS_TOL, SEGMENT_HALOS_WHY,
                SEGMENT_HALOS_SCENE, 0, 0),
    SEGMENT_ROW("ray@ortho", "the segmented ray caster with two halos, orthographic", SLICE_HALOS_TOL,
                SEGMENT_HALOS_WHY
                "; every ray meets the planes between segments at the same depths, so many samples lie "
                "on a plane: each plane's decision is bracketed both ways, all planes together and "
                "alternately (at 256, 1 pixel was 3.3e-3 off with the planes moved all one way)",
                SEGMENT_HALOS_SCENE, 0, 1),
    SEGMENT_ROW("ray@outlines", "the segmented ray caster with a halo and outlines (post passes)", SLICE_HALOS_TOL,
                SEGMENT_HALOS_WHY, SEGMENT_OUTLINES_SCENE, 0, 0),
    ONE_DRAW_ROW("ray@one_draw", "the one-draw ray caster (host contract 3) with two halos, M = 4", SLICE_HALOS_TOL,
                 ONE_DRAW_WHY, SEGMENT_HALOS_SCENE, 0, 32, 1),
    ONE_DRAW_ROW("ray@one_draw_median", "the one-draw ray caster, two halos, M = 4, the seeds' 3x3 median",
                 SLICE_HALOS_TOL, ONE_DRAW_WHY, SEGMENT_MEDIAN_SCENE, 0, 32, 1),
    ONE_DRAW_ROW("ray@one_draw_ortho", "the one-draw ray caster with two halos, orthographic", SLICE_HALOS_TOL,
                 ONE_DRAW_WHY, SEGMENT_HALOS_SCENE, 1, 32, 1),
    ONE_DRAW_ROW("ray@one_draw_outlines", "the one-draw ray caster with a halo and outlines (post passes)",
                 SLICE_HALOS_TOL, ONE_DRAW_WHY, SEGMENT_OUTLINES_SCENE, 0, 32, 1),
    ONE_DRAW_ROW("ray@one_draw_half", "the one-draw ray caster, two halos, the march's gradient RGBA16F", 5e-3,
                 "as ray@one_draw, on a half-float gradient (11 significant bits: relative error up to 2^-12 in each "
                 "component, so in |g| and the seeds, which the spreading and the halo profile carry on), against "
                 "the exact gradient: the error of the half gradient itself; measured max abs 1.3e-4 at 25x25, "
                 "2.9e-3 at 64x64, 3.3e-3 at 128x128",
                 SEGMENT_HALOS_SCENE, 0, 16, 1),
    ONE_DRAW_ROW("ray@one_draw_scale2", "the one-draw ray caster, two halos, M = 4, halo images at 1/2",
                 SLICE_HALOS_TOL, ONE_DRAW_SCALED_WHY, SEGMENT_HALOS_SCENE, 0, 32, 2),
    ONE_DRAW_ROW("ray@one_draw_scale4", "the one-draw ray caster, two halos, M = 4, halo images at 1/4",
                 SLICE_HALOS_TOL, ONE_DRAW_SCALED_WHY, SEGMENT_HALOS_SCENE, 0, 32, 4),
    HOST_ROW("ray@webgl", "webgl_caster.frag (ES 300 style, linked for GLSL 330 here), jitter 1, two halos, M = 4",
             "as ray; the jitter is the host's integer hash of the pixel, exact in C; " HOST_WHY_DERIVED "; the ceil "
             "step count bracketed (rays run to their end: the seeds read every sample)",
             SEGMENT_HOST_SCENE, conform_segment_webgl, 1.0f),
    HOST_ONE_DRAW_ROW("ray@webgl_one_draw", "webgl_caster.frag, jitter 1, two halos, M = 4, drawn once (contract 3)",
                      "as ray@webgl, the field as ray@one_draw; early termination at 0.98 bracketed",
                      SEGMENT_HOST_SCENE, conform_segment_webgl, 1.0f),
    HOST_ROW("ray@webgl_sample", "webgl_caster.frag, jitter 1, per-sample stages: early termination at 0.98",
             "as ray@webgl; the termination decision on 0.98 bracketed; holds at 25 to 128 pixels a side: at 256, 1 "
             "pixel of 65536 is 2.7e-3 off, where a sample of opacity 0.998 lies at a near-zero gradient (|g| "
             "5.9e-4 of a voxel, the ray's samples before it 0.1 to 0.17): its normal, and so its tone, is the "
             "direction of differences of two filtered fetches that float32 and the texture unit's weights give "
             "only to about 1e-3",
             SEGMENT_SAMPLE_SCENE, conform_segment_webgl, 1.0f),
    HOST_ROW("ray@exit_points", "exit_point_caster.frag (two passes, GL 4.5) with two halos, M = 4",
             "as ray; the exit is the back-face pass's interpolated point (the box's exit up to the rasterizer's "
             "float interpolation): its step count bracketed as ray's exits; " HOST_WHY_DERIVED,
             SEGMENT_HOST_SCENE, conform_segment_exit_points, 0.0f),
    HOST_ONE_DRAW_ROW("ray@exit_points_one_draw", "exit_point_caster.frag, two halos, M = 4, drawn once (contract 3)",
                      "as ray@exit_points, the field as ray@one_draw; early termination at 0.99 bracketed",
                      SEGMENT_HOST_SCENE, conform_segment_exit_points, 0.0f),
    HOST_ROW("ray@exit_points_sample", "exit_point_caster.frag, per-sample stages: early termination at 0.99",
             "as ray@exit_points; the termination decision on 0.99 bracketed", SEGMENT_SAMPLE_SCENE,
             conform_segment_exit_points, 0.0f),
    HOST_ROW("ray@tf2d", "tf2d_caster.frag (2D transfer function, Phong) with two halos, M = 4",
             "as ray; the 2D transfer function (smoothsteps of |g|) and the Phong headlight (pow 24) in float32 "
             "on the float32 gradient; the host's view, libhalo's planar depth; the exits bracketed",
             SEGMENT_HOST_SCENE, conform_segment_tf2d, 0.0f),
    HOST_ONE_DRAW_ROW("ray@tf2d_one_draw", "tf2d_caster.frag, two halos, M = 4, drawn once (contract 3)",
                      "as ray@tf2d, the field as ray@one_draw; early termination past 0.995 bracketed",
                      SEGMENT_HOST_SCENE, conform_segment_tf2d, 0.0f),
    HOST_ROW("ray@tf2d_sample", "tf2d_caster.frag, per-sample stages: early termination past 0.995",
             "as ray@tf2d; the termination decision on 0.995 bracketed", SEGMENT_SAMPLE_SCENE, conform_segment_tf2d,
             0.0f),
    HOST_ROW("ray@iso", "mip_iso_caster.frag, isosurface at 0.5, with two halos, M = 4",
             "as ray; the hit is a decision on value >= 0.5 (float32 trilinear value): bracketed with the value "
             "moved by 1e-5, as the exits; the host's gradient at hits only; " HOST_WHY_DERIVED,
             SEGMENT_HOST_SCENE, conform_segment_iso, 0.0f),
    HOST_ONE_DRAW_ROW("ray@iso_one_draw", "mip_iso_caster.frag's isosurface, two halos, M = 4, drawn once (contract 3)",
                      "as ray@iso, the field as ray@one_draw; a hit ends the ray", SEGMENT_HOST_SCENE,
                      conform_segment_iso, 0.0f),
    HOST_ROW("ray@iso_sample", "mip_iso_caster.frag's isosurface, per-sample stages: the first hit ends the ray",
             "as ray@iso; opacity 1 at a hit ends the ray (0.99)", SEGMENT_SAMPLE_SCENE, conform_segment_iso, 0.0f),
    HOST_ROW("ray@mip", "mip_iso_caster.frag's MIP variant (no stage: it refuses them), drawn once",
             "the ray rows' tolerance, generous here: float32 trilinear values, their maximum along the ray and one "
             "table lookup; the step count bracketed",
             SEGMENT_EMPTY_SCENE, conform_segment_mip, 0.0f),
    FEATURE_SPLAT("feature_splat", "the GPU halo buffer against its emulation, oblique view"),
    FEATURE_SPLAT("feature_splat@n3", "splats of 3^3, view along an axis"),
    FEATURE_SPLAT("feature_splat@n9", "splats of 9^3, threshold 0.2"),
    FEATURE_SPLAT("feature_splat@half", "the buffer at half resolution"),
    FEATURE_SPLAT("feature_splat@weighted", "gradient-weighted splats"),
    FEATURE_SPLAT("feature_splat@nocutoff", "no threshold, a side view"),
    FEATURE_SPLAT("feature_splat@constant", "a constant volume (nothing splats)"),
    FEATURE_SPLAT("feature_splat@voxel", "a single voxel, splats of 7^3"),
    FEATURE_SPLAT("feature_splat@edge", "features at the volume's edge"),
    FEATURE_SPLAT("feature_splat@edge_half", "features at the volume's edge, half resolution"),
    {"feature_reference", "feature", "the emulated buffer against the exact reference (double)", "%.0e",
     FEATURE_REFERENCE_TOLERANCE, 0.0, FEATURE_REFERENCE_WHY, conform_feature_row, NULL},
    FEATURE_APPLY("feature_halo", "the stage feature_halo on a probe against its emulation"),
    FEATURE_APPLY("feature_halo@live", "feature_halo, every parameter live"),
    FEATURE_APPLY("feature_halo@strong", "feature_halo with opacity gain and darkening 50"),
    LINES_ROW("line_strip", "line_strip's vertex stage on controlled strips (line_probe.vert)", "4e-6*(1+|p|+|eye|)",
              LINES_VERTEX_WHY),
    LINES_ROW("line_strip@degenerate", "line_strip on a line at the eye, zero-length segments, coincident vertices",
              "4e-6*(1+|p|+|eye|)", LINES_VERTEX_WHY),
    LINES_ROW("line_halo@linear", "line_halo's fragment stage across the strip, linear profile", "1e-6",
              LINES_HALO_WHY),
    LINES_ROW("line_halo@smooth", "line_halo's fragment stage, smooth profile", "1e-6", LINES_HALO_WHY),
    LINES_ROW("line_halo@step", "line_halo's fragment stage, step profile", "1e-6", LINES_HALO_WHY),
    LINES_ROW("lines@depth_gap", "a line behind another, depth gap above and below d_max (image test)",
              "gap>d_max hides", "the halo hides the line behind exactly when the gap exceeds d_max"),
    LINES_ROW("lines@near_plane", "a strip across the near plane (image test)", "finite",
              "every pixel finite, and the line drawn"),

    {"raycast", "render", "a small whole render of the ray caster with four stages against its C emulation", "%.0e",
     2e-4, 0.0,
     "float32 texel coordinates and trilinear weights (~1e-7 relative per fetch), central differences (~1e-6 on "
     "gradients), opacities scaled by k_gs <= 10 and ~100 composited samples; measured on llvmpipe (LLVM 15) 8e-6 "
     "at 25x25, 1.1e-5 at 64x64, 2.2e-5 at 128x128: a margin of about 10",
     conform_raycast_row, NULL},
    {"figure3", "figure3", "Bruckner & Groller 2007 Fig. 3 as numbers (emulation)", "|log f| < |log b|", 0.0, 0.0,
     "the paper's claim: spreading the seed gradient keeps small features' halos where a low-pass of the seeds "
     "loses them",
     conform_figure3_row, NULL},
};

const size_t conform_row_count = sizeof conform_rows / sizeof conform_rows[0];
