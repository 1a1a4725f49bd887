/* Headless OpenGL contexts: OSMesa, optionally EGL surfaceless (see headless.h). */
#include "gl/headless.h"

#include <GL/osmesa.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef HALO_HAVE_EGL
#include <EGL/egl.h>
#include <EGL/eglext.h>
#endif

typedef enum headless_backend { BACKEND_OSMESA, BACKEND_EGL } headless_backend;

struct halo_headless {
    headless_backend backend;
    OSMesaContext osmesa;
    unsigned char *osmesa_buffer; /* OSMesa needs a colour buffer to make a context current */
#ifdef HALO_HAVE_EGL
    EGLDisplay egl_display;
    EGLContext egl_context;
#endif
    char renderer[256];
};

/* The backend get_proc_address resolves against: the context created last. */
static headless_backend current_backend = BACKEND_OSMESA;

static void set_error(char *err, size_t errlen, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void set_error(char *err, size_t errlen, const char *fmt, ...)
{
    if (!err || errlen == 0)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

void *halo_headless_get_proc_address(const char *name)
{
    void *address = NULL;
#ifdef HALO_HAVE_EGL
    if (current_backend == BACKEND_EGL) {
        __eglMustCastToProperFunctionPointerType proc = eglGetProcAddress(name);
        memcpy(&address, &proc, sizeof address);
        return address;
    }
#endif
    OSMESAproc proc = OSMesaGetProcAddress(name);
    memcpy(&address, &proc, sizeof address); /* function and object pointers share a representation (POSIX) */
    return address;
}

static int create_osmesa(halo_headless *h, int width, int height, char *err, size_t errlen)
{
    static const int versions[][2] = {{4, 5}, {3, 3}};
    h->osmesa_buffer = malloc((size_t)width * (size_t)height * 4);
    if (!h->osmesa_buffer) {
        set_error(err, errlen, "out of memory");
        return 0;
    }
    for (size_t i = 0; i < sizeof versions / sizeof versions[0]; ++i) {
        const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                                  OSMESA_STENCIL_BITS, 8, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                                  OSMESA_CONTEXT_MAJOR_VERSION, versions[i][0],
                                  OSMESA_CONTEXT_MINOR_VERSION, versions[i][1], 0};
        h->osmesa = OSMesaCreateContextAttribs(attributes, NULL);
        if (h->osmesa)
            break;
    }
    if (!h->osmesa) {
        set_error(err, errlen, "OSMesa could not create an OpenGL 4.5 or 3.3 core context");
        return 0;
    }
    if (!OSMesaMakeCurrent(h->osmesa, h->osmesa_buffer, GL_UNSIGNED_BYTE, width, height)) {
        set_error(err, errlen, "OSMesaMakeCurrent failed");
        return 0;
    }
    h->backend = BACKEND_OSMESA;
    return 1;
}

static void destroy_osmesa(halo_headless *h)
{
    if (h->osmesa) {
        OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
        OSMesaDestroyContext(h->osmesa);
        h->osmesa = NULL;
    }
    free(h->osmesa_buffer);
    h->osmesa_buffer = NULL;
}

#ifdef HALO_HAVE_EGL
static int create_egl(halo_headless *h, char *err, size_t errlen)
{
    static const int versions[][2] = {{4, 5}, {3, 3}};
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display = NULL;
    __eglMustCastToProperFunctionPointerType proc = eglGetProcAddress("eglGetPlatformDisplayEXT");
    memcpy(&get_platform_display, &proc, sizeof get_platform_display);
    if (!get_platform_display) {
        set_error(err, errlen, "EGL has no eglGetPlatformDisplayEXT");
        return 0;
    }
    h->egl_display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    if (h->egl_display == EGL_NO_DISPLAY || !eglInitialize(h->egl_display, NULL, NULL)) {
        h->egl_display = EGL_NO_DISPLAY;
        set_error(err, errlen, "EGL surfaceless display unavailable");
        return 0;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        set_error(err, errlen, "EGL cannot bind the OpenGL API");
        return 0;
    }
    const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
                                        EGL_NONE};
    EGLConfig config;
    EGLint config_count = 0;
    if (!eglChooseConfig(h->egl_display, config_attributes, &config, 1, &config_count) || config_count < 1) {
        set_error(err, errlen, "EGL has no OpenGL config");
        return 0;
    }
    for (size_t i = 0; i < sizeof versions / sizeof versions[0] && !h->egl_context; ++i) {
        const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, versions[i][0], EGL_CONTEXT_MINOR_VERSION,
                                             versions[i][1], EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                             EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
        EGLContext context = eglCreateContext(h->egl_display, config, EGL_NO_CONTEXT, context_attributes);
        if (context != EGL_NO_CONTEXT)
            h->egl_context = context;
    }
    if (!h->egl_context) {
        set_error(err, errlen, "EGL could not create an OpenGL 4.5 or 3.3 core context");
        return 0;
    }
    if (!eglMakeCurrent(h->egl_display, EGL_NO_SURFACE, EGL_NO_SURFACE, h->egl_context)) {
        set_error(err, errlen, "eglMakeCurrent without a surface failed");
        return 0;
    }
    h->backend = BACKEND_EGL;
    return 1;
}

