/* What the example hosts' C sides share (raycast.c, slice.c, lines.c): raw program
 * builds, render targets, volume and transfer textures, and the orbit camera. Not part
 * of the installed libhalo. Every GL call goes through a halo_glfuncs table. */
#ifndef HALO_EXAMPLE_HOST_COMMON_H
#define HALO_EXAMPLE_HOST_COMMON_H

#include "raycast.h"

/* ---- Programs ------------------------------------------------------------------ */

/* 0 with a USAGE diagnostic unless desc names gl, a size in 1..16384 and (with a
 * program) a runtime. */
int halo_host_desc_check(const halo_host_desc *desc, halo_diagnostics *diag);

/* How halo_host_link_raw reports a driver log: one diagnostic per "0:LINE(COL):" line
 * (HALO_HOST_LOG_LINES), or the compile log appended to one diagnostic. */
enum { HALO_HOST_LOG_APPENDED, HALO_HOST_LOG_LINES };

/* Compiles and links unlinked host texts; 0 with diagnostics on failure. */
GLuint halo_host_link_raw(const halo_glfuncs *f, const char *vertex_source, const char *vertex_file,
                          const char *fragment_source, const char *fragment_file, int log_style,
                          halo_diagnostics *diag);

/* The same for texts linked by halo_link: the driver's log lines are mapped through
 * each program's origins to the module's or host's file:line (a NULL program: as raw). */
GLuint halo_host_link_mapped(const halo_glfuncs *f, const halo_program *vertex_program, const char *vertex_source,
                             const char *vertex_file, const halo_program *fragment_program, const char *fragment_source,
                             const char *fragment_file, int log_style, halo_diagnostics *diag);

/* The host's program: desc->program built with halo_gl_program_build, else the
 * unlinked fragment text (default: the embedded default_fragment); the vertex text
 * defaults to the embedded default_vertex. 0 with diagnostics on failure. */
GLuint halo_host_program_build(const halo_host_desc *desc, const char *default_vertex, const char *default_fragment,
                               int log_style, halo_diagnostics *diag);

/* ---- Targets and textures ------------------------------------------------------- */

/* Binds texture and gives it NEAREST filtering and width x height texels of
 * internal_format (format/type: the NULL upload's). Leaves it bound. */
void halo_host_image_texture(const halo_glfuncs *f, GLuint texture, GLint internal_format, int width, int height,
                             GLenum format, GLenum type);

/* size zeroed bytes; NULL with an OUT_OF_MEMORY diagnostic. */
void *halo_host_calloc(size_t size, halo_diagnostics *diag);

/* HALO_OK when GL reports no error; else a diagnostic id "FAILED (GL error 0x...)" and
 * HALO_ERROR_IO. */
halo_status halo_host_gl_check(const halo_glfuncs *f, halo_message_id id, const char *failed, halo_diagnostics *diag);

/* Generates *framebuffer with color_texture as colour attachment 0 and checks it;
 * 0 with a GL_LINK diagnostic for an incomplete target or a GL error. */
int halo_host_framebuffer(const halo_glfuncs *f, GLuint *framebuffer, GLuint color_texture, int width, int height,
                          halo_diagnostics *diag);

/* Uploads nx*ny*nz floats to texture as an R32F GL_LINEAR/CLAMP_TO_EDGE 3D texture.
 * HALO_ERROR_INPUT (USAGE) for no f or data or a side outside 2..2048. */
halo_status halo_host_upload_volume(const halo_glfuncs *f, GLuint texture, const float *data, int nx, int ny, int nz,
                                    halo_diagnostics *diag);
/* The same for a volume classified before it is interpolated (nx*ny*nz RGBA texels as
 * floats in [0,1]): GL_RGBA8, colour and opacity per voxel, filtered linearly. */
halo_status halo_host_upload_classified(const halo_glfuncs *f, GLuint texture, const float *rgba, int nx, int ny,
                                        int nz, halo_diagnostics *diag);
/* The same for a segmentation (integer label ids as floats), read with texelFetch:
 * GL_NEAREST, so that no two labels are ever blended. */
halo_status halo_host_upload_labels(const halo_glfuncs *f, GLuint texture, const float *labels, int nx, int ny, int nz,
                                    halo_diagnostics *diag);
/* The gradients of the volume (nx*ny*nz floats) to texture: the voxels' central
 * differences (halo_volume_gradients), GL_LINEAR, stored as internal_format: GL_RGB32F,
 * GL_RGB16F or GL_RGB8_SNORM. Built and uploaded in slabs of slices: no whole-volume CPU
 * copy, at most HALO_HOST_GRADIENT_SLAB_BYTES of floats at a time. A signed-normalised
 * texture holds g / *scale, *scale the largest |component| of the volume's gradients (so
 * that the 8 bits span the volume's own range), and so does GL_RGB16F when that exceeds
 * 1 (values beyond the contract's [0,1], whose gradients could pass half's 65504); the
 * shader multiplies by *scale. Otherwise *scale = 1. */
