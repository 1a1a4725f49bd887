/* Headless OpenGL contexts: EGL and OSMesa, each when built (see headless.h). */
#include "gl/headless.h"

#include "halo_gl_loader.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if !defined HALO_HAVE_EGL && !defined HALO_HAVE_OSMESA
#error "libhalo-headless needs EGL (HALO_HAVE_EGL) or OSMesa (HALO_HAVE_OSMESA)"
#endif

#ifdef HALO_HAVE_OSMESA
#include <GL/osmesa.h>
#endif
#ifdef HALO_HAVE_EGL
#include <EGL/egl.h>
#include <EGL/eglext.h>
#endif

typedef enum headless_backend { BACKEND_OSMESA, BACKEND_EGL } headless_backend;

struct halo_headless {
    headless_backend backend;
#ifdef HALO_HAVE_OSMESA
    OSMesaContext osmesa;
    unsigned char *osmesa_buffer; /* OSMesa needs a colour buffer to make a context current */
#endif
#ifdef HALO_HAVE_EGL
    EGLDisplay egl_display;
    EGLContext egl_context;
#endif
    int es; /* 30, 32: an OpenGL ES context */
    char renderer[256];
};

/* The backend get_proc_address resolves against: the context created last. */
#ifdef HALO_HAVE_OSMESA
static headless_backend current_backend = BACKEND_OSMESA;
#else
static headless_backend current_backend = BACKEND_EGL;
#endif

/* The process's choice: --backend (halo_headless_backend_option), else HALO_HEADLESS. */
static halo_headless_choice process_choice = HALO_HEADLESS_AUTO;
static int process_choice_set;

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

/* ---- The choice ----------------------------------------------------------------------- */

const char *halo_headless_built_backends(void)
{
#if defined HALO_HAVE_EGL && defined HALO_HAVE_OSMESA
    return "egl, osmesa";
#elif defined HALO_HAVE_EGL
    return "egl";
#else
    return "osmesa";
#endif
}

int halo_headless_parse_choice(const char *text, halo_headless_choice *choice)
{
    if (!text)
        return 0;
    if (!strcmp(text, "auto"))
        *choice = HALO_HEADLESS_AUTO;
    else if (!strcmp(text, "egl"))
        *choice = HALO_HEADLESS_EGL;
    else if (!strcmp(text, "osmesa"))
        *choice = HALO_HEADLESS_OSMESA;
    else if (!strcmp(text, "egl-es3.0"))
        *choice = HALO_HEADLESS_EGL_ES30;
    else if (!strcmp(text, "egl-es3.2"))
        *choice = HALO_HEADLESS_EGL_ES32;
    else
        return 0;
    return 1;
}

/* 1 when this build has the chosen backend (auto: always). */
static int choice_built(halo_headless_choice choice)
{
    int egl = 0, osmesa = 0;
#ifdef HALO_HAVE_EGL
    egl = 1;
#endif
#ifdef HALO_HAVE_OSMESA
    osmesa = 1;
#endif
    return choice == HALO_HEADLESS_OSMESA ? osmesa : choice == HALO_HEADLESS_AUTO ? 1 : egl;
}

/* Whether the tool draws on OpenGL ES (halo_headless_allow_es). */
static int es_allowed;

void halo_headless_allow_es(int allowed) { es_allowed = allowed != 0; }

static int check_choice(const char *where, const char *text, halo_headless_choice *choice, char *err, size_t errlen)
{
    if (!halo_headless_parse_choice(text, choice)) {
        set_error(err, errlen, "%s: '%s' is not egl, osmesa, auto, egl-es3.0 or egl-es3.2", where, text);
        return 0;
    }
    if (!es_allowed && (*choice == HALO_HEADLESS_EGL_ES30 || *choice == HALO_HEADLESS_EGL_ES32)) {
        set_error(err, errlen,
                  "%s: '%s': this tool draws with desktop OpenGL only (on OpenGL ES: halo-render, halo-validate "
                  "conform)",
                  where, text);
        return 0;
    }
    if (!choice_built(*choice)) {
        set_error(err, errlen, "%s: this build has no %s backend (built: %s)", where, text,
                  halo_headless_built_backends());
        return 0;
    }
    return 1;
}

