/* Host contract 2 in the GL runtime: the camera of the derived inputs, and a host's
 * frame drawn in view-aligned depth segments with the image passes run between them
 * (docs/host-contract.md, "Segmented ray casting"). The segment planes are the slice
 * host's: phi = front + k * step from the front of the volume's bounding sphere; segment
 * j takes the samples with phi in [front + (j M - 1/2) step, front + ((j + 1) M - 1/2) step),
 * those nearest to the planes j M .. (j + 1) M - 1, as the slice host draws M slices
 * between two generations. */
#include "halo.h"
#include "internal.h"
#include "diag.h"
#include "gl/frame.h"
#include "gl/glfuncs.h"
#include "gl/runtime.h"

#include <math.h>
#include <string.h>

#define DEFAULT_FIRST_UNIT 8
#define MAX_LOCATIONS      16

/* Draw buffers: the host's colour at 0 (GL_NONE before the last segment), the frame's
 * outputs, and the ray state. */
static void set_draw_buffers(const halo_glfuncs *f, const halo_program *p, int location, int last)
{
    GLenum buffers[MAX_LOCATIONS];
    int count = 1;
    buffers[0] = last ? GL_COLOR_ATTACHMENT0 : GL_NONE;
    for (int k = 1; k < MAX_LOCATIONS; ++k)
        buffers[k] = GL_NONE;
    for (size_t i = 0; i < halo_program_reflection(p).output_count; ++i) {
        int l = halo_program_reflection(p).outputs[i].location;
        if (l > 0 && l < MAX_LOCATIONS) {
            buffers[l] = GL_COLOR_ATTACHMENT0 + (GLenum)l;
            count = l + 1 > count ? l + 1 : count;
        }
    }
    if (location > 0 && location < MAX_LOCATIONS) {
        buffers[location] = GL_COLOR_ATTACHMENT0 + (GLenum)location;
        count = location + 1 > count ? location + 1 : count;
    }
    f->DrawBuffers(count, buffers);
}

static halo_status frame_draw(halo_gl_frame *fr, unsigned gl_program, const halo_gl_segments_desc *d,
                              halo_diagnostics *diag);

halo_status halo_gl_frame_draw(halo_gl_frame *fr, unsigned gl_program, const halo_gl_segments_desc *d,
                               halo_diagnostics *diag)
{
    if (!halo_segments_arguments_valid(fr, "frame", d, "halo_gl_frame_draw", diag))
        return HALO_ERROR_INPUT;
    halo_gl_frame_drawing(fr, 1);
    halo_status status = frame_draw(fr, gl_program, d, diag);
    if (halo_gl_frame_drawing(fr, 0)) { /* the outermost draw, and a callback destroyed the frame */
        halo_gl_frame_destroy(fr);
        halo_diag_error(diag, USAGE, "", 0, 0,
                        "halo_gl_frame_draw: the draw callback destroyed the frame; it is destroyed now that the "
                        "draw returned (destroy a frame after halo_gl_frame_draw, not from its callback)");
        return HALO_ERROR_INPUT;
    }
    return status;
}

