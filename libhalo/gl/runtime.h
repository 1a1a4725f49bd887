/* What the GL runtime (runtime.c) shares with frames (frame.c) and the feature halo
 * buffer (feature_splat.c): the runtime object, the compile / log helpers that map the
 * driver's messages back to module lines, and the saved bindings. Internal. */
#ifndef HALO_GL_RUNTIME_H
#define HALO_GL_RUNTIME_H

#include "halo.h"
#include "internal.h"
#include "gl/glfuncs.h"

struct halo_gl {
    halo_glfuncs f;    /* entry points the context lacks are NULL (halo_gl_create) */
    int es;            /* 30, 31, 32: OpenGL ES 3.x; 0: desktop OpenGL */
    int readback;      /* halo_gl_desc.readback resolved at creation: the frames' read-back bounds, 1 or 0 */
    int count_fetches; /* halo_gl_desc.count_fetches: the image passes count their texel fetches */
    /* The creator's reference (halo_gl_destroy) and one per frame made with it. */
    _Atomic long refs;
};

/* Counting fetches (halo_gl_desc.count_fetches): the text after an image pass's #version
 * line that makes every texelFetch add one to the atomic counter at binding 0. */
extern const char halo_gl_fetch_counting[];
/* Binds counter (a buffer of one GLuint) at index 0 of GL_ATOMIC_COUNTER_BUFFER, zeroed,
 * keeping what was bound there in saved; _end reads it and puts the bindings back. */
typedef struct halo_gl_fetch_binding {
    GLint buffer, indexed;
    GLint64 start, size;
} halo_gl_fetch_binding;
void halo_gl_fetches_begin(const halo_gl *gl, GLuint counter, halo_gl_fetch_binding *saved);
long long halo_gl_fetches_end(const halo_gl *gl, GLuint counter, const halo_gl_fetch_binding *saved);

/* Reads width x height pixels of the read framebuffer's read buffer as channels floats
 * each (1..4, pack alignment 4); OpenGL ES reads them as RGBA, the one float format it
 * must support, through scratch memory. 0 when that cannot be allocated. */
int halo_gl_read_floats(const halo_gl *gl, int x, int y, int width, int height, int channels, float *out);
/* Does the context have the extension (GL_EXT_float_blend)? */
int halo_gl_has_extension(const halo_gl *gl, const char *name);

/* Compiles one shader; returns its name or 0 after reporting the driver's messages.
 * Lines are mapped through p's line map, or through origins (an image pass). */
GLuint halo_gl_compile_mapped(const halo_glfuncs *f, GLenum type, const char *source, const halo_program *p,
                              const halo_line_origin *origins, int origin_count, const char *file,
                              halo_diagnostics *diag);
/* A program with both shaders attached; 0 (the shaders deleted) when either is 0 or the
 * program cannot be created (reported). */
GLuint halo_gl_program_attach(const halo_glfuncs *f, GLuint vertex, GLuint fragment, const char *file,
                              halo_diagnostics *diag);
/* Links program with the two shaders attached (then detached and deleted); returns it,
 * or 0 after reporting the driver's log at file ("what" when the log says nothing). */
GLuint halo_gl_link_attached(const halo_glfuncs *f, GLuint program, GLuint vertex, GLuint fragment, const char *file,
                             const char *what, halo_diagnostics *diag);
/* The program's info log (caller frees; NULL when out of memory). */
char *halo_gl_program_log(const halo_glfuncs *f, GLuint program);
/* Reports each message of a driver log (log is modified) as a diagnostic of id. */
void halo_gl_report_log(halo_diagnostics *diag, halo_message_id id, char *log, const halo_program *p,
                        const char *source, const char *file);

/* The host's state that libhalo's own draws, clears and read-backs set and give back:
 * bindings, and the switches a host may leave in any position (issue 26: a culled or
 * depth-tested full-screen pass draws nothing): framebuffers, viewport, program, vertex
 * array, active unit, switches, polygon mode, pixel store and pixel buffers. The scissor
 * and per-buffer blending are halo_gl_state's (below). */
typedef struct halo_gl_bindings {
    GLint draw_framebuffer, read_framebuffer, viewport[4], program, vertex_array, active_texture;
    GLboolean switched_on[5];         /* halo_gl_switches: culling ... sRGB (desktop GL) */
    GLint polygon_mode;               /* desktop GL only; 0: not queried */
    GLint pack[10];                   /* pixel store: pack alignment, row length, skip rows,
                                                    * skip pixels; unpack alignment, row length, image
                                                    * height, skip rows, skip pixels, skip images */
    GLint pack_buffer, unpack_buffer; /* the pixel buffer bindings */
} halo_gl_bindings;
void halo_gl_bindings_save(const halo_glfuncs *f, halo_gl_bindings *b);
/* What libhalo's draws need of those switches: no culling, depth or stencil test, no
 * rasterizer discard, no sRGB conversion, filled polygons, tight pixel packing and
 * unpacking (alignment 4), no pixel pack or unpack buffer. */
void halo_gl_bindings_neutral(const halo_glfuncs *f, const halo_gl_bindings *b);
void halo_gl_bindings_restore(const halo_glfuncs *f, const halo_gl_bindings *b);
/* All of the host's state that libhalo's own draws, clears and read-backs depend on or
 * change: the bindings and switches above, the scissor, and each draw buffer's blending
 * (switch, equations, functions) and colour mask. One save, neutral and restore for every
 * runtime entry point (frame.c, field.c, feature_splat.c); the caller saves and restores
 * the texture units it binds. Where the context has one blend state and colour mask for
 * all draw buffers (OpenGL ES 3.0, OpenGL 3.3: no indexed functions, halo_gl_create), one
 * entry holds it. */
#define HALO_GL_STATE_BUFFERS 8
typedef struct halo_gl_buffer_state {
    GLboolean blend, mask[4];
    GLint equation[2], function[4];
} halo_gl_buffer_state;
typedef struct halo_gl_state {
    halo_gl_bindings bindings;
    GLboolean scissor;
    GLint scissor_box[4];
    int buffer_count;
    halo_gl_buffer_state buffers[HALO_GL_STATE_BUFFERS];
} halo_gl_state;
void halo_gl_state_save(const halo_glfuncs *f, halo_gl_state *s);
/* halo_gl_bindings_neutral, and no scissor test, no blending, every colour written. */
void halo_gl_state_neutral(const halo_glfuncs *f, const halo_gl_state *s);
void halo_gl_state_restore(const halo_glfuncs *f, const halo_gl_state *s);
/* Makes the host's saved program current again: a program the host deleted while it was
 * current lives only as long as it stays current, so once libhalo bound its own it is gone;
 * then none (0) is made current instead of raising GL_INVALID_VALUE. */
void halo_gl_use_saved_program(const halo_glfuncs *f, GLint program);

#endif
