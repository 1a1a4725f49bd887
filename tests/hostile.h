/* A host that leaves hostile GL state around libhalo's runtime calls (issue 26), for the
 * tests that require libhalo to set all it needs and give all it touched back
 * (tests/libhalo/gl/test_segments.c: halo_gl_frame_draw; tests/examples/hosts/test_host_state.c:
 * the slice host's frame calls, the feature buffer, OpenGL ES contexts).
 *   hostile_set    every switch that would make a full-screen pass draw nothing or
 *                  something else, odd packing, bindings and per-buffer blending;
 *   hostile_check  names each piece of that state which is no longer so;
 *   hostile_unset  GL's default packing and draw-buffer state again (what the example
 *                  hosts, which set only what their draws need, take for granted).
 * On OpenGL ES (es != 0) the desktop-only state (polygon mode, sRGB switch) is left
 * alone, and without per-buffer functions (ES 3.0) the buffers share one state. */
#ifndef HALO_TEST_HOSTILE_H
#define HALO_TEST_HOSTILE_H

#include "halo.h"
#include "gl/glfuncs.h"
#include "gl/headless.h"

#include <stdio.h>
#include <string.h>

typedef struct hostile {
    const halo_glfuncs *f;
    int es;              /* 30 or 32 on OpenGL ES (halo_headless_es), else 0 */
    GLuint vertex_array; /* the host's odd binding */
    int checks, mismatches;
} hostile;

typedef void (*hostile_stencil_func_proc)(GLenum, GLint, GLuint);
typedef void (*hostile_cull_face_proc)(GLenum);

static inline int hostile_indexed(const halo_glfuncs *f)
{
    return f->Disablei && f->Enablei && f->IsEnabledi && f->BlendFuncSeparatei && f->BlendEquationSeparatei &&
           f->ColorMaski && f->GetIntegeri_v && f->GetBooleani_v;
}

static inline void hostile_set(hostile *h)
{
    const halo_glfuncs *f = h->f;
    hostile_stencil_func_proc stencil_func = NULL;
    void *address = halo_headless_get_proc_address("glStencilFunc");
    memcpy(&stencil_func, &address, sizeof stencil_func);
    hostile_cull_face_proc cull_face = NULL;
    address = halo_headless_get_proc_address("glCullFace");
    memcpy(&cull_face, &address, sizeof cull_face);
    if (!h->vertex_array)
        f->GenVertexArrays(1, &h->vertex_array);
    f->Enable(GL_CULL_FACE);
    if (cull_face)
        cull_face(GL_FRONT_AND_BACK);
    f->Enable(GL_DEPTH_TEST);
    f->DepthFunc(GL_NEVER);
    f->DepthMask(GL_FALSE);
    f->Enable(GL_STENCIL_TEST);
    if (stencil_func)
        stencil_func(GL_NEVER, 1, 0xFF);
    f->Enable(GL_BLEND);
    f->BlendFunc(GL_ZERO, GL_ZERO);
    f->BlendEquation(GL_FUNC_REVERSE_SUBTRACT);
    f->Enable(GL_SCISSOR_TEST);
    f->Scissor(0, 0, 1, 1);
    f->ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    if (f->PolygonMode && !h->es)
        f->PolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    f->Enable(GL_RASTERIZER_DISCARD);
    if (!h->es)
        f->Enable(GL_FRAMEBUFFER_SRGB);
    f->PixelStorei(GL_PACK_ALIGNMENT, 8);
    f->PixelStorei(GL_PACK_ROW_LENGTH, 3);
    f->PixelStorei(GL_UNPACK_ALIGNMENT, 2);
    f->PixelStorei(GL_UNPACK_ROW_LENGTH, 5);
    /* draw buffers 1..3 (where libhalo's outputs go) each in a state of their own: blending
     * off on 1, odd functions and equations on 2 and 3, odd masks */
    if (hostile_indexed(f))
        for (GLuint k = 1; k <= 3; ++k) {
            (k == 1 ? f->Disablei : f->Enablei)(GL_BLEND, k);
            f->BlendFuncSeparatei(k, GL_DST_COLOR, GL_SRC_ALPHA, GL_ONE_MINUS_DST_ALPHA, GL_CONSTANT_COLOR);
            f->BlendEquationSeparatei(k, k == 2 ? GL_MIN : GL_FUNC_SUBTRACT, GL_MAX);
            f->ColorMaski(k, k == 3, GL_TRUE, GL_FALSE, k == 2);
        }
    f->Viewport(0, 0, 1, 1);
    f->ActiveTexture(GL_TEXTURE7);
    f->BindVertexArray(h->vertex_array);
    f->UseProgram(0);
}

