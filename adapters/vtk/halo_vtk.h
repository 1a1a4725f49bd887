/* libhalo-vtk: libhalo's stages inside VTK's GPU volume ray caster (VTK 9.1 and up).
 *
 * One call installs a linked scene into a vtkGPUVolumeRayCastMapper through the
 * volume's vtkOpenGLShaderProperty: the stages' declarations and the per-sample piece
 * (docs/composers.md) become fragment shader replacements, their live parameters VTK
 * custom uniforms. The adapter converts VTK's conventions (value normalised over the
 * data range, opacity corrected for the sample distance, no gradient unless shading is
 * on) to the host contract's; see docs/hosts/vtk.md. After the first render,
 * halo_vtk_check says whether the splice took, and validates the shader VTK composed
 * with libhalo's diagnostics. C++, since VTK is. */
#ifndef HALO_VTK_H
#define HALO_VTK_H

#include "halo.h"

class vtkGPUVolumeRayCastMapper;
class vtkRenderer;
class vtkVolume;

typedef struct halo_vtk halo_vtk;

typedef struct halo_vtk_desc {
    vtkGPUVolumeRayCastMapper *mapper; /* required; its input must be set */
    vtkVolume *volume;                 /* required: its shader property takes the replacements */
    vtkRenderer *renderer;             /* required: the renderer the volume is in */
    const halo_library *library;       /* required */
    const halo_scene *scene;           /* NULL: no stage (the shader stays VTK's own) */
    double window[2];                  /* the data values mapped to 0 and 1 (the contract's value);
                                        * {0, 0}: the input's scalar range */
    int all_live;                      /* every parameter a uniform (halo_vtk_set on any of them) */
    int segments;                      /* halo_vtk_mapper_new's mapper with volumetric halos: 0 (default):
                                        * VTK draws once, over the halo field libhalo computes first
                                        * (host contract 3); 1: once per depth segment (host contract 2:
                                        * the pieces of a distributed volume, halo_vtk_set_exchange) */
    int image_scale;                   /* halo images at 1/image_scale of VTK's frame per side (halo_link_desc.
                                        * image_scale): 0 or 1 full, 2, 4; drawn once, libhalo's march at that
                                        * scale too (docs/performance.md: the cheaper halo frame, its error).
                                        * Drawn once, a frame whose halo field is over field_max_bytes is
                                        * drawn at twice this scale (at most 4), with a warning (FIELD_MEMORY),
                                        * and so are the frames after it (halo_vtk_program: the new program) */
    int own_gradient;                  /* with VTK's shading on, the stages read the gradient VTK computes for
                                        * its lighting (no fetch of their own); 1: the adapter's gradient
                                        * texture always (docs/hosts/vtk.md, "The gradient") */
    size_t field_max_bytes;            /* drawn once: the cap on the frame's halo field
                                        * (halo_gl_segments_desc.field_max_bytes); 0: libhalo's, 1 GiB */
} halo_vtk_desc;

/* Installs the scene. Returns NULL, with the reason in diag, when the mapper or the
 * scene cannot take it: a blend mode other than composite, more than one component, a
 * label mask, or stages that need image passes (volumetric halos, outlines, feature
 * halos: with VTK's own mapper; the adapter's, halo_vtk_mapper_new, takes them;
 * docs/hosts/vtk.md). */
halo_vtk *halo_vtk_install(const halo_vtk_desc *desc, halo_diagnostics *diag);
/* A vtkGPUVolumeRayCastMapper (VTK's OpenGL one, subclassed) for scenes with image
 * passes: libhalo computes the frame's halo field from its own copy of the volume (the
 * value over the window, 4 bytes a voxel, and a derived gradient, 8), VTK draws once with
 * early ray termination, and the at=post passes (outlines) run on VTK's image; or, with
 * halo_vtk_desc.segments, VTK's ray caster is drawn once per depth segment with the passes
 * between. Without such a scene it renders as VTK's own. Delete() it as any VTK object. */
vtkGPUVolumeRayCastMapper *halo_vtk_mapper_new(void);
/* Removes the replacements and uniforms; the mapper renders as VTK's own again. The
 * handle is gone after it: a second remove does nothing, halo_vtk_set and halo_vtk_check
 * on it report USAGE and the getters return NULL / 0 (its address is compared with the
 * live installs, never read). A later install may get the same address back, and a stale
 * handle then names it: drop the handle when you remove it. NULL: nothing. */
void halo_vtk_remove(halo_vtk *h);
/* A live parameter's new value: a uniform update, no shader rebuild. */
halo_status halo_vtk_set(halo_vtk *h, const char *stage, const char *param, const double *values, int count,
                         halo_diagnostics *diag);
/* After a render: HALO_OK when the shader VTK built holds the stages (the splice took)
 * and validates; else diagnostics say why (the blend mode changed, VTK's code moved). */
halo_status halo_vtk_check(halo_vtk *h, halo_diagnostics *diag);
/* The input is a piece of a larger image (a brick of a distributed volume: ParaView):
 * whole_extent is the whole dataset's point extent, the input's extent lies within it.
 * Positions, depth and the segments of volumetric halos are then the whole volume's, the
 * same on every piece (docs/distributed.md). Call again when the whole extent changes. */
halo_status halo_vtk_set_whole_extent(halo_vtk *h, const int whole_extent[6]);
/* Volumetric halos across pieces. Drawn once (the default): libhalo's march reads each
 * piece, and once a frame exchange gets the seeds of every depth segment (layers x
 * width x height RGBA floats; above 256 MiB in consecutive calls of whole layers, the
 * same calls on every piece) to combine in place with the other pieces' by blend (max).
 * With segments = 1: after each depth segment, the adapter reads each output
 * image (the seeds: width * height RGBA floats) and calls exchange to combine it, in
 * place, with the other pieces' by the output's blend (max for seeds), before the passes
 * spread it. Every piece must draw the same segments (same camera and whole extent). */
typedef void (*halo_vtk_exchange_fn)(void *user, float *values, size_t count, halo_blend blend);
void halo_vtk_set_exchange(halo_vtk *h, halo_vtk_exchange_fn exchange, void *user);
/* The linked program (its pieces and reflection). */
const halo_program *halo_vtk_program(const halo_vtk *h);
/* Shader programs VTK built with the stages since the install (a live change adds none). */
int halo_vtk_build_count(const halo_vtk *h);

#endif
