/* Reading a JSON file the way libhalo's scene reader does: a UTF-8 byte-order mark at
 * its start (editors write it) is skipped, so the renderers' own reads of a scene
 * (its render window, the sweep's camera) agree with halo_scene_load. */
#ifndef HALO_EXAMPLE_JSON_FILE_H
#define HALO_EXAMPLE_JSON_FILE_H

#include <jansson.h>

/* As json_load_file(path, flags, error). */
json_t *halo_json_load_file(const char *path, size_t flags, json_error_t *error);

#endif
