/* The host contract's structs (docs/host-contract.md): what a host fills per hook
 * (halo_sample, halo_line_vertex, halo_line_fragment), read by the module parser (which
 * names a module may need from the host) and by the linker (which emits them). */
#include "internal.h"

#include <string.h>

/* One per hook that runs inside the host. */
const halo_hook_struct halo_hook_structs[] = {
    {HALO_HOOK_SAMPLE,
     "halo_sample",
     "halo_make_sample",
     "s",
     8,
     {{"vec3", "position"},
      {"float", "value"},
      {"vec3", "gradient"},
      {"vec3", "view"},
      {"float", "depth"},
      {"vec2", "fragcoord"},
      {"vec3", "color"},
      {"float", "opacity"}}},
    {HALO_HOOK_LINE_VERTEX,
     "halo_line_vertex",
     "halo_make_line_vertex",
     "v",
     7,
     {{"vec3", "position"},
      {"vec3", "direction"},
      {"vec2", "uv"},
      {"vec3", "eye"},
      {"float", "width"},
      {"vec3", "color"},
      {"float", "opacity"}}},
    {HALO_HOOK_LINE_FRAGMENT,
     "halo_line_fragment",
     "halo_make_line_fragment",
     "f",
     6,
     {{"vec2", "uv"},
      {"float", "depth"},
      {"vec2", "fragcoord"},
      {"vec3", "color"},
      {"float", "opacity"},
      {"vec3", "background"}}},
};
const size_t halo_hook_struct_count = sizeof halo_hook_structs / sizeof halo_hook_structs[0];

int halo_is_host_resource(const char *name)
{
    for (size_t h = 0; h < halo_hook_struct_count; h++)
        for (int i = 0; i < halo_hook_structs[h].field_count; i++)
            if (!strcmp(halo_hook_structs[h].fields[i][1], name))
                return 1;
    return 0;
}
