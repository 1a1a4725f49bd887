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

#include <math.h>
#include <string.h>

#define DEFAULT_FIRST_UNIT 8
#define MAX_LOCATIONS 16

int halo_mat4_invert(const double m[16], double out[16])
{
    double a[4][8];
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col) {
            a[row][col] = m[col * 4 + row];
            a[row][col + 4] = row == col ? 1.0 : 0.0;
        }
    for (int col = 0; col < 4; ++col) {
        int pivot = col;
        for (int row = col + 1; row < 4; ++row)
            if (fabs(a[row][col]) > fabs(a[pivot][col]))
                pivot = row;
        if (!(fabs(a[pivot][col]) >= 1e-300))
            return 0;
        if (pivot != col)
            for (int k = 0; k < 8; ++k) {
                double tmp = a[col][k];
                a[col][k] = a[pivot][k];
                a[pivot][k] = tmp;
            }
        double scale = 1.0 / a[col][col];
        for (int k = 0; k < 8; ++k)
            a[col][k] *= scale;
        for (int row = 0; row < 4; ++row)
            if (row != col) {
                double factor = a[row][col];
                for (int k = 0; k < 8; ++k)
                    a[row][k] -= factor * a[col][k];
            }
    }
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col)
            out[col * 4 + row] = a[row][col + 4];
    return 1;
}

/* From clip space -> ray space: the clip w row (perspective: the distance along the view
 * axis) or, for an orthographic camera (w constant), the clip z row. The eye is the point
 * whose clip x, y and w are 0: inverse * (0, 0, 1, 0). */
static int segment_camera(const halo_gl_segments_desc *d, halo_segment_plan *c)
{
    double inverse[16], m[16];
    for (int i = 0; i < 16; ++i)
        inverse[i] = d->inverse_view_projection[i];
    if (!halo_mat4_invert(inverse, m))
        return 0;
    double w_row[4] = {m[3], m[7], m[11], m[15]}, z_row[4] = {m[2], m[6], m[10], m[14]};
    double w_norm = sqrt(w_row[0] * w_row[0] + w_row[1] * w_row[1] + w_row[2] * w_row[2]);
    double z_norm = sqrt(z_row[0] * z_row[0] + z_row[1] * z_row[1] + z_row[2] * z_row[2]);
    int perspective = w_norm > 1e-9 * z_norm;
    const double *row = perspective ? w_row : z_row;
    double norm = perspective ? w_norm : z_norm;
    if (!(norm > 0.0) || !isfinite(norm))
        return 0;
    for (int k = 0; k < 4; ++k)
        c->plane[k] = row[k] / norm;
    if (perspective) {
        double w = inverse[11];
        if (!(fabs(w) > 0.0))
            return 0;
        for (int k = 0; k < 3; ++k)
            c->eye[k] = inverse[8 + k] / w;
        c->eye[3] = 1.0;
    } else {
        for (int k = 0; k < 3; ++k)
            c->eye[k] = -c->plane[k];
        c->eye[3] = 0.0;
    }
    double low[3] = {0, 0, 0}, high[3] = {1, 1, 1}, centre_phi = c->plane[3], radius = 0.0;
    int unit_cube = 1;
    for (int k = 0; k < 3; ++k)
        unit_cube &= d->box_min[k] == 0.0f && d->box_max[k] == 0.0f;
    for (int k = 0; k < 3 && !unit_cube; ++k) {
        low[k] = d->box_min[k];
        high[k] = d->box_max[k];
    }
    for (int k = 0; k < 3; ++k) {
        centre_phi += c->plane[k] * 0.5 * (low[k] + high[k]);
        radius += 0.25 * (high[k] - low[k]) * (high[k] - low[k]);
    }
    radius = sqrt(radius);
    c->front = centre_phi - radius;
    c->back = centre_phi + radius;
    for (int k = 0; k < 4; ++k)
        if (!isfinite(c->eye[k]) || !isfinite(c->plane[k]))
            return 0;
    return isfinite(c->front) && isfinite(c->back);
}

static int desc_valid(const halo_gl_segments_desc *d, const char *function, halo_diagnostics *diag)
{
    if (d && d->inverse_view_projection && d->step > 0.0f && isfinite(d->step))
        return 1;
    halo_diag_error(diag, USAGE, "", 0, 0, "%s: inverse_view_projection and a finite step > 0 are required",
                    function);
    return 0;
}

/* The checks of the public entry points: the object (named object_name) and the desc are
 * not NULL and the desc is valid; reported as function's. */
static int arguments_valid(const void *object, const char *object_name, const halo_gl_segments_desc *d,
                           const char *function, halo_diagnostics *diag)
{
    if (!object || !d) {
        halo_diag_null(diag, function, object ? "desc" : object_name);
        return 0;
    }
    return desc_valid(d, function, diag);
}

void halo_segment_camera_set(const halo_glfuncs *f, unsigned program, const halo_segment_plan *c)
{
    f->Uniform4f(f->GetUniformLocation(program, "halo_camera_eye"), (float)c->eye[0], (float)c->eye[1],
                 (float)c->eye[2], (float)c->eye[3]);
    f->Uniform4f(f->GetUniformLocation(program, "halo_camera_plane"), (float)c->plane[0], (float)c->plane[1],
                 (float)c->plane[2], (float)c->plane[3]);
    f->Uniform2f(f->GetUniformLocation(program, "halo_camera_depth_range"), (float)c->front, (float)c->back);
}

