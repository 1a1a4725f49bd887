/* The C side of the example line host (line.vert / line.frag): depth-dependent halos
 * for dense line data (Everts et al. 2009, docs/lines.md). Not part of the installed
 * libhalo: halo-lines, halo-validate and the tests link it from the hosts library.
 *
 * Every GL call goes through a halo_glfuncs table; the caller's context must be current. */
#ifndef HALO_EXAMPLE_LINES_H
#define HALO_EXAMPLE_LINES_H

#include "halo.h"
#include "halo_gl_loader.h"
#include "linegen.h"

/* ---- Scenes and programs -------------------------------------------------------- */

/* A line scene lists the stages of both line hooks; each host takes its own. Disables
 * in scene every stage whose hook is not `hook` (HALO_HOOK_LINE_VERTEX or
 * HALO_HOOK_LINE_FRAGMENT). */
void halo_lines_scene_keep_hook(halo_scene *scene, const halo_library *lib, halo_hook hook);

/* Links the line host's shaders (vertex_source / fragment_source, NULL: the embedded
 * line.vert / line.frag) with the stages of a scene for each hook: the scene is the file
 * scene_path, else the JSON text scene_text, else none (no stage). On success both
 * programs are set (free with halo_program_destroy). */
halo_status halo_lines_link(const halo_library *lib, const char *scene_path, const char *scene_text,
                            const char *vertex_source, const char *fragment_source, halo_program **vertex,
                            halo_program **fragment, halo_diagnostics *diag);

/* The same with scene objects (NULL: no stage); the stages of the other hook must already
 * be disabled (halo_lines_scene_keep_hook). */
halo_status halo_lines_link_scenes(const halo_library *lib, const halo_scene *vertex_scene,
                                   const halo_scene *fragment_scene, const char *vertex_source,
                                   const char *fragment_source, halo_program **vertex, halo_program **fragment,
                                   halo_diagnostics *diag);

/* Compiles and links a vertex and a fragment shader: each either a linked program
 * (driver messages mapped to the module's or host's file:line) or, where the program is
 * NULL, the plain text. Returns the GL program or 0 with GL_COMPILE / GL_LINK. */
unsigned halo_lines_build_program(const halo_glfuncs *gl, const halo_program *vertex_program, const char *vertex_source,
                                  const char *vertex_file, const halo_program *fragment_program,
                                  const char *fragment_source, const char *fragment_file, halo_diagnostics *diag);

/* ---- The line renderer ------------------------------------------------------------ */

typedef struct halo_lines_desc {
    const halo_glfuncs *gl;               /* required; the context must be current */
    const halo_program *vertex_program;   /* line.vert linked (kind HALO_SHADER_VERTEX), or NULL ... */
    const halo_program *fragment_program; /* line.frag linked, or NULL ... */
    const char *vertex_source;            /* ... for this unlinked text (default: embedded line.vert) */
    const char *fragment_source;          /* ... (default: embedded line.frag) */
    int width, height;                    /* render target size, 1..16384, required */
} halo_lines_desc;

/* What a draw sees. Zero is the default wherever it makes sense. */
typedef struct halo_lines_view {
    double azimuth, elevation; /* degrees: the camera orbits the data's centre (0, 0: on +z, looking down -z) */
    double zoom;               /* 1 (or 0): the bounding sphere fits the view */
    double centre[3];          /* with radius > 0: the bounds to frame; else the data's bounding sphere */
    double radius;
    double eye_shift;     /* stereo: moves the eye along the camera's right axis by this fraction of
                                  the eye distance, still looking at the centre */
    double background[3]; /* linear RGB; the halo colour */
    double line_color[3]; /* linear RGB */
    int mask_channels;    /* 0: write all; else bits 1 red, 2 green, 4 blue (anaglyph) */
    int keep_color;       /* 1: clear only depth (the second eye of an anaglyph) */
} halo_lines_view;

/* The values a draw uploads (float-rounded), for an emulation or a test. */
typedef struct halo_lines_state {
    double view_projection[16]; /* column-major, world -> clip */
    double eye[3], forward[3];
    double depth_range[2];    /* host uniform depth_range: along forward */
    double distance_range[2]; /* halo_host_depth_range: distances from the eye */
    double width_unit;        /* the data's radius */
} halo_lines_state;

typedef struct halo_lines halo_lines;

halo_lines *halo_lines_create(const halo_lines_desc *desc, halo_diagnostics *diag);
void halo_lines_destroy(halo_lines *l);
/* Builds the strip (each point twice, v = 0 and 1; u = arc length / line length; D the
 * average of the unit directions of the adjacent non-zero segments, or 0 where a line
 * has no extent) and uploads it. */
halo_status halo_lines_set_data(halo_lines *l, const halo_polylines *lines, halo_diagnostics *diag);
/* Strip vertices uploaded (twice the points). */
size_t halo_lines_vertex_count(const halo_lines *l);
/* Draws into the RGBA8 target with a DEPTH32F buffer (clears first, see keep_color). */
halo_status halo_lines_draw(halo_lines *l, const halo_lines_view *view, halo_diagnostics *diag);
/* Waits for the GPU (for timing). */
void halo_lines_finish(halo_lines *l);
/* Reads the target: width*height*4 floats, rows bottom-up. */
halo_status halo_lines_read(halo_lines *l, float *rgba, halo_diagnostics *diag);
/* The state of the last draw (or of `view` without drawing when view is not NULL). */
void halo_lines_get_state(const halo_lines *l, const halo_lines_view *view, halo_lines_state *state);
/* Window coordinates (pixels, origin bottom-left) of a world point under state. */
void halo_lines_project(const halo_lines *l, const halo_lines_state *state, const double point[3], double pixel[2]);

/* The strip geometry of halo_lines_set_data, for emulations: for point k of line i,
 * its averaged direction and u. direction[3*k..], u[k] for every point. */
void halo_lines_strip_attributes(const halo_polylines *lines, double *direction, double *u);

#endif
