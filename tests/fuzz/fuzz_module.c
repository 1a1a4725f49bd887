/* Fuzz target: the module-annotation parser and the linker on arbitrary module text. */
#include "fuzz.h"
#include "halo.h"
#include "internal.h"

#include <stdlib.h>
#include <string.h>

static const char host[] =
    "#version 330 core\n#pragma halo declarations\nout vec4 c;\nvoid main() {\n"
    "#ifdef HALO_LINKED\n halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.1), "
    "vec3(0.0, 0.0, 1.0), 0.5, gl_FragCoord.xy, vec3(1.0), 0.5);\n halo_apply(s);\n"
    " c = vec4(s.color, s.opacity);\n halo_finish();\n#endif\n}\n";

/* The built-in library is parsed once; each input module is swapped in for the run
 * (replacing a module of the same name, as halo_library_add with HALO_ADD_REPLACE does) and out
 * again, so that an input costs its own parse and link, not the whole library's
 * (about 280 inputs/s when the library was rebuilt per input). */
static halo_library *library;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text(data, size);
    if (!text)
        return 0;
    halo_diagnostics *diag = halo_diagnostics_create();
    if (!library)
        library = halo_library_create(diag);
    halo_module *m = library ? halo_module_parse("fuzz.glsl", text, diag) : NULL;
    if (m) {
        size_t slot = library->count;
        for (size_t i = 0; i < library->count; i++)
            if (!strcmp(halo_module_name_of(library->modules[i]), halo_module_name_of(m)))
                slot = i;
        halo_module **grown =
            slot == library->count ? realloc(library->modules, (library->count + 1) * sizeof *grown) : library->modules;
        if (grown) {
            library->modules = grown;
            halo_module *kept = slot < library->count ? grown[slot] : NULL;
            grown[slot] = m;
            if (!kept)
                library->count++;
            halo_scene *scene = halo_scene_create(library);
            if (scene && halo_scene_enable(scene, halo_module_name_of(m), 1, diag) == HALO_OK) {
                halo_program *p = halo_link(
                    &(halo_link_desc){
                        .library = library, .scene = scene, .host_source = host, .host_file = "host.frag"},
                    diag);
                if (p) {
                    char *json = halo_program_reflect_json(p);
                    free(json);
                }
                halo_program_destroy(p);
            }
            halo_scene_destroy(scene);
            if (kept)
                grown[slot] = kept;
            else
                library->count--;
        }
        halo_module_free(m);
    }
    halo_diagnostics_destroy(diag);
    free(text);
    return 0;
}
