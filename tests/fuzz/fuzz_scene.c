/* Fuzz target: the scene reader on arbitrary JSON. */
#include "fuzz.h"
#include "halo.h"

#include <stdlib.h>
#include <string.h>

static halo_library *library;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!library)
        library = halo_library_create(NULL);
    if (!library)
        return 0;
    char *text = fuzz_text(data, size);
    if (!text)
        return 0;
    halo_diagnostics *diag = halo_diagnostics_create();
    halo_scene *scene = halo_scene_load("fuzz.json", text, library, diag);
    if (scene) {
        static const char host[] =
            "#pragma halo declarations\nlayout(location = 0) out vec4 c;\n"
            "void main() { halo_sample s; halo_apply(s); halo_finish(); c = vec4(1.0); }\n";
        halo_program *p = halo_link(&(halo_link_desc){.library = library, .scene = scene, .host_source = host}, diag);
        halo_program_destroy(p);
    }
    halo_scene_destroy(scene);
    halo_diagnostics_destroy(diag);
    free(text);
    return 0;
}
