/* The camera of host contracts 2 and 3 in the GL runtime: from a host's inverse
 * view-projection to the view axis, the eye and the depth range of the volume's bounding
 * sphere (the uniforms of halo_view_at and halo_depth_at), and the plan of the depth
 * segments: the slice host's planes phi = front + k * step from the front of the
 * bounding sphere, M of them a segment (segments.c draws a host in them; field.c
 * computes the field of each before one draw). */
#include "halo.h"
#include "internal.h"
#include "diag.h"
#include "gl/frame.h"
#include "gl/glfuncs.h"

#include <math.h>
#include <string.h>

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

void halo_segments_box(const halo_gl_segments_desc *d, double low[3], double high[3])
{
    int unit_cube = 1;
    for (int k = 0; k < 3; ++k)
        unit_cube &= d->box_min[k] == 0.0f && d->box_max[k] == 0.0f;
    for (int k = 0; k < 3; ++k) {
        low[k] = unit_cube ? 0.0 : d->box_min[k];
        high[k] = unit_cube ? 1.0 : d->box_max[k];
    }
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
    double low[3], high[3], centre_phi = c->plane[3], radius = 0.0;
    halo_segments_box(d, low, high);
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

int halo_segments_desc_valid(const halo_gl_segments_desc *d, const char *function, halo_diagnostics *diag)
{
    if (d && d->inverse_view_projection && d->step > 0.0f && isfinite(d->step))
        return 1;
    halo_diag_error(diag, USAGE, "", 0, 0, "%s: inverse_view_projection and a finite step > 0 are required", function);
    return 0;
}

/* The checks of the public entry points: the object (named object_name) and the desc are
 * not NULL and the desc is valid; reported as function's. */
int halo_segments_arguments_valid(const void *object, const char *object_name, const halo_gl_segments_desc *d,
                                  const char *function, halo_diagnostics *diag)
{
    if (!object || !d) {
        halo_diag_null(diag, function, object ? "desc" : object_name);
        return 0;
    }
    return halo_segments_desc_valid(d, function, diag);
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
    if (!halo_segments_arguments_valid(gl, "gl", desc, "halo_gl_set_camera", diag))
        return HALO_ERROR_INPUT;
    halo_segment_plan camera;
    if (!segment_camera(desc, &camera)) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_gl_set_camera: inverse_view_projection is not invertible");
        return HALO_ERROR_INPUT;
    }
    halo_segment_camera_set(halo_gl_functions(gl), gl_program, &camera);
    return HALO_OK;
}

/* M: the desc's, the program's (its reflection's interval), or the paper's 4. */
static int segment_interval(const halo_program *p, const halo_gl_segments_desc *d)
{
    if (d->interval > 0)
        return d->interval;
    int m = halo_program_reflection(p).interval;
    return m > 0 ? m : 4;
}

int halo_segment_plan_make(const halo_gl_segments_desc *d, const halo_program *p, halo_segment_plan *plan,
                           halo_diagnostics *diag)
{
    if (!p || !halo_segments_desc_valid(d, "halo_gl_frame_draw", diag))
        return 0;
    int location = halo_program_reflection(p).segment_location;
    if (d->segments > 0 && location <= 0 && !p->one_draw) {
        halo_diag_error(diag, USAGE, "", 0, 0,
                        "halo_gl_frame_draw: segments = %d needs a program linked with force_segments from a host "
                        "that calls halo_segment_begin",
                        d->segments);
        return 0;
    }
    if (d->segments > HALO_SEGMENTS_MAX) {
        halo_diag_error(diag, USAGE, "", 0, 0,
                        "halo_gl_frame_draw: segments = %d: at most %d (each is a draw of the host and, with "
                        "volumetric halos, a generation)",
                        d->segments, HALO_SEGMENTS_MAX);
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
            plan->segments = count < 1.0 ? 1 : count > HALO_SEGMENTS_MAX ? HALO_SEGMENTS_MAX : (int)count;
            plan->length =
                count > HALO_SEGMENTS_MAX ? planes * d->step / HALO_SEGMENTS_MAX : interval * (double)d->step;
        }
    }
    return 1;
}