int halo_headless_backend_option(int *argc, char **argv, char *err, size_t errlen)
{
    int kept = 0;
    for (int i = 0; i < *argc; ++i) {
        const char *a = argv[i];
        const char *value = NULL;
        if (!strcmp(a, "--backend")) {
            if (i + 1 >= *argc) {
                set_error(err, errlen, "--backend needs a value (egl, osmesa, auto, egl-es3.0 or egl-es3.2)");
                return 0;
            }
            value = argv[++i];
        } else if (!strncmp(a, "--backend=", 10)) {
            value = a + 10;
        } else {
            argv[kept++] = argv[i];
            continue;
        }
        if (!check_choice("--backend", value, &process_choice, err, errlen))
            return 0;
        process_choice_set = 1;
    }
    for (int i = kept; i < *argc; ++i)
        argv[i] = NULL;
    *argc = kept;
    return 1;
}

int halo_headless_take_backend_option(int *argc, char **argv, const char *program)
{
    char err[160];
    if (halo_headless_backend_option(argc, argv, err, sizeof err))
        return 1;
    fprintf(stderr, "%s: error: %s\n", program, err);
    return 0;
}

/* ---- Both backends -------------------------------------------------------------------- */

void *halo_headless_get_proc_address(const char *name)
{
    void *address = NULL;
#ifdef HALO_HAVE_EGL
    if (current_backend == BACKEND_EGL) {
        __eglMustCastToProperFunctionPointerType proc = eglGetProcAddress(name);
        memcpy(&address, &proc, sizeof address); /* function and object pointers share a representation (POSIX) */
        return address;
    }
#endif
#ifdef HALO_HAVE_OSMESA
    OSMESAproc proc = OSMesaGetProcAddress(name);
    memcpy(&address, &proc, sizeof address);
#else
    (void)name;
#endif
    return address;
}

/* The tools' table, loaded again for each backend the process switches to. */
const halo_glfuncs *halo_headless_functions(void)
{
    static halo_glfuncs table;
    static int loaded_for = -1;
    if (loaded_for != (int)current_backend) {
        if (!halo_glfuncs_load(&table, sizeof table, halo_headless_get_proc_address, NULL))
            return NULL;
        loaded_for = (int)current_backend;
    }
    return &table;
}

/* GL_RENDERER of the current context, through the current backend. */
static void query_renderer(halo_headless *h)
{
    enum { RENDERER = 0x1F01 }; /* GL_RENDERER */
    typedef const unsigned char *(*get_string_fn)(unsigned int);
    get_string_fn get_string = NULL;
    void *address = halo_headless_get_proc_address("glGetString");
    memcpy(&get_string, &address, sizeof get_string);
    const char *renderer = get_string ? (const char *)get_string(RENDERER) : NULL;
    snprintf(h->renderer, sizeof h->renderer, "%s", renderer ? renderer : "unknown");
}

/* ---- OSMesa ----------------------------------------------------------------------------- */

