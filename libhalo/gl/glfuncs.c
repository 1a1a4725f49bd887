/* Loading the OpenGL entry point table (halo_gl_loader.h). */
#include "gl/glfuncs.h"

#include <string.h>

int halo_glfuncs_load(halo_glfuncs *f, size_t size, void *(*get_proc_address)(const char *name),
                      const char **missing_name)
{
    int complete = 1;
    if (missing_name)
        *missing_name = NULL;
    if (!f) {
        if (missing_name)
            *missing_name = "f";
        return 0;
    }
    if (size != sizeof *f) { /* a table of another libhalo's header: not written */
        if (missing_name)
            *missing_name = "size (the halo_glfuncs of another libhalo version's header)";
        return 0;
    }
    memset(f, 0, sizeof *f);
    if (!get_proc_address) {
        if (missing_name)
            *missing_name = "get_proc_address";
        return 0;
    }
    /* Object pointers and function pointers share a representation on every platform
     * OpenGL runs on (POSIX requires it for dlsym); memcpy keeps ISO C quiet. */
#define HALO_X_GLFUNC_LOAD(type, name)                  \
    {                                                   \
        void *address = get_proc_address("gl" #name);   \
        if (address) {                                  \
            memcpy(&f->name, &address, sizeof f->name); \
        } else {                                        \
            if (complete && missing_name)               \
                *missing_name = "gl" #name;             \
            complete = 0;                               \
        }                                               \
    }
    HALO_GL_FUNCTIONS(HALO_X_GLFUNC_LOAD)
#undef HALO_X_GLFUNC_LOAD
#define HALO_X_GLFUNC_LOAD_OPTIONAL(type, name)         \
    {                                                   \
        void *address = get_proc_address("gl" #name);   \
        if (address)                                    \
            memcpy(&f->name, &address, sizeof f->name); \
    }
    HALO_GL_FUNCTIONS_OPTIONAL(HALO_X_GLFUNC_LOAD_OPTIONAL)
#undef HALO_X_GLFUNC_LOAD_OPTIONAL
    return complete;
}