static inline void hostile_unset(hostile *h)
{
    const halo_glfuncs *f = h->f;
    f->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    f->PixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    f->PixelStorei(GL_PACK_ALIGNMENT, 4);
    f->PixelStorei(GL_PACK_ROW_LENGTH, 0);
    for (GLuint k = 1; k <= 3 && hostile_indexed(f); ++k) {
        f->Disablei(GL_BLEND, k);
        f->BlendFuncSeparatei(k, GL_ONE, GL_ZERO, GL_ONE, GL_ZERO);
        f->BlendEquationSeparatei(k, GL_FUNC_ADD, GL_FUNC_ADD);
        f->ColorMaski(k, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    }
}

/* Is the state still what hostile_set left? Prints what is not (prefixed by `what`); with
 * bindings 0 (before a host's draw, for which libhalo binds its program and textures and
 * sets its outputs' blending), only the switches, masks and packing. */
static inline void hostile_check(hostile *h, int bindings, const char *what)
{
    const halo_glfuncs *f = h->f;
    struct {
        const char *name;
        GLenum cap;
    } caps[] = {{"GL_CULL_FACE", GL_CULL_FACE},
                {"GL_DEPTH_TEST", GL_DEPTH_TEST},
                {"GL_STENCIL_TEST", GL_STENCIL_TEST},
                {"GL_BLEND", GL_BLEND},
                {"GL_SCISSOR_TEST", GL_SCISSOR_TEST},
                {"GL_RASTERIZER_DISCARD", GL_RASTERIZER_DISCARD},
                {"GL_FRAMEBUFFER_SRGB", GL_FRAMEBUFFER_SRGB}};
    h->checks++;
    for (size_t i = 0; i < sizeof caps / sizeof caps[0]; ++i)
        if (!(h->es && caps[i].cap == GL_FRAMEBUFFER_SRGB) && !f->IsEnabled(caps[i].cap)) {
            printf("  %s: %s was switched off\n", what, caps[i].name);
            h->mismatches++;
        }
    struct {
        const char *name;
        GLenum query;
        GLint expected;
    } values[] = {{"GL_CULL_FACE_MODE", GL_CULL_FACE_MODE, GL_FRONT_AND_BACK},
                  {"GL_DEPTH_FUNC", GL_DEPTH_FUNC, GL_NEVER},
                  {"GL_STENCIL_FUNC", GL_STENCIL_FUNC, GL_NEVER},
                  {"GL_BLEND_SRC_RGB", GL_BLEND_SRC_RGB, GL_ZERO},
                  {"GL_BLEND_DST_ALPHA", GL_BLEND_DST_ALPHA, GL_ZERO},
                  {"GL_BLEND_EQUATION_RGB", GL_BLEND_EQUATION_RGB, GL_FUNC_REVERSE_SUBTRACT},
                  {"GL_BLEND_EQUATION_ALPHA", GL_BLEND_EQUATION_ALPHA, GL_FUNC_REVERSE_SUBTRACT},
                  {"GL_PACK_ALIGNMENT", GL_PACK_ALIGNMENT, 8},
                  {"GL_PACK_ROW_LENGTH", GL_PACK_ROW_LENGTH, 3},
                  {"GL_UNPACK_ALIGNMENT", GL_UNPACK_ALIGNMENT, 2},
                  {"GL_UNPACK_ROW_LENGTH", GL_UNPACK_ROW_LENGTH, 5},
                  {"GL_ACTIVE_TEXTURE", GL_ACTIVE_TEXTURE, GL_TEXTURE7},
                  {"GL_VERTEX_ARRAY_BINDING", GL_VERTEX_ARRAY_BINDING, (GLint)h->vertex_array},
                  {"GL_CURRENT_PROGRAM", GL_CURRENT_PROGRAM, 0},
                  {"GL_POLYGON_MODE", GL_POLYGON_MODE, GL_LINE}};
    for (size_t i = 0; i < sizeof values / sizeof values[0]; ++i) {
        if (!bindings && (values[i].query == GL_ACTIVE_TEXTURE || values[i].query == GL_VERTEX_ARRAY_BINDING ||
                          values[i].query == GL_CURRENT_PROGRAM))
            continue;
        if (h->es && values[i].query == GL_POLYGON_MODE)
            continue;
        GLint v[4] = {0, 0, 0, 0};
        f->GetIntegerv(values[i].query, v);
        if (v[0] != values[i].expected) {
            printf("  %s: %s is 0x%x, the host left 0x%x\n", what, values[i].name, (unsigned)v[0],
                   (unsigned)values[i].expected);
            h->mismatches++;
        }
    }
    /* draw buffers 1..3: libhalo sets its outputs' blending there for the host's draws, and
     * gives the host's back when its call returns */
    for (GLuint k = 1; k <= 3 && bindings && hostile_indexed(f); ++k) {
        GLint src_rgb = 0, dst_alpha = 0, equation_rgb = 0, equation_alpha = 0;
        GLboolean m[4] = {0, 0, 0, 0};
        f->GetIntegeri_v(GL_BLEND_SRC_RGB, k, &src_rgb);
        f->GetIntegeri_v(GL_BLEND_DST_ALPHA, k, &dst_alpha);
        f->GetIntegeri_v(GL_BLEND_EQUATION_RGB, k, &equation_rgb);
        f->GetIntegeri_v(GL_BLEND_EQUATION_ALPHA, k, &equation_alpha);
        f->GetBooleani_v(GL_COLOR_WRITEMASK, k, m);
        if ((f->IsEnabledi(GL_BLEND, k) != 0) != (k != 1) || src_rgb != GL_DST_COLOR ||
            dst_alpha != GL_CONSTANT_COLOR || equation_rgb != (k == 2 ? GL_MIN : GL_FUNC_SUBTRACT) ||
            equation_alpha != GL_MAX || m[0] != (k == 3) || !m[1] || m[2] || m[3] != (k == 2)) {
            printf("  %s: draw buffer %u's blending or colour mask was changed\n", what, k);
            h->mismatches++;
        }
    }
    GLint box[4], viewport[4];
    GLboolean mask[4] = {1, 1, 1, 1}, depth_mask = 1;
    f->GetIntegerv(GL_SCISSOR_BOX, box);
    f->GetIntegerv(GL_VIEWPORT, viewport);
    f->GetBooleanv(GL_COLOR_WRITEMASK, mask);
    f->GetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask);
    if (box[2] != 1 || box[3] != 1 || (bindings && (viewport[2] != 1 || viewport[3] != 1)) || mask[0] || mask[1] ||
        mask[2] || mask[3] || depth_mask) {
        printf("  %s: the scissor box, viewport or write masks were changed\n", what);
        h->mismatches++;
    }
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        printf("  %s: GL error 0x%x pending\n", what, error);
        h->mismatches++;
    }
}

#endif
