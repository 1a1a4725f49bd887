/* Writing rendered images (the examples' one C++ dependency, OpenImageIO). */
#ifndef HALO_EXAMPLE_IMAGE_WRITE_H
#define HALO_EXAMPLE_IMAGE_WRITE_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Writes w×h RGBA floats (rows bottom-up, as glReadPixels returns them) to path,
 * upright. ".exr" (any case): 32-bit float, values as they are. Anything else
 * (".png"...): 8 bits per channel, values clamped to [0,1] and written as they are
 * (no sRGB encoding), NaN as 0. Returns 0, or -1 with a message in err. */
int halo_image_write(const char *path, int w, int h, const float *rgba, char *err, size_t errlen);
/* Whether halo_image_write can write path, asked before rendering: its format is one
 * OpenImageIO writes, its folder exists and is writable, and the path is no folder and,
 * when it exists, writable. Writes nothing. Returns 0, or -1 with "PATH: why" in err. */
int halo_image_check(const char *path, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif
#endif
