/* Fuzz target: the module-annotation parser and the linker on arbitrary module text. */
#include "fuzz.h"
#include "halo.h"
#include "internal.h"

#include <stdlib.h>
#include <string.h>

static const char host[] = "#version 330 core\n#pragma halo declarations\nout vec4 c;\nvoid main() {\n"
                           "#ifdef HALO_LINKED\n halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.1), "
                           "vec3(0.0, 0.0, 1.0), 0.5, gl_FragCoord.xy, vec3(1.0), 0.5);\n halo_apply(s);\n"
                           " c = vec4(s.color, s.opacity);\n halo_finish();\n#endif\n}\n";

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    halo_diagnostics *diag = halo_diagnostics_create();
    halo_library *lib = halo_library_create(diag);
    if (lib && halo_library_override_source(lib, "fuzz.glsl", text, diag) == HALO_OK) {
        /* Link every module of the library that came from the input. */
        for (size_t i = 0; i < halo_library_module_count(lib); i++) {
            const halo_module *m = halo_library_module(lib, i);
            if (strcmp(halo_module_file(m), "fuzz.glsl")) continue;
            halo_scene *scene = halo_scene_create(lib);
            if (scene && halo_scene_enable(scene, halo_module_name(m), 1, diag) == HALO_OK) {
                halo_program *p = halo_link(&(halo_link_desc){.library = lib, .scene = scene, .host_source = host,
                                                              .host_file = "host.frag"},
                                            diag);
                if (p) {
                    char *json = halo_program_reflect_json(p);
                    free(json);
                }
                halo_program_destroy(p);
            }
            halo_scene_destroy(scene);
        }
    }
    halo_library_destroy(lib);
    halo_diagnostics_destroy(diag);
    free(text);
    return 0;
}