#ifdef HALO_HAVE_OSMESA
static int create_osmesa(halo_headless *h, int width, int height, char *err, size_t errlen)
{
    static const int versions[][2] = {{4, 5}, {3, 3}};
    h->osmesa_buffer = malloc((size_t)width * (size_t)height * 4);
    if (!h->osmesa_buffer) {
        set_error(err, errlen, "out of memory");
        return 0;
    }
    for (size_t i = 0; i < sizeof versions / sizeof versions[0]; ++i) {
        const int attributes[] = {OSMESA_FORMAT,
                                  OSMESA_RGBA,
                                  OSMESA_DEPTH_BITS,
                                  24,
                                  OSMESA_STENCIL_BITS,
                                  8,
                                  OSMESA_PROFILE,
                                  OSMESA_CORE_PROFILE,
                                  OSMESA_CONTEXT_MAJOR_VERSION,
                                  versions[i][0],
                                  OSMESA_CONTEXT_MINOR_VERSION,
                                  versions[i][1],
                                  0};
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
#endif

/* ---- EGL -------------------------------------------------------------------------------- */

#ifdef HALO_HAVE_EGL
/* A software rasterizer by its GL_RENDERER: Mesa's llvmpipe and softpipe, and the
 * names other software drivers give. */
static int renderer_is_software(const char *renderer)
{
    static const char *const software[] = {"llvmpipe", "softpipe", "swrast", "Software Rasterizer", "SwiftShader"};
    for (size_t i = 0; i < sizeof software / sizeof software[0]; ++i)
        if (strstr(renderer, software[i]))
            return 1;
    return 0;
}

/* Mesa names the driver of a display (EGL_MESA_query_driver) before any context
 * exists: "swrast" is llvmpipe or softpipe. 0 when unknown. */
static int display_is_software(EGLDisplay display)
{
    const char *extensions = eglQueryString(display, EGL_EXTENSIONS);
    if (!extensions || !strstr(extensions, "EGL_MESA_query_driver"))
        return 0;
    typedef const char *(*driver_name_fn)(EGLDisplay);
    driver_name_fn driver_name = NULL;
    __eglMustCastToProperFunctionPointerType proc = eglGetProcAddress("eglGetDisplayDriverName");
    memcpy(&driver_name, &proc, sizeof driver_name);
    const char *name = driver_name ? driver_name(display) : NULL;
    return name && strstr(name, "swrast") != NULL;
}

static void destroy_egl(halo_headless *h)
{
    if (h->egl_display != EGL_NO_DISPLAY) {
        eglMakeCurrent(h->egl_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (h->egl_context != EGL_NO_CONTEXT)
            eglDestroyContext(h->egl_display, h->egl_context);
        eglTerminate(h->egl_display);
    }
    h->egl_display = EGL_NO_DISPLAY;
    h->egl_context = EGL_NO_CONTEXT;
}

/* An OpenGL 4.5 (else 3.3) core context on an initialized display, or (h->es) an OpenGL
 * ES 3.0 or 3.2 one, made current without a surface. */
static int create_egl_context(halo_headless *h, char *err, size_t errlen)
{
    static const int versions[][2] = {{4, 5}, {3, 3}};
    const char *api = h->es ? "OpenGL ES" : "OpenGL";
    if (!eglBindAPI(h->es ? EGL_OPENGL_ES_API : EGL_OPENGL_API)) {
        set_error(err, errlen, "EGL cannot bind the %s API", api);
        return 0;
    }
    const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, h->es ? EGL_OPENGL_ES3_BIT : EGL_OPENGL_BIT,
                                        EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_NONE};
    EGLConfig config;
    EGLint config_count = 0;
    if (!eglChooseConfig(h->egl_display, config_attributes, &config, 1, &config_count) || config_count < 1) {
        set_error(err, errlen, "EGL has no %s%s config", api, h->es ? " 3" : "");
        return 0;
    }
    if (h->es) {
        const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, h->es % 10,
                                             EGL_NONE};
        h->egl_context = eglCreateContext(h->egl_display, config, EGL_NO_CONTEXT, context_attributes);
    }
    for (size_t i = 0; i < sizeof versions / sizeof versions[0] && h->egl_context == EGL_NO_CONTEXT && !h->es; ++i) {
        const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                             versions[i][0],
                                             EGL_CONTEXT_MINOR_VERSION,
                                             versions[i][1],
                                             EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                             EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                             EGL_NONE};
        h->egl_context = eglCreateContext(h->egl_display, config, EGL_NO_CONTEXT, context_attributes);
    }
    if (h->egl_context == EGL_NO_CONTEXT) {
        if (h->es)
            set_error(err, errlen, "EGL could not create an OpenGL ES 3.%d context", h->es % 10);
        else
            set_error(err, errlen, "EGL could not create an OpenGL 4.5 or 3.3 core context");
        return 0;
    }
    if (!eglMakeCurrent(h->egl_display, EGL_NO_SURFACE, EGL_NO_SURFACE, h->egl_context)) {
        set_error(err, errlen, "eglMakeCurrent without a surface failed");
        return 0;
    }
    return 1;
}

/* Tries one display: a context, its renderer, and (hardware_only) a hardware one.
 * Leaves h without an EGL display when it fails. */