halo_status halo_gl_set_camera(halo_gl *gl, unsigned gl_program, const halo_gl_segments_desc *desc,
                               halo_diagnostics *diag)
{
    if (!arguments_valid(gl, "gl", desc, "halo_gl_set_camera", diag))
        return HALO_ERROR_INPUT;
    halo_segment_plan camera;
    if (!segment_camera(desc, &camera)) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_gl_set_camera: inverse_view_projection is not invertible");
        return HALO_ERROR_INPUT;
    }
    halo_segment_camera_set(halo_gl_functions(gl), gl_program, &camera);
    return HALO_OK;
}

/* M: the desc's, the program's halo_generate.interval, or the paper's 4. */
static int segment_interval(const halo_program *p, const halo_gl_segments_desc *d)
{
    if (d->interval > 0)
        return d->interval;
    const halo_uniform_info *u = halo_program_find_uniform(p, "halo_generate", "interval");
    if (u && u->value && u->count > 0 && u->value[0] >= 1.0 && u->value[0] < 1e6)
        return (int)u->value[0];
    return 4;
}

/* Draw buffers: the host's colour at 0 (GL_NONE before the last segment), the frame's
 * outputs, and the ray state. */
static void set_draw_buffers(const halo_glfuncs *f, const halo_program *p, int location, int last)
{
    GLenum buffers[MAX_LOCATIONS];
    int count = 1;
    buffers[0] = last ? GL_COLOR_ATTACHMENT0 : GL_NONE;
    for (int k = 1; k < MAX_LOCATIONS; ++k)
        buffers[k] = GL_NONE;
    for (size_t i = 0; i < halo_program_output_count(p); ++i) {
        int l = halo_program_output(p, i)->location;
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

int halo_segment_plan_make(const halo_gl_segments_desc *d, const halo_program *p, halo_segment_plan *plan,
                           halo_diagnostics *diag)
{
    if (!p || !desc_valid(d, "halo_gl_frame_draw", diag))
        return 0;
    int location = halo_program_segment_location(p);
    if (d->segments > 0 && location <= 0 && !p->one_draw) {
        halo_diag_error(diag, USAGE, "", 0, 0,
                        "halo_gl_frame_draw: segments = %d needs a program linked with force_segments from a host "
                        "that calls halo_segment_begin", d->segments);
        return 0;
    }
    if (!segment_camera(d, plan)) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_gl_frame_draw: inverse_view_projection is not invertible");
        return 0;
    }
    /* planes front + k step, k = 0 .. count - 1; a segment of M of them, each sample in
     * the segment of its nearest plane */
    double span = plan->back - plan->front;
    double planes = floor(span / d->step) + 1.0;
    plan->segments = 1;
    plan->start = plan->front - 0.5 * d->step;
    plan->length = span + d->step;
    if (location > 0 || p->one_draw) { /* host contract 3: segments of the field, one host draw */
        if (d->segments > 0) {
            plan->segments = d->segments;
            plan->length = planes * d->step / d->segments;
        } else {
            int interval = segment_interval(p, d);
            double count = ceil(planes / interval);
            plan->segments = count < 1.0 ? 1 : count > 65536.0 ? 65536 : (int)count;
            plan->length = count > 65536.0 ? planes * d->step / 65536.0 : interval * (double)d->step;
        }
    }
    return 1;
}

halo_status halo_gl_frame_draw(halo_gl_frame *fr, unsigned gl_program, const halo_gl_segments_desc *d,
                               halo_diagnostics *diag)
{
    if (!arguments_valid(fr, "frame", d, "halo_gl_frame_draw", diag))
        return HALO_ERROR_INPUT;
    if (!d->draw) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_gl_frame_draw: desc.draw is required");
        return HALO_ERROR_INPUT;
    }
    halo_gl *gl = halo_gl_frame_runtime(fr);
    const halo_glfuncs *f = halo_gl_functions(gl);
    const halo_program *p = halo_gl_frame_program(fr);
    if (p->one_draw)
        return halo_gl_field_draw(fr, gl_program, d, diag);
    int location = halo_program_segment_location(p);
    if (halo_program_group_count(p) > 1) {
        halo_diag_error(diag, USAGE, "", 0, 0,
                        "halo_gl_frame_draw: a program with %d feature groups is drawn once per group by the "
                        "host (halo_gl_frame_begin_group/end_group around its draws); not by halo_gl_frame_draw",
                        halo_program_group_count(p));
        return HALO_ERROR_INPUT;
    }
    halo_segment_plan plan;
    if (!halo_segment_plan_make(d, p, &plan, diag))
        return HALO_ERROR_INPUT;
    int first_unit = d->first_unit > 0 ? d->first_unit : DEFAULT_FIRST_UNIT;
    int state_unit = first_unit + (int)halo_program_sampler_count(p);
    int segments = plan.segments;
    int generate = 0;
    for (size_t i = 0; i < halo_program_pass_count(p); ++i)
        generate |= halo_program_pass(p, i)->post == 0;

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
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)state_unit);
    f->BindTexture(GL_TEXTURE_2D, (GLuint)saved_texture);
    f->ActiveTexture((GLenum)saved_active);
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)saved_framebuffer);
    f->UseProgram((GLuint)saved_program);
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        halo_diag_error(diag, GL_LINK, "", 0, 0, "OpenGL error 0x%x while drawing the host in %d segment%s", error,
                        segments, segments == 1 ? "" : "s");
        return HALO_ERROR_IO;
    }
    return HALO_OK;
}
