/* The bench's memory column: peak resident bytes per voxel, measured from outside on
 * halo-render (docs/performance.md, "Memory"). */
#ifndef HALO_BENCH_MEMORY_H
#define HALO_BENCH_MEMORY_H

#include "hosts/slice.h"

#include <stdio.h>

typedef struct halo_bench_memory {
    int size; /* the volume side measured; 0: not measured */
    /* [0][0]: no halos; [1][format]: the scene with the gradient texture in format
     * (halo_gradient_format); NaN where the run failed */
    double bytes_per_voxel[2][HALO_GRADIENT_FORMAT_COUNT];
} halo_bench_memory;

/* Runs halo-render (the binary beside this program's, or ../tools/halo-render in the
 * build tree) with --host slice --size 64x64 --quiet on the built-in volume at size^3
 * and at 32^3, and takes (peak(size) - peak(32)) / (size^3 - 32^3) from the children's
 * ru_maxrss: once without stages, once for the scene (scene_path, or scene_text written
 * to a temporary file) per gradient format. Returns 1, or 0 with a line on stderr (no
 * halo-render found, no temporary folder). */
int halo_bench_memory_measure(const char *scene_path, const char *scene_text, int size, halo_bench_memory *out,
                              FILE *progress);

/* The column's text for a configuration: "12.0", or "-". */
void halo_bench_memory_cell(const halo_bench_memory *m, int halos, int gradient, char *out, size_t size);

#endif