static int try_egl_display(halo_headless *h, EGLDisplay display, int hardware_only, const char *what, char *err,
                           size_t errlen)
{
    h->egl_display = display;
    if (display == EGL_NO_DISPLAY || !eglInitialize(display, NULL, NULL)) {
        h->egl_display = EGL_NO_DISPLAY;
        set_error(err, errlen, "%s: no display", what);
        return 0;
    }
    if (hardware_only && display_is_software(display)) {
        set_error(err, errlen, "%s: software renderer only", what);
        destroy_egl(h);
        return 0;
    }
    if (!create_egl_context(h, err, errlen)) {
        destroy_egl(h);
        return 0;
    }
    h->backend = current_backend = BACKEND_EGL;
    query_renderer(h);
    if (hardware_only && renderer_is_software(h->renderer)) {
        set_error(err, errlen, "%s: software renderer only (%s)", what, h->renderer);
        destroy_egl(h);
        return 0;
    }
    return 1;
}

/* Mesa's software device (llvmpipe) says so in its extensions: no display needed. */
static int device_is_software(EGLDeviceEXT device)
{
    PFNEGLQUERYDEVICESTRINGEXTPROC query_string = NULL;
    __eglMustCastToProperFunctionPointerType proc = eglGetProcAddress("eglQueryDeviceStringEXT");
    memcpy(&query_string, &proc, sizeof query_string);
    const char *extensions = query_string ? query_string(device, EGL_EXTENSIONS) : NULL;
    return extensions && strstr(extensions, "EGL_MESA_device_software") != NULL;
}

/* EGL: the surfaceless platform (Mesa), then each device of EGL_EXT_platform_device
 * (NVIDIA's headless route). hardware_only (auto's first try): the devices only,
 * skipping software ones before initializing a display (Mesa 22.3 leaks a little at
 * every eglInitialize/eglTerminate, which LeakSanitizer reports after the driver is
 * unloaded, where no suppression can name it). */
static int create_egl(halo_headless *h, int hardware_only, char *err, size_t errlen)
{
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display = NULL;
    __eglMustCastToProperFunctionPointerType proc = eglGetProcAddress("eglGetPlatformDisplayEXT");
    memcpy(&get_platform_display, &proc, sizeof get_platform_display);
    if (!get_platform_display) {
        set_error(err, errlen, "EGL has no eglGetPlatformDisplayEXT");
        return 0;
    }
    const char *client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!hardware_only && client_extensions && strstr(client_extensions, "EGL_MESA_platform_surfaceless") &&
        try_egl_display(h, get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL),
                        hardware_only, "surfaceless", err, errlen))
        return 1;
    PFNEGLQUERYDEVICESEXTPROC query_devices = NULL;
    proc = eglGetProcAddress("eglQueryDevicesEXT");
    memcpy(&query_devices, &proc, sizeof query_devices);
    EGLDeviceEXT devices[16];
    EGLint device_count = 0;
    if (!client_extensions || !strstr(client_extensions, "EGL_EXT_platform_device") || !query_devices ||
        !query_devices(16, devices, &device_count))
        device_count = 0;
    for (EGLint i = 0; i < device_count; ++i) {
        char what[32];
        snprintf(what, sizeof what, "device %d", (int)i);
        if (hardware_only && device_is_software(devices[i])) {
            set_error(err, errlen, "%s: software renderer only", what);
            continue;
        }
        if (try_egl_display(h, get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], NULL), hardware_only, what,
                            err, errlen))
            return 1;
    }
    if (device_count == 0 &&
        (hardware_only || !client_extensions || !strstr(client_extensions, "EGL_MESA_platform_surfaceless")))
        set_error(err, errlen, hardware_only ? "no device" : "neither the surfaceless platform nor a device");
    return 0;
}
#endif

/* ---- Creating ----------------------------------------------------------------------------- */

/* The choice of --backend, else of HALO_HEADLESS, else auto. */
static int effective_choice(halo_headless_choice *choice, char *err, size_t errlen)
{
    const char *environment = getenv("HALO_HEADLESS");
    if (process_choice_set || !environment || !environment[0]) {
        *choice = process_choice;
        return 1;
    }
    return check_choice("HALO_HEADLESS", environment, choice, err, errlen);
}