static void destroy_egl(halo_headless *h)
{
    if (h->egl_display != EGL_NO_DISPLAY) {
        eglMakeCurrent(h->egl_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (h->egl_context)
            eglDestroyContext(h->egl_display, h->egl_context);
        eglTerminate(h->egl_display);
    }
    h->egl_display = EGL_NO_DISPLAY;
    h->egl_context = NULL;
}
#endif

static void query_renderer(halo_headless *h)
{
    typedef const GLubyte *(*get_string_fn)(GLenum);
    get_string_fn get_string = NULL;
    void *address = halo_headless_get_proc_address("glGetString");
    memcpy(&get_string, &address, sizeof get_string);
    const char *renderer = get_string ? (const char *)get_string(GL_RENDERER) : NULL;
    snprintf(h->renderer, sizeof h->renderer, "%s", renderer ? renderer : "unknown");
}

halo_headless *halo_headless_create(int width, int height, char *err, size_t errlen)
{
    if (width < 1 || height < 1 || width > 16384 || height > 16384) {
        set_error(err, errlen, "invalid context size %dx%d", width, height);
        return NULL;
    }
    halo_headless *h = calloc(1, sizeof *h);
    if (!h) {
        set_error(err, errlen, "out of memory");
        return NULL;
    }
    const char *choice = getenv("HALO_HEADLESS");
    int egl_first = choice && strcmp(choice, "egl") == 0;
    int osmesa_only = choice && strcmp(choice, "osmesa") == 0;
    char osmesa_error[256] = "", egl_error[256] = "not built with EGL";
    int ok = 0;
#ifdef HALO_HAVE_EGL
    h->egl_display = EGL_NO_DISPLAY;
    if (egl_first) {
        ok = create_egl(h, egl_error, sizeof egl_error);
        if (!ok)
            destroy_egl(h);
    }
#else
    (void)egl_first;
#endif
    if (!ok) {
        ok = create_osmesa(h, width, height, osmesa_error, sizeof osmesa_error);
        if (!ok)
            destroy_osmesa(h);
    }
#ifdef HALO_HAVE_EGL
    if (!ok && !egl_first && !osmesa_only) {
        ok = create_egl(h, egl_error, sizeof egl_error);
        if (!ok)
            destroy_egl(h);
    }
#else
    (void)osmesa_only;
#endif
    if (!ok) {
        set_error(err, errlen, "no headless OpenGL context: OSMesa: %s; EGL: %s",
                  osmesa_error[0] ? osmesa_error : "not tried", egl_error);
        free(h);
        return NULL;
    }
    current_backend = h->backend;
    query_renderer(h);
    return h;
}

void halo_headless_destroy(halo_headless *h)
{
    if (!h)
        return;
    if (h->backend == BACKEND_OSMESA)
        destroy_osmesa(h);
#ifdef HALO_HAVE_EGL
    else
        destroy_egl(h);
#endif
    free(h);
}

const char *halo_headless_renderer(halo_headless *h)
{
    return h ? h->renderer : "";
}

const char *halo_headless_backend(halo_headless *h)
{
    return h && h->backend == BACKEND_EGL ? "egl" : "osmesa";
}
