/* Fuzz target: host-shader checks and the GLSL tokenizer on arbitrary host text. */
#include "fuzz.h"
#include "halo.h"

#include <stdlib.h>
#include <string.h>

static halo_library *library;
static halo_scene *scene;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!library) {
        library = halo_library_create(NULL);
        scene = library ? halo_scene_load("s.json", "{\"stages\": [\"silhouette\", \"tone_shading\"]}", library, NULL)
                        : NULL;
    }
    if (!scene)
        return 0;
    char *text = fuzz_text(data, size);
    if (!text)
        return 0;
    halo_diagnostics *diag = halo_diagnostics_create();
    halo_program *p = halo_link(
        &(halo_link_desc){.library = library, .scene = scene, .host_source = text, .host_file = "fuzz.frag"}, diag);
    halo_program_destroy(p);
    halo_diagnostics_destroy(diag);
    free(text);
    return 0;
}