int halo_headless_choice_es(void)
{
    halo_headless_choice choice;
    if (!effective_choice(&choice, NULL, 0))
        return 0;
    return choice == HALO_HEADLESS_EGL_ES30 ? 30 : choice == HALO_HEADLESS_EGL_ES32 ? 32 : 0;
}

halo_headless *halo_headless_create(int width, int height, char *err, size_t errlen)
{
    if (width < 1 || height < 1 || width > 16384 || height > 16384) {
        set_error(err, errlen, "no headless OpenGL context: invalid context size %dx%d", width, height);
        return NULL;
    }
    halo_headless_choice choice;
    char choice_error[160];
    if (!effective_choice(&choice, choice_error, sizeof choice_error)) {
        set_error(err, errlen, "no headless OpenGL context: %s", choice_error);
        return NULL;
    }
    halo_headless *h = calloc(1, sizeof *h);
    if (!h) {
        set_error(err, errlen, "no headless OpenGL context: out of memory");
        return NULL;
    }
    char osmesa_error[256] = "not built with OSMesa", egl_error[256] = "not built with EGL";
    int ok = 0;
#ifdef HALO_HAVE_EGL
    h->egl_display = EGL_NO_DISPLAY;
    h->egl_context = EGL_NO_CONTEXT;
    h->es = choice == HALO_HEADLESS_EGL_ES30 ? 30 : choice == HALO_HEADLESS_EGL_ES32 ? 32 : 0;
    if (h->es == 30)
        /* Mesa gives an ES 3.2 context for 3.0 (EGL allows a compatible later version), which
         * would hide what ES 3.0 lacks; this makes it report 3.0, as WebGL 2's contexts do
         * (the runtime then leaves out what 3.2 added). Read when the display is initialized;
         * the tools are single-threaded here. */
        setenv("MESA_GLES_VERSION_OVERRIDE", "3.0", 0);
    /* auto: a GPU first (a hardware renderer), then OSMesa, then EGL's software renderer */
    if (choice != HALO_HEADLESS_OSMESA)
        ok = create_egl(h, choice == HALO_HEADLESS_AUTO, egl_error, sizeof egl_error);
#endif
#ifdef HALO_HAVE_OSMESA
    if (!ok && (choice == HALO_HEADLESS_AUTO || choice == HALO_HEADLESS_OSMESA)) {
        ok = create_osmesa(h, width, height, osmesa_error, sizeof osmesa_error);
        if (ok) {
            current_backend = BACKEND_OSMESA;
            query_renderer(h);
        } else {
            destroy_osmesa(h);
        }
    }
#endif
#ifdef HALO_HAVE_EGL
    if (!ok && choice == HALO_HEADLESS_AUTO)
        ok = create_egl(h, 0, egl_error, sizeof egl_error);
#endif
    if (!ok) {
        if (choice != HALO_HEADLESS_AUTO && choice != HALO_HEADLESS_OSMESA)
            set_error(err, errlen, "no headless OpenGL context: EGL: %s", egl_error);
        else if (choice == HALO_HEADLESS_OSMESA)
            set_error(err, errlen, "no headless OpenGL context: OSMesa: %s", osmesa_error);
        else
            set_error(err, errlen, "no headless OpenGL context: EGL: %s; OSMesa: %s", egl_error, osmesa_error);
        free(h);
        return NULL;
    }
    return h;
}

void halo_headless_destroy(halo_headless *h)
{
    if (!h)
        return;
#ifdef HALO_HAVE_OSMESA
    if (h->backend == BACKEND_OSMESA)
        destroy_osmesa(h);
#endif
#ifdef HALO_HAVE_EGL
    if (h->backend == BACKEND_EGL)
        destroy_egl(h);
#endif
    free(h);
}

int halo_headless_es(const halo_headless *h) { return h ? h->es : 0; }

const char *halo_headless_renderer(halo_headless *h) { return h ? h->renderer : ""; }

const char *halo_headless_backend(halo_headless *h) { return h && h->backend == BACKEND_EGL ? "egl" : "osmesa"; }
