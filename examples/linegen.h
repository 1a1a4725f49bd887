/* Line data for the line host (examples/hosts/lines.c) and halo-lines: polylines read
 * from the text format of docs/polyline-format.md, streamlines of an analytic flow and
 * knotted tubes. Not part of the installed libhalo. */
#ifndef HALO_EXAMPLE_LINEGEN_H
#define HALO_EXAMPLE_LINEGEN_H

#include <stddef.h>

#include "halo.h"

/* A set of polylines: line i has the points first[i] .. first[i + 1] - 1. */
typedef struct halo_polylines {
    size_t line_count;
    size_t point_count;
    size_t *first;  /* line_count + 1 entries */
    double *points; /* 3 * point_count: x, y, z */
} halo_polylines;

/* Frees the arrays and zeroes the struct (a zeroed struct is an empty set). */
void halo_polylines_free(halo_polylines *lines);

/* Reads the polyline text format (docs/polyline-format.md). Every error is reported
 * with file:line:column (SCENE_VERSION: header; SCENE_KEY_UNKNOWN: a word that is not
 * a keyword, or a point before the first 'line'; SCENE_TYPE: not a number;
 * SCENE_VALUE_NONFINITE: not finite or beyond +-1e30; SCENE_VALUE_COUNT: not three
 * coordinates, a line of fewer than two points, no line at all; IO_READ). On error
 * *out is left empty. */
halo_status halo_polylines_load(const char *path, halo_polylines *out, halo_diagnostics *diag);
halo_status halo_polylines_parse(const char *text, const char *file, halo_polylines *out, halo_diagnostics *diag);
/* Writes lines in the text format; 0 or -1. */
int halo_polylines_write(const char *path, const halo_polylines *lines);

/* Streamlines of the ABC (Arnold-Beltrami-Childress) flow
 *   u = (A sin z + C cos y, B sin x + A cos z, C sin y + B cos x), A = sqrt 3, B = sqrt 2, C = 1,
 * integrated with fixed-step RK4 (step 0.01) from seeds drawn uniformly (splitmix64 from
 * `seed`) in the box [-pi, pi]^3 (the flow shifted by pi), each until it leaves the box or
 * has max_points points; lines are added until there are at least target_points points.
 * Coordinates are in the box. */
halo_status halo_linegen_streamlines(size_t target_points, int max_points, unsigned long long seed, halo_polylines *out,
                                     halo_diagnostics *diag);

/* A (p, q) torus knot, c(t) = ((2 + cos qt) cos pt, (2 + cos qt) sin pt, -sin qt), drawn
 * as a tube of tube_lines parallel polylines at distance tube_radius from the curve
 * (rotation-minimizing frame, its twist spread so that the tube closes), points_per_line
 * points each. */
halo_status halo_linegen_knot(int p, int q, int tube_lines, int points_per_line, double tube_radius,
                              halo_polylines *out, halo_diagnostics *diag);

#endif