#define HALO_HOST_GRADIENT_SLAB_BYTES (4u << 20)
halo_status halo_host_upload_gradients(const halo_glfuncs *f, GLuint texture, const float *volume, int nx, int ny,
                                       int nz, GLint internal_format, float *scale, halo_diagnostics *diag);

/* The scale halo_host_upload_gradients and halo_host_build_gradients store the volume's
 * gradients with in internal_format (see above): 1, or the largest |component|. */
float halo_host_gradient_scale(const float *volume, const int dims[3], GLint internal_format);
/* Whether the GL renders into layers of a 3D texture of internal_format (a probe of 2^3
 * texels; GL errors of the probe are cleared). */
int halo_host_gradients_renderable(const halo_glfuncs *f, GLint internal_format);
/* The same gradients as halo_host_upload_gradients, built on the GPU from volume_texture
 * (the R32F volume of halo_host_upload_volume, read with texelFetch) one layer per draw
 * (gradient.frag), stored as g / scale: no CPU copy of the volume is needed, so the host
 * can free its own before. The floats are the CPU's (central differences in float,
 * then the scale); only the conversion to internal_format may round differently.
 * Leaves framebuffer 0, no program and no 3D texture on unit 0 bound. */
halo_status halo_host_build_gradients(const halo_glfuncs *f, GLuint texture, GLuint volume_texture, int nx, int ny,
                                      int nz, GLint internal_format, float scale, halo_diagnostics *diag);

/* The packed formats: one texture for the value and the gradient (one fetch for both).
 * R holds (value - range[0]) / range[1], GBA g / scale; internal_format
 * GL_RGBA16_SNORM (packed16: 16 bits each, 8 bytes a voxel; scale the largest |component|,
 * so that GBA stays in [-1, 1]; a zero gradient is code 0, exactly 0 when read) or GL_RGBA32F (packed32: floats, 16 bytes a voxel; scale 1).
 * Built on the GPU from volume_texture as halo_host_build_gradients is; the shader
 * decodes range[0] + R range[1] and GBA scale, linear maps of the filtered
 * texels. */
halo_status halo_host_build_packed(const halo_glfuncs *f, GLuint texture, GLuint volume_texture, int nx, int ny, int nz,
                                   GLint internal_format, float scale, const float range[2], halo_diagnostics *diag);
/* The volume's finite values' range for halo_host_build_packed: range[0] the least,
 * range[1] the span (1 when they are all equal or there are none). */
void halo_host_value_range(const float *volume, const int dims[3], float range[2]);

/* The transfer table: control points (value, r, g, b, opacity) sorted by value,
 * linearly interpolated, constant beyond the first and last. */
void halo_host_fill_transfer(float *table, const halo_render_settings *s);

/* Fills table from settings (see above), uploads it to texture and takes the step
 * (voxels, default 0.5) and background colour of settings (NULL: defaults). */
halo_status halo_host_upload_transfer(const halo_glfuncs *f, GLuint texture, float *table,
                                      const halo_render_settings *settings, float *step_voxels, float background[3],
                                      halo_diagnostics *diag);

int halo_host_max_dimension(const int dims[3]);

/* ---- Camera ---------------------------------------------------------------------- */

/* 4x4 matrices, column-major (m[column * 4 + row]) as OpenGL takes them. */
void halo_host_matrix_multiply(const double a[16], const double b[16], double out[16]);
/* By cofactors over the determinant; returns 0 for a singular matrix. */
int halo_host_matrix_invert(const double m[16], double out[16]);

/* The ray caster's orbit camera around the unit volume's centre. */
typedef struct halo_host_camera {
    double eye[3];
    double back[3]; /* from the centre to the eye */
    double right[3], up[3];
    float inverse_view_projection[16];
    double view_projection[16]; /* column-major, volume texture space -> clip space */
} halo_host_camera;

/* Degrees; non-finite angles count as 0 and zoom as 1. Returns 0 (camera partly
 * filled) when the view-projection matrix is singular. */
/* The perspective projection (column-major) of the example hosts: a field of view of
 * 2 half_fov radians across the smaller image side (aspect = width / height). */
void halo_host_perspective(double half_fov, double aspect, double near_plane, double far_plane, double out[16]);
int halo_host_orbit_camera(double azimuth, double elevation, double zoom, int width, int height,
                           halo_host_camera *camera);
/* The same with an orthographic projection when orthographic is 1 (the eye stays where the
 * perspective one is: hosts that take a view vector from it see nearly parallel rays). */
int halo_host_orbit_camera_projection(double azimuth, double elevation, double zoom, int width, int height,
                                      int orthographic, halo_host_camera *camera);
/* The camera in the float fields that the hosts keep and upload: the inverse
 * view-projection, the eye and the image-plane axes. */
void halo_host_camera_keep(const halo_host_camera *camera, float inverse_view_projection[16], float eye[3],
                           float screen_right[3], float screen_up[3]);

#endif