static halo_status frame_draw(halo_gl_frame *fr, unsigned gl_program, const halo_gl_segments_desc *d,
                              halo_diagnostics *diag)
{
    if (!d->draw) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_gl_frame_draw: desc.draw is required");
        return HALO_ERROR_INPUT;
    }
    halo_gl *gl = halo_gl_frame_runtime(fr);
    const halo_glfuncs *f = halo_gl_functions(gl);
    const halo_program *p = halo_gl_frame_program(fr);
    int location = halo_program_reflection(p).segment_location;
    if (halo_program_reflection(p).group_count > 1) {
        halo_diag_error(diag, USAGE, "", 0, 0,
                        "halo_gl_frame_draw: a program with %d feature groups is drawn once per group by the "
                        "host (halo_gl_frame_begin_group/end_group around its draws); not by halo_gl_frame_draw",
                        halo_program_reflection(p).group_count);
        return HALO_ERROR_INPUT;
    }
    if (p->one_draw) /* host contract 3 */
        return halo_gl_field_draw(fr, gl_program, d, diag);
    halo_segment_plan plan;
    if (!halo_segment_plan_make(d, p, &plan, diag))
        return HALO_ERROR_INPUT;
    int first_unit = d->first_unit > 0 ? d->first_unit : DEFAULT_FIRST_UNIT;
    int state_unit = first_unit + (int)halo_program_reflection(p).sampler_count;
    int segments = plan.segments;
    int generate = 0;
    for (size_t i = 0; i < halo_program_reflection(p).pass_count; ++i)
        generate |= halo_program_reflection(p).passes[i].at == HALO_PASS_AT_GENERATE;

    GLint saved_program = 0, saved_framebuffer = 0, saved_active = GL_TEXTURE0, saved_texture = 0;
    f->GetIntegerv(GL_CURRENT_PROGRAM, &saved_program);
    f->GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &saved_framebuffer);
    f->GetIntegerv(GL_ACTIVE_TEXTURE, &saved_active);
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)state_unit);
    f->GetIntegerv(GL_TEXTURE_BINDING_2D, &saved_texture);

    f->UseProgram(gl_program);
    halo_segment_camera_set(f, gl_program, &plan);
    halo_gl_frame_begin(fr);
    halo_gl_frame_segments_reset(fr);
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, d->framebuffer);
    /* one blend for all buffers (OpenGL ES 3.0): the outputs' attach turns it off */
    GLboolean blend = f->IsEnabled(GL_BLEND);
    halo_gl_frame_attach(fr, d->framebuffer);
    halo_gl_frame_bind(fr, gl_program, first_unit);
    GLint flags_location = f->GetUniformLocation(gl_program, "halo_segment_flags");
    GLint bounds_location = f->GetUniformLocation(gl_program, "halo_segment_bounds");
    if (location > 0) {
        f->Uniform1i(f->GetUniformLocation(gl_program, "halo_segment_state"), state_unit);
        if (f->Disablei)
            f->Disablei(GL_BLEND, (GLuint)location);
    }
    for (int j = 0; j < segments; ++j) {
        int last = j == segments - 1;
        /* the host's draw may have left another program or framebuffer bound (what the
         * generation gives back is the host's state after its draw) */
        f->UseProgram(gl_program);
        f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, d->framebuffer);
        if (location > 0) {
            f->Uniform1i(flags_location, (j == 0 ? 1 : 0) | (last ? 2 : 0));
            f->Uniform2f(bounds_location, (float)(plan.start + j * plan.length),
                         (float)(plan.start + (j + 1) * plan.length));
            f->ActiveTexture(GL_TEXTURE0 + (GLenum)state_unit);
            f->BindTexture(GL_TEXTURE_2D, halo_gl_frame_state(fr, 0));
            f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)location, GL_TEXTURE_2D,
                                    halo_gl_frame_state(fr, 1), 0);
            set_draw_buffers(f, p, location, last);
        }
        d->draw(d->user);
        if (halo_gl_frame_drawing(fr, -1) < 0) /* the callback destroyed the frame: no more segments */
            break;
        if (location > 0)
            halo_gl_frame_state_flip(fr);
        if (!last && generate) {
            halo_gl_frame_generate(fr); /* restores program, framebuffer and the bound samplers */
        }
    }
    if (location > 0) {
        f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, d->framebuffer);
        f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)location, GL_TEXTURE_2D, 0, 0);
        set_draw_buffers(f, p, 0, 1);
    } else if (segments == 1) {
        halo_gl_frame_state_flip(fr); /* counts the one draw */
    }
    if (!halo_gl_blend_per_buffer(f) && halo_program_reflection(p).output_count > 0)
        (blend ? f->Enable : f->Disable)(GL_BLEND);
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)state_unit);
    f->BindTexture(GL_TEXTURE_2D, (GLuint)saved_texture);
    f->ActiveTexture((GLenum)saved_active);
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)saved_framebuffer);
    halo_gl_use_saved_program(f, saved_program);
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        halo_diag_error(diag, GL_LINK, "", 0, 0, "OpenGL error 0x%x while drawing the host in %d segment%s", error,
                        segments, segments == 1 ? "" : "s");
        return HALO_ERROR_IO;
    }
    return HALO_OK;
}
