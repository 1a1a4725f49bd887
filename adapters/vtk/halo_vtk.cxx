/* libhalo-vtk: the stages inside vtkGPUVolumeRayCastMapper (halo_vtk.h, docs/hosts/vtk.md).
 *
 * VTK composes its ray-casting shader from a template and //VTK:: tags. libhalo links
 * the scene as pieces (docs/composers.md) with VTK's names, and this file puts them in:
 *   - the declarations, with a few functions of ours that convert VTK's conventions,
 *     after //VTK::Base::Dec (they read in_volume, g_dirStep and the camera);
 *   - the sample piece where VTK's composite mode has the classified, not yet
 *     premultiplied colour of a sample: before "g_srcColor.rgb *= g_srcColor.a;";
 *   - the live parameters as VTK custom uniforms (VTK declares them; bools as int).
 * Facts about VTK 9.1 used here (read from its shader template and composer): the
 * value in `scalar` is normalised over the input's scalar range; computeOpacity already
 * holds 1 - (1 - a)^(in_sampleDistance / unit distance); the gradient exists only with
 * shading on (in computeLighting), so the stages get their own (central differences of
 * in_volume[0]), or with shading on take VTK's from computeLighting. */
#include "halo_vtk.h"

#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkMatrix4x4.h>
#include <vtkObjectFactory.h>
#include <vtkOpenGLGPUVolumeRayCastMapper.h>
#include <vtkOpenGLState.h>
#include <vtk_glew.h>

#include <dlfcn.h>
#include <vtkAbstractMapper.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkGPUVolumeRayCastMapper.h>
#include <vtkImageData.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkOpenGLShaderCache.h>
#include <vtkOpenGLShaderProperty.h>
#include <vtkRenderer.h>
#include <vtkPointData.h>
#include <vtkShader.h>
#include <vtkShaderProgram.h>
#include <vtkTextureUnitManager.h>
#include <vtkSmartPointer.h>
#include <vtkUniforms.h>
#include <vtkVolume.h>
#include <vtkVolumeProperty.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace
{

/* Where the sample piece goes: VTK's composite mode premultiplies the classified colour
 * here, just before compositing (one occurrence in a composite, one-component shader). */
const char splice_point[] = "g_srcColor.rgb *= g_srcColor.a;";
/* After VTK's base declarations: in_volume, the matrices, in_cameraPos. */
const char declarations_tag[] = "//VTK::Shading::Dec";
const char file_name[] = "(VTK volume shader)";

/* Host contract 2 in VTK's ray loop (volumetric halos): the loop's samples are
 * g_dataPos + i g_dirStep, i = 0, 1, ... while g_currentT (= i) < g_terminatePointMax. */
const char extension_tag[] = "//VTK::System::Dec";
/* the adapter's gradient texture has a fixed unit (layout(binding), GLSL 4.20's, an extension
 * in VTK's GLSL 150): VTK builds and binds its program itself, libhalo-vtk cannot set a
 * sampler there before VTK's first draw */
const char extension_text[] = "//VTK::System::Dec\n#extension GL_ARB_shading_language_420pack : require\n";
const char extension_segmented_text[] =
    "//VTK::System::Dec\n#extension GL_ARB_shading_language_420pack : require\n"
    "#extension GL_ARB_explicit_attrib_location : require\n";
const char begin_tag[] = "//VTK::Shading::Init";
/* A piece of a larger volume: VTK starts each piece's rays one step inside the piece, so
 * the samples of the pieces are not those of the whole volume; move the first one on to
 * the whole volume's lattice (one step inside its box, then whole steps; back by less
 * than a step, or forward by a hair), which makes the pieces sample where one renderer of
 * the whole volume samples. */
#define HALO_VTK_ALIGN                                                                                                   \
    "    if (halo_vtk_piece != 0) {\n"                                                                                   \
    "        // ---- libhalo-vtk: this piece's samples on the whole volume's lattice ----\n"                             \
    "        vec3 o = halo_vtk_global(g_dataPos), d = g_dirStep * halo_vtk_global_scale;\n"                              \
    "        float enter = -1e30;\n"                                                                                     \
    "        for (int a = 0; a < 3; ++a)\n"                                                                              \
    "            if (abs(d[a]) > 1e-12)\n"                                                                               \
    "                enter = max(enter, min((halo_vtk_box_lo[a] - o[a]) / d[a], (halo_vtk_box_hi[a] - o[a]) / d[a]));\n" \
    "        // the whole volume's samples are at enter + k, k = 1, 2, ... (in steps from here);\n"                      \
    "        // this piece takes those after its entry (one step back), the one on its entry\n"                          \
    "        // being the piece's in front\n"                                                                            \
    "        float behind = -enter, shift = floor(behind + 1e-4) - behind;\n"                                            \
    "        if (enter > -1e29 && shift != 0.0) {\n"                                                                     \
    "            g_dataPos += shift * g_dirStep;\n"                                                                      \
    "            g_terminatePointMax -= shift;\n"                                                                        \
    "        }\n"                                                                                                        \
    "    }\n"
const char align_text[] = "//VTK::Shading::Init\n" HALO_VTK_ALIGN;
const char begin_text[] =
    "//VTK::Shading::Init\n" HALO_VTK_ALIGN
    "    // ---- libhalo-vtk: this segment's samples of the ray (host contract 2) ----\n"
    "    float halo_vtk_max = g_terminatePointMax;\n"
    "    int halo_vtk_first = 0, halo_vtk_end = int(ceil(max(g_terminatePointMax, 0.0))) + 1;\n"
    "    halo_segment_begin(halo_vtk_global(g_dataPos), g_dirStep * halo_vtk_global_scale, 0.0, 1.0, halo_vtk_first,\n"
    "                       halo_vtk_end, g_fragColor);\n"
    "    if (halo_vtk_first >= halo_vtk_end)\n"
    "        g_exit = true;\n"
    "    g_dataPos += float(halo_vtk_first) * g_dirStep;\n"
    "    g_currentT = float(halo_vtk_first);\n"
    "    g_terminatePointMax = min(g_terminatePointMax, float(halo_vtk_end - 1));\n";
const char end_tag[] = "//VTK::Shading::Exit";
const char end_text[] =
    "//VTK::Shading::Exit\n"
    "    // the ray has ended unless it stopped at this segment's end\n"
    "    halo_segment_end(g_fragColor, !(g_currentT >= float(halo_vtk_end - 1) && float(halo_vtk_end - 1) < halo_vtk_max));\n";
/* early ray termination waits while the stages read every sample (HALO_RAY_MAY_END) */
const char termination_text[] = "(g_fragColor.a > g_opacityThreshold)";
const char termination_guarded[] = "(HALO_RAY_MAY_END != 0 && g_fragColor.a > g_opacityThreshold)";
/* VTK classifies only samples with opacity; the seeds of halos come from every sample
 * (a transparent one too, as in every libhalo host): let them in while the stages read
 * every sample */
const char visible_test[] = "if (g_srcColor.a > 0.0)";
const char visible_test_guarded[] = "if (g_srcColor.a > 0.0 || HALO_RAY_MAY_END == 0)";
/* ... and while they read images made by passes (the halo field, drawn once: host contract
 * 3): a transparent sample where the field is nonzero becomes the halo */
const char visible_test_images[] = "if (g_srcColor.a > 0.0 || HALO_RAY_MAY_END == 0 || halo_vtk_reads_images)";
/* VTK's gradient, computed for its lighting with shading on (VTK 9.2: in computeLighting,
 * which computeColor calls just before the splice point, for every sample that reaches it):
 * kept for the stages. The #define tells the sample piece that it exists; where VTK's text
 * differs (VTK 9.1 names it otherwise), nothing is replaced and the stages read the
 * adapter's gradient texture. */
const char shading_gradient_text[] = "vec4 shading_gradient = computeGradient(g_dataPos, component, in_volume[0], 0);";
const char shading_gradient_kept[] =
    "vec4 shading_gradient = computeGradient(g_dataPos, component, in_volume[0], 0);\n"
    "#define HALO_VTK_SHADING_GRADIENT\n"
    "  halo_vtk_shading_gradient = shading_gradient;";
/* The sample's gradient. VTK's lighting-only computeGradient returns (g1 - g2) / spacing
 * with w = -1, g1 and g2 the scaled values at +-in_cellStep (1 / (N - 1) of the texture:
 * N / (N - 1) voxels); with gradient opacity it returns a unit vector and its magnitude
 * (w >= 0), and a sample whose lighting did not run leaves w = 0 (reset after each
 * sample): then the adapter's texture. As the contract's gradient (central differences
 * halved, per voxel step, of the value over the window): times the spacing, over
 * 2 in_cellStep N voxels, over the window's width. */
const char sample_gradient[] =
    "#ifdef HALO_VTK_SHADING_GRADIENT\n"
    "#define halo_vtk_sample_gradient(p) (halo_vtk_shading_gradient.w < 0.0 ? halo_vtk_shading_gradient.xyz * "
    "in_cellSpacing[0] / (in_cellStep[0] * vec3(textureSize(in_volume[0], 0))) * (0.5 / (halo_vtk_window.y - "
    "halo_vtk_window.x)) : halo_vtk_gradient(p))\n"
    "#else\n"
    "#define halo_vtk_sample_gradient(p) halo_vtk_gradient(p)\n"
    "#endif\n";
/* after the stages: the kept gradient is this sample's only */
const char sample_gradient_used[] =
    "#ifdef HALO_VTK_SHADING_GRADIENT\nhalo_vtk_shading_gradient = vec4(0.0);\n#endif\n";
const char finish_point[] = "gl_FragData[0] = g_fragColor;";
const char finish_text[] = "gl_FragData[0] = g_fragColor;\n  halo_finish();";
/* A piece of a distributed volume (halo_vtk_set_whole_extent): ParaView composites the
 * pieces' partial rays (premultiplied) in floating point and converts the result to bytes
 * without a clamp, so a partial ray brighter than its opacity (stages such as tone
 * shading add light) must be clamped to a valid premultiplied colour here. */
const char piece_clamp[] =
    "if (halo_vtk_piece != 0)\n"
    "    g_fragColor.rgb = clamp(g_fragColor.rgb, vec3(0.0), vec3(clamp(g_fragColor.a, 0.0, 1.0)));\n  ";

/* Every replacement the adapter makes in VTK's fragment shader, in one table walked by
 * the install (add those of its mode), halo_vtk_remove (clear every VTK text once) and
 * halo_vtk_check (each added one is in the shader VTK built). */
enum splice_mode : unsigned {
    SPLICE_OWN = 1,        /* VTK's own mapper: per-sample stages */
    SPLICE_DRAWN_ONCE = 2, /* halo_vtk_mapper_new's, drawn once over the halo field */
    SPLICE_SEGMENTS = 4,   /* halo_vtk_mapper_new's, drawn in depth segments */
    SPLICE_HALO = SPLICE_DRAWN_ONCE | SPLICE_SEGMENTS,
    SPLICE_ALL = SPLICE_OWN | SPLICE_HALO,
};
enum splice_text {
    TEXT_DECLARATIONS,
    TEXT_SAMPLE,
    TEXT_FIXED,
    TEXT_VISIBLE,
    TEXT_FINISH_OWN,
    TEXT_FINISH_HALO,
    TEXT_SHADING_GRADIENT
};
struct splice {
    const char *vtk_text; /* what VTK's shader holds */
    bool all;             /* every occurrence (VTK's tags) or the first */
    unsigned modes;
    splice_text kind;
    const char *fixed; /* TEXT_FIXED: the replacement */
    bool optional;     /* VTK's text may be absent (halo_vtk_check does not ask for it) */
};
const splice splices[] = {
    {declarations_tag, true, SPLICE_ALL, TEXT_DECLARATIONS, nullptr, false},
    {splice_point, false, SPLICE_ALL, TEXT_SAMPLE, nullptr, false},
    {extension_tag, true, SPLICE_OWN, TEXT_FIXED, extension_text, false},
    {extension_tag, true, SPLICE_HALO, TEXT_FIXED, extension_segmented_text, false},
    {begin_tag, true, SPLICE_OWN | SPLICE_DRAWN_ONCE, TEXT_FIXED, align_text, false},
    {begin_tag, true, SPLICE_SEGMENTS, TEXT_FIXED, begin_text, false},
    {end_tag, true, SPLICE_SEGMENTS, TEXT_FIXED, end_text, false},
    {termination_text, false, SPLICE_HALO, TEXT_FIXED, termination_guarded, false},
    {finish_point, false, SPLICE_OWN, TEXT_FINISH_OWN, nullptr, false},
    {finish_point, false, SPLICE_HALO, TEXT_FINISH_HALO, nullptr, false},
    {visible_test, false, SPLICE_HALO, TEXT_VISIBLE, nullptr, false},
    {shading_gradient_text, false, SPLICE_ALL, TEXT_SHADING_GRADIENT, shading_gradient_kept, true},
};
const int first_unit = 20;    /* libhalo's images: above the units VTK's volume mapper takes */
const int gradient_unit = 19; /* the adapter's gradient texture: the binding in conversions */

/* Our functions: VTK's conventions to the host contract's (docs/hosts/vtk.md). */
const char conversions[] =
    "// ---- libhalo-vtk: VTK's conventions to the host contract's ----\n"
    "// value: VTK's scalar is normalised over the input's range; halo_vtk_window maps the\n"
    "// window's ends (in that normalisation) to 0 and 1\n"
    "float halo_vtk_value(vec4 scalar) {\n"
    "    return (scalar.r - halo_vtk_window.x) / (halo_vtk_window.y - halo_vtk_window.x);\n"
    "}\n"
    "// the contract's gradient: central differences over +-1 voxel, halved, of the value, at\n"
    "// the points (the adapter computes them once a volume), filtered as VTK's volume\n"
    "layout(binding = 19) uniform sampler3D halo_vtk_gradient_texture;\n"
    "vec3 halo_vtk_gradient(vec3 p) { return texture(halo_vtk_gradient_texture, p).rgb; }\n"
    "// VTK's own gradient with its shading on, kept by computeLighting (halo_vtk_sample_gradient)\n"
    "vec4 halo_vtk_shading_gradient = vec4(0.0);\n"
    "// the whole dataset's texture space: a piece of it (a brick of a distributed volume, ParaView)\n"
    "// has its own texture space, which halo_vtk_global_scale and _offset map into the whole one\n"
    "vec3 halo_vtk_global(vec3 p) { return p * halo_vtk_global_scale + halo_vtk_global_offset; }\n"
    "// the eye in the (whole) texture space\n"
    "vec3 halo_vtk_eye() {\n"
    "    vec4 e = in_inverseTextureDatasetMatrix[0] * in_inverseVolumeMatrix[0] * vec4(in_cameraPos, 1.0);\n"
    "    return halo_vtk_global(e.xyz / e.w);\n"
    "}\n"
    "// towards the eye, along the ray (perspective and parallel), per voxel step like the gradient\n"
    "vec3 halo_vtk_view() {\n"
    "    vec3 d = g_dirStep * vec3(textureSize(in_volume[0], 0));\n"
    "    float l = dot(d, d);\n"
    "    return l > 0.0 ? -d * inversesqrt(l) : vec3(0.0);\n"
    "}\n"
    "// 0 at the front of the (whole) volume's bounding sphere (texture space), 1 at its back\n"
    "float halo_vtk_depth(vec3 p) {\n"
    "    const float radius = 0.8660254037844386;\n"
    "    vec3 eye = halo_vtk_eye();\n"
    "    p = halo_vtk_global(p);\n"
    "    return clamp((distance(eye, p) - (distance(eye, vec3(0.5)) - radius)) / (2.0 * radius), 0.0, 1.0);\n"
    "}\n"
    "// VTK's opacity is corrected for the sample distance: a = 1 - (1 - a_unit)^e\n"
    "float halo_vtk_exponent() { return in_sampleDistance / halo_vtk_unit_distance; }\n"
    "float halo_vtk_correct(float a, float e) {\n"
    "    float t = 1.0 - clamp(a, 0.0, 1.0);\n"
    "    return 1.0 - (t > 0.0 ? pow(t, e) : 0.0);\n"
    "}\n";

const halo_pieces_desc vtk_names = {
    /* position */ "halo_vtk_global(g_dataPos)",
    /* value */ "halo_vtk_value(scalar)",
    /* gradient */ "halo_vtk_sample_gradient(g_dataPos)",
    /* view */ "halo_vtk_view()",
    /* depth */ "halo_vtk_depth(g_dataPos)",
    /* fragcoord */ "gl_FragCoord.xy",
    /* color */ "g_srcColor",
    /* volume */ nullptr,
    /* gradient_texture */ nullptr,
    /* segmented */ 0,
    /* first_output_location */ 0,
};

} // namespace

struct halo_vtk {
    /* held until halo_vtk_remove: the application may delete its own references first */
    vtkSmartPointer<vtkGPUVolumeRayCastMapper> mapper;
    vtkSmartPointer<vtkVolume> volume;
    vtkSmartPointer<vtkOpenGLShaderProperty> property;
    vtkSmartPointer<vtkRenderer> renderer;
    halo_program *program = nullptr;
    std::string sample;       /* the replacement at the splice point */
    std::string declarations; /* the replacement at the declarations tag */
    unsigned mode = 0;        /* the splices' mode (splice_mode) */
    std::vector<std::string> uniforms;
    vtkSmartPointer<vtkCallbackCommand> observer;
    unsigned long observer_tag = 0;
    vtkSmartPointer<vtkCallbackCommand> start_observer; /* binds the gradient texture */
    unsigned long start_observer_tag = 0;
    int saved_gradient_binding = 0;
    std::vector<int> reserved_units; /* held in VTK's texture unit manager during the mapper's render */
    std::string last_source;         /* the fragment shader VTK built last */
    int last_handle = -1;
    int builds = 0;
    int took = 0;
    /* volumetric halos: drawn in depth segments by halo_vtk_mapper (libhalo's GL runtime) */
    int segmented = 0;
    halo_gl *gl = nullptr;
    halo_gl_frame *frame = nullptr;
    int width = 0, height = 0;
    unsigned framebuffer = 0, color = 0, blit_program = 0, blit_vao = 0;
    int program_handle = -1;
    unsigned host_color = 0, host_color_framebuffer = 0; /* VTK's image for the at=post passes */
    int host_color_width = 0, host_color_height = 0;
    const char *post_image = nullptr; /* the image the last at=post pass writes, or NULL */
    int failed = 0;                   /* a segmented draw failed (diagnostics in diag) */
    /* host contract 3 (a one_draw program): libhalo's march reads its own copy of the volume,
     * the value over the window in [0, 1] (R32F), remade when the input changes */
    int one_draw = 0;
    double window_data[2] = {0, 1};                   /* the window in the input's units */
    unsigned value_texture = 0, gradient_texture = 0; /* the gradient: RGBA16F, also the stages' in VTK */
    bool own_gradient = false;                        /* halo_vtk_desc.own_gradient: never VTK's shading gradient */
    vtkMTimeType value_time = 0;
    int value_version = 0, value_size[3] = {0, 0, 0};
    halo_diagnostics *diag = nullptr; /* the install's: GL errors of the segmented draws */
    /* a piece of a larger volume (halo_vtk_set_whole_extent): the whole point extent */
    int whole[6] = {0, -1, 0, -1, 0, -1};
    halo_vtk_exchange_fn exchange = nullptr; /* halo_vtk_set_exchange */
    void *exchange_user = nullptr;
    std::vector<float> exchange_buffer;
    /* drawn once: the scene linked at the install with halo images at 1/2 and 1/4 too (the
     * scene may be gone later), taken when a frame's halo field is over its cap
     * (relink_smaller); that cap */
    int image_scale = 1;
    halo_program *smaller[2] = {nullptr, nullptr};
    size_t field_max_bytes = 0;
    int one_draw_linked = 0; /* linked with one_draw */
};

namespace
{

/* A splice's replacement text for this install. */
std::string replacement(const halo_vtk *h, const splice &sp)
{
    switch (sp.kind) {
    case TEXT_DECLARATIONS:
        return h->declarations;
    case TEXT_SAMPLE:
        return h->sample;
    case TEXT_VISIBLE:
        return halo_program_reflection(h->program).sampler_count ? visible_test_images : visible_test_guarded;
    case TEXT_FINISH_OWN:
        return std::string(piece_clamp) + finish_point;
    case TEXT_FINISH_HALO:
        return std::string(piece_clamp) + finish_text;
    case TEXT_SHADING_GRADIENT:
        return h->own_gradient ? shading_gradient_text : sp.fixed;
    case TEXT_FIXED:
        break;
    }
    return sp.fixed;
}

/* The live installs (a second one on the same mapper or volume is refused). */
std::vector<halo_vtk *> &installs()
{
    static std::vector<halo_vtk *> list;
    return list;
}

void add_error(halo_diagnostics *diag, halo_message_id id, const std::string &text)
{
    halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, id, nullptr, 0, 0, nullptr, "%s", text.c_str());
}

/* h is a live install: not NULL and not removed (a removed handle's memory is gone; its
 * address is compared, never read). Otherwise one USAGE diagnostic naming the call. */
bool installed(const halo_vtk *h)
{
    for (const halo_vtk *other : installs())
        if (other == h)
            return true;
    return false;
}

bool live_install(const halo_vtk *h, const char *call, halo_diagnostics *diag)
{
    if (installed(h))
        return true;
    add_error(diag, HALO_MSG_USAGE,
              std::string(call) + (h ? ": this halo_vtk was removed (halo_vtk_remove) or never installed"
                                     : ": the halo_vtk is NULL (halo_vtk_install failed: its diagnostics say why)"));
    return false;
}

/* Uploads one engine uniform as a VTK custom uniform; arrays padded to their size so that
 * VTK's declaration never changes (a change would rebuild the shader). */
void set_uniform(vtkUniforms *u, const halo_uniform_decl &d, std::vector<std::string> *names)
{
    if (d.name) {
        int comps = d.components, n = d.array_size ? d.array_size : 1;
        if (!strcmp(d.glsl_type, "int")) {
            std::vector<int> v((size_t)n * comps, 0);
            for (int k = 0; k < n * comps && d.count > 0; k++)
                v[(size_t)k] = (int)d.value[k < d.count * comps ? k : d.count * comps - 1];
            if (d.array_size)
                u->SetUniform1iv(d.name, n, v.data());
            else
                u->SetUniformi(d.name, v[0]);
        } else {
            std::vector<float> v((size_t)n * comps, 0.0f);
            for (int k = 0; k < n * comps; k++) {
                int from = k < d.count * comps ? k : (d.count - 1) * comps + k % comps;
                v[(size_t)k] = d.count > 0 ? (float)d.value[from] : 0.0f;
            }
            u->SetUniform(d.name,
                          comps == 1 && !d.array_size ? vtkUniforms::TupleTypeScalar : vtkUniforms::TupleTypeVector,
                          comps, v);
        }
        if (names)
            names->push_back(d.name);
    }
    if (d.count_name) {
        u->SetUniformi(d.count_name, d.count);
        if (names)
            names->push_back(d.count_name);
    }
}

void upload_all(halo_vtk *h, std::vector<std::string> *names)
{
    vtkUniforms *u = h->property->GetFragmentCustomUniforms();
    const halo_reflection r = halo_program_reflection(h->program);
    for (size_t i = 0; i < r.declaration_count; ++i)
        set_uniform(u, r.declarations[i], names);
}

/* Notes the program VTK drew the volume with, and whether the stages are in it. */
void note_program(halo_vtk *h, vtkShaderProgram *program)
{
    if (!program || !program->GetFragmentShader())
        return;
    if (program->GetFragmentShader()->GetSource().find("g_srcColor") == std::string::npos)
        return;
    int handle = program->GetHandle();
    if (handle == h->last_handle)
        return;
    h->last_handle = handle;
    h->last_source = program->GetFragmentShader()->GetSource();
    h->took = h->last_source.find(halo_program_source(h->program, HALO_PIECE_SAMPLE)) != std::string::npos;
    h->builds++;
}

/* The adapter's textures of the input, one texel per point as VTK's own volume texture,
 * remade when the input or its scalars change: the contract's gradient (RGBA16F, what the
 * stages read in VTK's shader and libhalo's march) and, with value (host contract 3), the
 * contract's value (the input's scalar over the window: R32F), which the march samples.
 * The gradient's name, or 0 after a diagnostic. */
unsigned volume_textures(halo_vtk *h, vtkImageData *image, int value)
{
    /* the array the mapper renders (its scalar mode and selected array, as VTK's own texture) */
    int cells = 0;
    vtkDataArray *scalars =
        vtkAbstractMapper::GetScalars(image, h->mapper->GetScalarMode(), h->mapper->GetArrayAccessMode(),
                                      h->mapper->GetArrayId(), h->mapper->GetArrayName(), cells);
    if (!scalars || cells) {
        if (!h->failed)
            add_error(h->diag, HALO_MSG_ENGINE_UNSUPPORTED,
                      cells ? "libhalo-vtk: the mapper renders cell data: libhalo's march and gradient take point "
                              "scalars"
                            : "libhalo-vtk: the mapper's input has no scalars to render");
        return 0;
    }
    vtkMTimeType t = std::max(image->GetMTime(), scalars->GetMTime());
    int dims[3];
    image->GetDimensions(dims);
    if (h->gradient_texture && (h->value_texture || !value) && t == h->value_time &&
        !memcmp(dims, h->value_size, sizeof dims))
        return h->gradient_texture;
    GLint max3d = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3d);
    if (dims[0] < 1 || dims[1] < 1 || dims[2] < 1 || dims[0] > max3d || dims[1] > max3d || dims[2] > max3d) {
        add_error(h->diag, HALO_MSG_ENGINE_UNSUPPORTED,
                  "libhalo-vtk: the volume's " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" +
                      std::to_string(dims[2]) + " points exceed this context's 3D texture size (" +
                      std::to_string(max3d) + ") for the halo field's march");
        return 0;
    }
    size_t n = (size_t)dims[0] * (size_t)dims[1] * (size_t)dims[2];
    std::vector<float> values(n);
    double w0 = h->window_data[0], scale = 1.0 / (h->window_data[1] - h->window_data[0]);
    for (size_t i = 0; i < n; i++)
        values[i] = (float)((scalars->GetComponent((vtkIdType)i, 0) - w0) * scale);
    /* the contract's gradient at the points: central differences, clamped at the borders as
     * a CLAMP_TO_EDGE read of the values, halved (what halo_vtk_gradient reads at a point) */
    std::vector<float> gradient(4 * n);
    const size_t stride[3] = {1, (size_t)dims[0], (size_t)dims[0] * (size_t)dims[1]};
    size_t i = 0;
    for (int z = 0; z < dims[2]; z++)
        for (int y = 0; y < dims[1]; y++)
            for (int x = 0; x < dims[0]; x++, i++) {
                const int at[3] = {x, y, z};
                for (int a = 0; a < 3; a++) {
                    size_t up = at[a] + 1 < dims[a] ? i + stride[a] : i, down = at[a] > 0 ? i - stride[a] : i;
                    gradient[4 * i + (size_t)a] = 0.5f * (values[up] - values[down]);
                }
                gradient[4 * i + 3] = 0.0f;
            }
    if (!h->value_texture && value)
        glGenTextures(1, &h->value_texture);
    if (!h->gradient_texture)
        glGenTextures(1, &h->gradient_texture);
    GLint saved = 0;
    glGetIntegerv(GL_TEXTURE_BINDING_3D, &saved);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    for (int k = h->value_texture ? 0 : 1; k < 2; k++) {
        glBindTexture(GL_TEXTURE_3D, k ? h->gradient_texture : h->value_texture);
        if (k)
            glTexImage3D(GL_TEXTURE_3D, 0, GL_RGBA16F, dims[0], dims[1], dims[2], 0, GL_RGBA, GL_FLOAT,
                         gradient.data());
        else
            glTexImage3D(GL_TEXTURE_3D, 0, GL_R32F, dims[0], dims[1], dims[2], 0, GL_RED, GL_FLOAT, values.data());
        glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
            glTexParameteri(GL_TEXTURE_3D, wrap, GL_CLAMP_TO_EDGE);
    }
    glBindTexture(GL_TEXTURE_3D, (GLuint)saved);
    h->value_time = t;
    memcpy(h->value_size, dims, sizeof dims);
    h->value_version++;
    return h->gradient_texture;
}

/* Before VTK's mapper renders (every path: VTK alone, one draw, segments): the gradient
 * texture on its unit, made or remade first; the unit's binding is restored after. */
/* The texture units the adapter binds by number (the gradient's, and with the halo mapper
 * libhalo's images from first_unit on), held in the window's texture unit manager from
 * the mapper's render start to its end, so that the textures VTK activates meanwhile
 * take other units. A unit already held is a collision: refused with a message. */
const int reserved_halo_units = 12; /* first_unit and the frame's images after it */
int reserve_units(halo_vtk *h)
{
    vtkOpenGLRenderWindow *window =
        h->renderer ? vtkOpenGLRenderWindow::SafeDownCast(h->renderer->GetRenderWindow()) : nullptr;
    vtkTextureUnitManager *units = window ? window->GetTextureUnitManager() : nullptr;
    if (!units)
        return 1;
    int last = h->segmented ? first_unit + reserved_halo_units - 1 : gradient_unit;
    if (last >= units->GetNumberOfTextureUnits())
        last = units->GetNumberOfTextureUnits() - 1;
    for (int u = gradient_unit; u <= last; u++) {
        if (units->IsAllocated(u)) {
            if (!h->failed)
                add_error(h->diag, HALO_MSG_ENGINE_UNSUPPORTED,
                          "libhalo-vtk: texture unit " + std::to_string(u) +
                              " is held in VTK's texture unit manager when the volume renders; the adapter binds "
                              "its textures on units " +
                              std::to_string(gradient_unit) + " to " + std::to_string(last) + " (docs/hosts/vtk.md)");
            h->failed = 1;
            return 0;
        }
        if (units->Allocate(u) == u)
            h->reserved_units.push_back(u);
    }
    return 1;
}

void release_units(halo_vtk *h)
{
    vtkOpenGLRenderWindow *window =
        h->renderer ? vtkOpenGLRenderWindow::SafeDownCast(h->renderer->GetRenderWindow()) : nullptr;
    vtkTextureUnitManager *units = window ? window->GetTextureUnitManager() : nullptr;
    for (int u : h->reserved_units)
        if (units && units->IsAllocated(u))
            units->Free(u);
    h->reserved_units.clear();
}

void on_render_start(vtkObject *, unsigned long, void *client, void *)
{
    halo_vtk *h = static_cast<halo_vtk *>(client);
    release_units(h); /* a render that did not end (an exception in VTK) */
    reserve_units(h);
    vtkImageData *image = vtkImageData::SafeDownCast(h->mapper->GetInput());
    GLint active = GL_TEXTURE0;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    unsigned gradient = image ? volume_textures(h, image, h->one_draw) : 0;
    if (!gradient)
        h->failed = 1;
    glActiveTexture(GL_TEXTURE0 + gradient_unit);
    glGetIntegerv(GL_TEXTURE_BINDING_3D, &h->saved_gradient_binding);
    glBindTexture(GL_TEXTURE_3D, gradient);
    glActiveTexture((GLenum)active);
}

/* After the mapper's render, the ray-casting program is the one the render window's
 * shader cache bound last (VTK 9.1 sends no UpdateShaderEvent from the volume mapper). */
void on_render_end(vtkObject *, unsigned long, void *client, void *)
{
    halo_vtk *h = static_cast<halo_vtk *>(client);
    release_units(h);
    GLint active = GL_TEXTURE0;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    glActiveTexture(GL_TEXTURE0 + gradient_unit);
    glBindTexture(GL_TEXTURE_3D, (GLuint)h->saved_gradient_binding);
    glActiveTexture((GLenum)active);
    vtkOpenGLRenderWindow *window =
        h->renderer ? vtkOpenGLRenderWindow::SafeDownCast(h->renderer->GetRenderWindow()) : nullptr;
    if (window)
        note_program(h, window->GetShaderCache()->GetLastShaderBound());
}

} // namespace


/* ---- Volumetric halos: VTK's mapper drawn once per depth segment ---- */

namespace
{

void *gl_proc(const char *name)
{
    static void *(*get)(const unsigned char *) = nullptr;
    if (!get)
        get = (void *(*)(const unsigned char *))dlsym(RTLD_DEFAULT, "glXGetProcAddressARB");
    void *p = get ? get((const unsigned char *)name) : nullptr;
    return p ? p : dlsym(RTLD_DEFAULT, name);
}

/* The box of the texture space the segments and the stages use: the input's points, or
 * the whole dataset's (halo_vtk_set_whole_extent). A texture coordinate t in [0,1]^3
 * covers the cells around the points: world = origin + (first + t n - 1/2) spacing. */
void texture_box(const halo_vtk *h, vtkImageData *image, int first[3], int n[3])
{
    int extent[6];
    image->GetExtent(extent);
    const int *box = h->whole[1] >= h->whole[0] ? h->whole : extent;
    for (int a = 0; a < 3; a++) {
        first[a] = box[2 * a];
        n[a] = box[2 * a + 1] - box[2 * a] + 1;
    }
}

/* The uniforms that map the input's texture space into the whole one: identity unless
 * the input is a piece (halo_vtk_set_whole_extent). */
void update_global(halo_vtk *h)
{
    vtkImageData *image = vtkImageData::SafeDownCast(h->mapper->GetInput());
    float scale[3] = {1, 1, 1}, offset[3] = {0, 0, 0};
    if (image && h->whole[1] >= h->whole[0]) {
        int extent[6], first[3], n[3];
        image->GetExtent(extent);
        texture_box(h, image, first, n);
        for (int a = 0; a < 3; a++) {
            scale[a] = (float)(extent[2 * a + 1] - extent[2 * a] + 1) / (float)n[a];
            offset[a] = (float)(extent[2 * a] - first[a]) / (float)n[a];
        }
    }
    vtkUniforms *u = h->property->GetFragmentCustomUniforms();
    u->SetUniform3f("halo_vtk_global_scale", scale);
    u->SetUniform3f("halo_vtk_global_offset", offset);
    u->SetUniformi("halo_vtk_piece", h->whole[1] >= h->whole[0]);
    /* the whole volume's box of points (VTK's rays start one step inside it), texture space */
    float lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    if (image && h->whole[1] >= h->whole[0]) {
        int first[3], n[3];
        texture_box(h, image, first, n);
        for (int a = 0; a < 3; a++) {
            lo[a] = 0.5f / (float)n[a];
            hi[a] = 1.0f - 0.5f / (float)n[a];
        }
    }
    u->SetUniform3f("halo_vtk_box_lo", lo);
    u->SetUniform3f("halo_vtk_box_hi", hi);
}

/* clip space -> the (whole) volume texture space, column-major: libhalo's segment planes
 * are in the space of the ray positions the segments get (halo_vtk_global(g_dataPos)) */
void texture_from_clip(const halo_vtk *h, vtkRenderer *ren, vtkVolume *vol, vtkImageData *image, float out[16])
{
    int first[3], n[3];
    double spacing[3], origin[3];
    texture_box(h, image, first, n);
    image->GetSpacing(spacing);
    image->GetOrigin(origin);
    vtkNew<vtkMatrix4x4> t2d;
    for (int a = 0; a < 3; a++) {
        t2d->SetElement(a, a, n[a] * spacing[a]);
        t2d->SetElement(a, 3, origin[a] + (first[a] - 0.5) * spacing[a]);
    }
    vtkNew<vtkMatrix4x4> t2w, t2c, c2t;
    vtkMatrix4x4::Multiply4x4(vol->GetMatrix(), t2d, t2w);
    double aspect[2];
    ren->ComputeAspect();
    ren->GetAspect(aspect);
    vtkMatrix4x4 *w2c = ren->GetActiveCamera()->GetCompositeProjectionTransformMatrix(aspect[0] / aspect[1], -1, 1);
    vtkMatrix4x4::Multiply4x4(w2c, t2w, t2c);
    vtkMatrix4x4::Invert(t2c, c2t);
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++)
            out[c * 4 + r] = (float)c2t->GetElement(r, c);
}

/* The image plane's axes (halo_host_screen_right, _up: directional halos) in the space
 * of the adapter's view and gradient, voxel index space. */
void set_screen_axes(vtkRenderer *ren, vtkVolume *vol, vtkImageData *image, unsigned program)
{
    double spacing[3], up[3], dop[3], right[3];
    image->GetSpacing(spacing);
    vtkCamera *camera = ren->GetActiveCamera();
    camera->GetViewUp(up);
    camera->GetDirectionOfProjection(dop);
    right[0] = dop[1] * up[2] - dop[2] * up[1];
    right[1] = dop[2] * up[0] - dop[0] * up[2];
    right[2] = dop[0] * up[1] - dop[1] * up[0];
    /* index = inverse(volume matrix * diag(spacing)) world, for directions */
    vtkNew<vtkMatrix4x4> i2w, w2i;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            i2w->SetElement(r, c, vol->GetMatrix()->GetElement(r, c) * spacing[c]);
    vtkMatrix4x4::Invert(i2w, w2i);
    const char *names[2] = {"halo_host_screen_right", "halo_host_screen_up"};
    const double *axes[2] = {right, up};
    GLint saved = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &saved);
    glUseProgram(program);
    for (int k = 0; k < 2; k++) {
        double v[3], n = 0.0;
        for (int r = 0; r < 3; r++) {
            v[r] = w2i->GetElement(r, 0) * axes[k][0] + w2i->GetElement(r, 1) * axes[k][1] +
                   w2i->GetElement(r, 2) * axes[k][2];
            n += v[r] * v[r];
        }
        n = n > 0.0 ? 1.0 / std::sqrt(n) : 0.0;
        GLint at = glGetUniformLocation(program, names[k]);
        if (at >= 0)
            glUniform3f(at, (float)(v[0] * n), (float)(v[1] * n), (float)(v[2] * n));
    }
    glUseProgram((GLuint)saved);
}

GLuint compile(GLenum type, const char *text)
{
    GLuint sh = glCreateShader(type);
    glShaderSource(sh, 1, &text, nullptr);
    glCompileShader(sh);
    return sh;
}

/* texture over VTK's framebuffer (premultiplied, or replacing it): one full-screen triangle */
void blit(halo_vtk *h, unsigned texture, int blend)
{
    if (!h->blit_program) {
        const char *vs =
            "#version 150\nout vec2 uv;\nvoid main() {\n"
            "    vec2 c = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));\n"
            "    uv = c; gl_Position = vec4(c * 2.0 - 1.0, 0.0, 1.0);\n}\n";
        const char *fs =
            "#version 150\nin vec2 uv;\nout vec4 color;\nuniform sampler2D image;\n"
            "void main() { color = texture(image, uv); }\n";
        GLuint v = compile(GL_VERTEX_SHADER, vs), f = compile(GL_FRAGMENT_SHADER, fs);
        h->blit_program = glCreateProgram();
        glAttachShader(h->blit_program, v);
        glAttachShader(h->blit_program, f);
        glBindFragDataLocation(h->blit_program, 0, "color");
        glLinkProgram(h->blit_program);
        glDeleteShader(v);
        glDeleteShader(f);
        glGenVertexArrays(1, &h->blit_vao);
    }
    glUseProgram(h->blit_program);
    glActiveTexture(GL_TEXTURE0 + first_unit);
    glBindTexture(GL_TEXTURE_2D, texture);
    glUniform1i(glGetUniformLocation(h->blit_program, "image"), first_unit);
    glBindVertexArray(h->blit_vao);
    glDisable(GL_DEPTH_TEST);
    if (blend) {
        glEnable(GL_BLEND);
        glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    } else {
        glDisable(GL_BLEND);
    }
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindTexture(GL_TEXTURE_2D, 0);
}

} // namespace

/* The mapper for volumetric halos (halo_vtk_mapper_new): VTK's own, drawn by libhalo's
 * runtime once per depth segment into libhalo's frame, the passes run between, and the
 * result composited over VTK's framebuffer. */
class haloVTKMapper : public vtkOpenGLGPUVolumeRayCastMapper
{
  public:
    static haloVTKMapper *New();
    vtkTypeMacro(haloVTKMapper, vtkOpenGLGPUVolumeRayCastMapper);
    halo_vtk *halo = nullptr;
    vtkRenderer *draw_renderer = nullptr;
    vtkVolume *draw_volume = nullptr;

  protected:
    void GPURender(vtkRenderer *ren, vtkVolume *vol) override;
    static void draw(void *user);
};
vtkStandardNewMacro(haloVTKMapper);

namespace
{

/* The linked program's pieces, and what it draws with halo_vtk_mapper_new's mapper (in
 * segments, over the field drawn once, the at=post passes' image). */
void take_program(halo_vtk *h, halo_program *program)
{
    h->program = program;
    h->declarations = std::string(declarations_tag) + "\n" + conversions + "const bool halo_vtk_reads_images = " +
                      (halo_program_reflection(program).sampler_count ? "true" : "false") + ";\n" +
                      halo_program_source(program, HALO_PIECE_DECLARATIONS);
    h->sample = std::string(
                    "// ---- libhalo-vtk: the stages, on the opacity per unit distance ----\n"
                    "g_srcColor.a = halo_vtk_correct(g_srcColor.a, 1.0 / halo_vtk_exponent());\n") +
                sample_gradient + halo_program_source(program, HALO_PIECE_SAMPLE) + sample_gradient_used +
                "g_srcColor.a = halo_vtk_correct(g_srcColor.a, halo_vtk_exponent());\n" + splice_point;
    h->segmented = h->one_draw = 0;
    h->post_image = nullptr;
    if (!haloVTKMapper::SafeDownCast(h->mapper))
        return;
    halo_reflection r = halo_program_reflection(program);
    h->segmented = r.output_count || r.pass_count;
    for (size_t i = 0; i < r.pass_count && h->one_draw_linked; i++)
        h->one_draw |= !r.passes[i].at; /* passes between slices: the field */
    for (size_t i = 0; i < r.pass_count; i++)
        if (r.passes[i].at)
            h->post_image = r.passes[i].output;
}

/* The replacements of h's splices in VTK's shader: with add, those of h's mode set (a text
 * set again replaces its old replacement); without, every VTK text of the table cleared
 * once (clearing one that is not there does nothing). */
void replace_splices(halo_vtk *h, bool add)
{
    for (size_t i = 0; !add && i < sizeof splices / sizeof splices[0]; i++) {
        bool seen = false;
        for (size_t k = 0; k < i; k++)
            seen |= splices[k].vtk_text == splices[i].vtk_text;
        if (!seen)
            h->property->ClearFragmentShaderReplacement(splices[i].vtk_text, splices[i].all);
    }
    for (const splice &sp : splices)
        if (add && (sp.modes & h->mode))
            h->property->AddFragmentShaderReplacement(sp.vtk_text, sp.all, replacement(h, sp), false);
}

/* A frame drawn once whose halo field is over its cap (FIELD_MEMORY): the scene linked
 * again with halo images at twice the scale (at most 4), the live values set since the
 * install kept, the replacements and uniforms replaced, the frame made again; VTK builds
 * its shader anew at the next draw. false when it cannot (already at 1/4). */
bool relink_smaller(halo_vtk *h)
{
    /* smaller[0] halves the install's scale, smaller[1] halves it again */
    int k = 0;
    while (k < 2 && !h->smaller[k])
        k++;
    halo_program *program = k < 2 && h->one_draw ? h->smaller[k] : nullptr;
    if (!program)
        return false;
    h->smaller[k] = nullptr;
    halo_reflection r = halo_program_reflection(h->program);
    for (size_t i = 0; i < r.uniform_count; i++)
        if (r.uniforms[i].live) /* count: elements (halo_program_set) */
            halo_program_set(program, r.uniforms[i].stage, r.uniforms[i].param, r.uniforms[i].value,
                             r.uniforms[i].count, h->diag);
    halo_program_destroy(h->program);
    h->image_scale = halo_program_reflection(program).image_scale;
    take_program(h, program);
    replace_splices(h, true);
    upload_all(h, nullptr);
    halo_gl_frame_destroy(h->frame);
    h->frame = nullptr;
    h->program_handle = -1;
    return true;
}

} // namespace

/* Volumetric halos across pieces (halo_vtk_set_exchange): after a segment, each output
 * image the pieces drew (the seeds) combined over all pieces by its blend, so that every
 * piece spreads the same seeds; done before the passes run on them. */
static void exchange_outputs(halo_vtk *h)
{
    for (size_t i = 0; i < halo_program_reflection(h->program).output_count; i++) {
        const halo_output_info *o = &halo_program_reflection(h->program).outputs[i];
        unsigned texture = halo_gl_frame_texture(h->frame, o->image);
        if (!texture)
            continue;
        size_t count = (size_t)h->width * (size_t)h->height * 4;
        h->exchange_buffer.resize(count);
        GLint saved = 0;
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &saved);
        glBindTexture(GL_TEXTURE_2D, texture);
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, h->exchange_buffer.data());
        h->exchange(h->exchange_user, h->exchange_buffer.data(), count, o->blend);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, h->width, h->height, GL_RGBA, GL_FLOAT, h->exchange_buffer.data());
        glBindTexture(GL_TEXTURE_2D, (GLuint)saved);
    }
}

void haloVTKMapper::draw(void *user)
{
    haloVTKMapper *m = static_cast<haloVTKMapper *>(user);
    halo_vtk *h = m->halo;
    /* one fragment per pixel: each target written this segment starts from zero, so that
     * VTK's blending of the volume leaves the shader's values as they are */
    static const float zero[4] = {0, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, zero);
    int state = halo_program_reflection(h->program).segment_location;
    if (state > 0)
        glClearBufferfv(GL_COLOR, state, zero);
    vtkOpenGLRenderWindow *win = vtkOpenGLRenderWindow::SafeDownCast(m->draw_renderer->GetRenderWindow());
    win->GetState()->Reset(); /* VTK's state cache: what libhalo bound is current */
    m->vtkOpenGLGPUVolumeRayCastMapper::GPURender(m->draw_renderer, m->draw_volume);
    note_program(h, win->GetShaderCache()->GetLastShaderBound());
    if (h->exchange && !h->one_draw)
        exchange_outputs(h); /* drawn once: the seeds' exchange is libhalo's */
    win->GetState()->Reset();
}

void haloVTKMapper::GPURender(vtkRenderer *ren, vtkVolume *vol)
{
    halo_vtk *h = this->halo;
    if (h)
        update_global(h);
    if (!h || !h->segmented) {
        this->vtkOpenGLGPUVolumeRayCastMapper::GPURender(ren, vol);
        return;
    }
    vtkOpenGLRenderWindow *win = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
    vtkOpenGLState *ostate = win->GetState();
    int w, h_, x0, y0;
    ren->GetTiledSizeAndOrigin(&w, &h_, &x0, &y0);
    const int *tile = win->GetTileScale();
    if (tile[0] > 1 || tile[1] > 1) {
        /* an image larger than the window, drawn in tiles (vtkWindowToImageFilter's scale, a
         * ParaView screenshot above the view's size): the image passes of one tile would see
         * nothing beyond its edge (seams at the tiles' borders); the volume is not drawn */
        if (!h->failed)
            add_error(h->diag, HALO_MSG_ENGINE_UNSUPPORTED,
                      "libhalo-vtk: VTK is rendering in " + std::to_string(tile[0]) + "x" + std::to_string(tile[1]) +
                          " tiles (an image larger than the window); the scene's image passes (volumetric halos, "
                          "outlines) need the whole image: render the window at the size wanted instead "
                          "(docs/hosts/vtk.md)");
        h->failed = 1;
        return;
    }
    if (!h->gl) {
        halo_gl_desc gd = {};
        gd.get_proc_address = gl_proc;
        gd.readback = HALO_GL_READBACK_AUTO;
        h->gl = halo_gl_create(&gd, h->diag);
        if (!h->gl)
            return;
    }
    ostate->Push();
    ostate->PushFramebufferBindings();
    GLint vtk_framebuffer = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &vtk_framebuffer);
    if (!h->frame || w != h->width || h_ != h->height) {
        halo_gl_frame_destroy(h->frame);
        h->frame = halo_gl_frame_create(h->gl, h->program, w, h_, h->diag);
        if (!h->color)
            glGenTextures(1, &h->color);
        glBindTexture(GL_TEXTURE_2D, h->color);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA16F, w, h_, 0, GL_RGBA, GL_FLOAT, nullptr);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glBindTexture(GL_TEXTURE_2D, 0);
        if (!h->framebuffer)
            glGenFramebuffers(1, &h->framebuffer);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, h->framebuffer);
        glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, h->color, 0);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)vtk_framebuffer);
        h->width = w;
        h->height = h_;
    }
    if (!h->frame) {
        ostate->PopFramebufferBindings();
        ostate->Pop();
        return;
    }
    this->halo = h;
    this->draw_renderer = ren;
    this->draw_volume = vol;
    glViewport(0, 0, w, h_);
    if (h->program_handle < 0) {
        /* VTK builds its shader on its first draw: one draw to learn the program, its image
         * discarded. libhalo's samplers are not set yet (all on unit 0: the field's
         * sampler2DArray beside sampler2D images is an invalid draw, which VTK would report
         * as a warning); halo_gl_frame_draw sets them before every draw that counts. */
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, h->framebuffer);
        ostate->Reset();
        int warnings = vtkObject::GetGlobalWarningDisplay();
        if (h->one_draw)
            vtkObject::GlobalWarningDisplayOff();
        this->vtkOpenGLGPUVolumeRayCastMapper::GPURender(ren, vol);
        vtkObject::SetGlobalWarningDisplay(warnings);
        while (glGetError() != GL_NO_ERROR) {}
        vtkShaderProgram *prog = win->GetShaderCache()->GetLastShaderBound();
        note_program(h, prog);
        h->program_handle = prog ? prog->GetHandle() : 0;
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)vtk_framebuffer);
    }
    vtkImageData *image = vtkImageData::SafeDownCast(this->GetInput());
    float inverse[16];
    texture_from_clip(h, ren, vol, image, inverse);
    int first[3], dims[3];
    double spacing[3];
    texture_box(h, image, first, dims);
    image->GetSpacing(spacing);
    halo_gl_segments_desc sd = {};
    sd.inverse_view_projection = inverse;
    sd.step = (float)(this->GetSampleDistance() / (dims[0] * spacing[0]));
    sd.framebuffer = h->framebuffer;
    sd.first_unit = first_unit + 1;
    sd.draw = &haloVTKMapper::draw;
    sd.user = this;
    if (h->one_draw) {
        /* a piece of a larger volume (halo_vtk_set_whole_extent): its march reads this piece,
         * which covers its texels' part of the whole volume's texture space, and the seeds of
         * every segment are combined across the pieces once a frame (halo_vtk_set_exchange) */
        int extent[6], piece = 0;
        image->GetExtent(extent);
        for (int a = 0; a < 3; a++) {
            int n = extent[2 * a + 1] - extent[2 * a] + 1;
            piece |= extent[2 * a] != first[a] || n != dims[a];
            sd.piece_min[a] = (float)(extent[2 * a] - first[a]) / (float)dims[a];
            sd.piece_max[a] = (float)(extent[2 * a] - first[a] + n) / (float)dims[a];
        }
        /* this frame's refusals (h->failed keeps that one happened, for halo_vtk_check) */
        int refused = 0;
        if (!piece) {
            memset(sd.piece_min, 0, sizeof sd.piece_min);
            memset(sd.piece_max, 0, sizeof sd.piece_max);
        } else if (!h->exchange) {
            if (!h->failed)
                add_error(h->diag, HALO_MSG_ENGINE_UNSUPPORTED,
                          "libhalo-vtk: volumetric halos on a piece of a larger volume need the other pieces' seeds: "
                          "set halo_vtk_set_exchange (docs/distributed.md)");
            refused = 1;
        } else {
            sd.exchange = h->exchange;
            sd.exchange_user = h->exchange_user;
        }
        unsigned made = refused ? 0 : volume_textures(h, image, 1);
        if (!made || !h->value_texture) {
            h->failed = 1;
            ostate->PopFramebufferBindings();
            ostate->Pop();
            return;
        }
        sd.volume_texture = h->value_texture;
        sd.gradient_texture = h->gradient_texture;
        sd.volume_version = h->value_version;
        memcpy(sd.volume_size, h->value_size, sizeof sd.volume_size);
    }
    set_screen_axes(ren, vol, image, (unsigned)h->program_handle);
    sd.field_max_bytes = h->field_max_bytes;
    /* a field over its cap (its diagnostic taken apart): linked again with smaller halo
     * images, with a warning, and this frame drawn anew (nothing of it drawn yet) */
    halo_diagnostics *draw_diag = halo_diagnostics_create();
    halo_status drawn = halo_gl_frame_draw(h->frame, (unsigned)h->program_handle, &sd, draw_diag ? draw_diag : h->diag);
    int relinked = drawn != HALO_OK && draw_diag && halo_diagnostics_has(draw_diag, HALO_MSG_FIELD_MEMORY) &&
                   halo_diagnostics_describe(draw_diag).errors == 1 && relink_smaller(h);
    for (size_t i = 0; draw_diag && i < halo_diagnostics_describe(draw_diag).count; i++) {
        const halo_diagnostic *g = halo_diagnostics_get(draw_diag, i);
        if (relinked && g->id == HALO_MSG_FIELD_MEMORY)
            halo_diagnostics_report(h->diag, HALO_SEVERITY_WARNING, HALO_MSG_FIELD_MEMORY, nullptr, 0, 0, nullptr,
                                    "libhalo-vtk: %s: linked again with halo images at 1/%d "
                                    "(halo_vtk_desc.image_scale %d)",
                                    g->text, h->image_scale, h->image_scale);
        else
            halo_diagnostics_report(h->diag, g->severity, g->id, g->file, g->line, g->column, g->source_line, "%s",
                                    g->text);
    }
    halo_diagnostics_destroy(draw_diag);
    if (relinked) {
        ostate->PopFramebufferBindings();
        ostate->Pop();
        this->GPURender(ren, vol);
        return;
    }
    if (drawn != HALO_OK)
        h->failed = 1;
    /* the volume over VTK's framebuffer */
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)vtk_framebuffer);
    glViewport(x0, y0, w, h_);
    blit(h, h->color, 1);
    if (h->post_image) {
        /* at=post passes (outlines): on VTK's whole image, which then shows their result */
        if (!h->host_color)
            glGenTextures(1, &h->host_color);
        glActiveTexture(GL_TEXTURE0 + first_unit);
        glBindTexture(GL_TEXTURE_2D, h->host_color);
        if (h->host_color_width != w || h->host_color_height != h_) {
            glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA16F, w, h_, 0, GL_RGBA, GL_FLOAT, nullptr);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            h->host_color_width = w;
            h->host_color_height = h_;
        }
        glBindTexture(GL_TEXTURE_2D, 0);
        /* VTK's image into the texture: resolved by a blit, since VTK's framebuffer may be
         * multisampled (a window's default), which glCopyTexSubImage2D cannot read */
        GLint read_framebuffer = 0;
        glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_framebuffer);
        if (!h->host_color_framebuffer)
            glGenFramebuffers(1, &h->host_color_framebuffer);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, h->host_color_framebuffer);
        glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, h->host_color, 0);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)vtk_framebuffer);
        glBlitFramebuffer(x0, y0, x0 + w, y0 + h_, 0, 0, w, h_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)read_framebuffer);
        halo_gl_frame_post(h->frame, h->host_color);
        unsigned result = halo_gl_frame_texture(h->frame, h->post_image);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)vtk_framebuffer);
        glViewport(x0, y0, w, h_);
        if (result)
            blit(h, result, 0);
        else
            h->failed = 1;
    }
    ostate->PopFramebufferBindings();
    ostate->Pop();
}

vtkGPUVolumeRayCastMapper *halo_vtk_mapper_new(void) { return haloVTKMapper::New(); }

halo_vtk *halo_vtk_install(const halo_vtk_desc *desc, halo_diagnostics *diag)
{
    if (!desc || !desc->mapper || !desc->volume || !desc->renderer || !desc->library) {
        add_error(diag, HALO_MSG_USAGE, "halo_vtk_install: mapper, volume, renderer and library are required");
        return nullptr;
    }
    vtkGPUVolumeRayCastMapper *mapper = desc->mapper;
    for (const halo_vtk *other : installs()) /* one install's replacements would clear the other's */
        if (other->mapper == mapper || other->volume == desc->volume) {
            add_error(diag, HALO_MSG_USAGE,
                      std::string("halo_vtk_install: this ") + (other->mapper == mapper ? "mapper" : "volume") +
                          " already has an install: halo_vtk_remove it first");
            return nullptr;
        }
    vtkOpenGLShaderProperty *property = vtkOpenGLShaderProperty::SafeDownCast(desc->volume->GetShaderProperty());
    if (!property) {
        add_error(diag, HALO_MSG_USAGE,
                  "halo_vtk_install: the volume has no OpenGL shader property (VTK's OpenGL2 "
                  "rendering module is not initialised: VTK_MODULE_INIT(vtkRenderingOpenGL2))");
        return nullptr;
    }
    /* What VTK's shader can take: one splice point, in composite mode with one component. */
    static const char *const modes[] = {
        "composite", "maximum intensity", "minimum intensity", "average intensity", "additive", "isosurface", "slice"};
    int mode = mapper->GetBlendMode();
    if (mode != vtkVolumeMapper::COMPOSITE_BLEND) {
        add_error(diag, HALO_MSG_ENGINE_UNSUPPORTED,
                  std::string("the VTK mapper's blend mode is ") + (mode >= 0 && mode < 7 ? modes[mode] : "unknown") +
                      ": libhalo's stages run only in composite blend mode, where VTK classifies and composites "
                      "each sample (docs/hosts/vtk.md, blend modes)");
        return nullptr;
    }
    vtkImageData *input = vtkImageData::SafeDownCast(mapper->GetInput());
    if (!input || !input->GetPointData() || !input->GetPointData()->GetScalars()) {
        add_error(diag, HALO_MSG_USAGE, "halo_vtk_install: set the mapper's input (point scalars) first");
        return nullptr;
    }
    int components = input->GetNumberOfScalarComponents();
    if (components != 1) {
        add_error(diag, HALO_MSG_ENGINE_UNSUPPORTED,
                  "the volume has " + std::to_string(components) +
                      " components: libhalo's stages take one scalar value per sample (docs/hosts/vtk.md)");
        return nullptr;
    }
    if (mapper->GetMaskInput()) {
        add_error(diag, HALO_MSG_ENGINE_UNSUPPORTED,
                  "the mapper has a mask input: VTK's masked shading has no splice point for libhalo's stages");
        return nullptr;
    }
    /* halo_vtk_mapper_new's mapper draws in depth segments: every stage; VTK's own, one pass */
    haloVTKMapper *segmenting = haloVTKMapper::SafeDownCast(mapper);
    halo_pieces_desc names = vtk_names;
    names.segmented = segmenting && desc->segments;
    names.first_output_location = 1; /* VTK's colour is fragOutput0 */
    halo_link_desc link = {};
    link.library = desc->library;
    link.scene = desc->scene;
    link.all_live = desc->all_live;
    link.target = HALO_TARGET_GLSL150;
    link.engine_uniforms = 1;
    link.output_locations = HALO_LOCATIONS_EXTENSION;
    link.pieces = &names;
    link.one_draw = segmenting && !desc->segments;
    link.image_scale = desc->image_scale;
    halo_program *program = halo_link(&link, diag);
    if (!program && !segmenting && halo_diagnostics_has(diag, HALO_MSG_HOST_SINGLE_PASS))
        halo_diagnostics_report(diag, HALO_SEVERITY_NOTE, HALO_MSG_HOST_SINGLE_PASS, nullptr, 0, 0, nullptr,
                                "in VTK: create the mapper with halo_vtk_mapper_new(), which draws VTK's volume "
                                "in depth segments (docs/hosts/vtk.md)");
    if (!program)
        return nullptr;
    if (!segmenting && (halo_program_reflection(program).output_count || halo_program_reflection(program).pass_count)) {
        std::string stages;
        for (size_t i = 0; i < halo_program_reflection(program).stage_count; i++)
            stages += (stages.empty() ? "" : ", ") + std::string(halo_program_reflection(program).stages[i].name);
        add_error(diag, HALO_MSG_HOST_SINGLE_PASS,
                  "the scene's stages (" + stages +
                      ") include some that write extra outputs or run image passes (volumetric halos, outlines, "
                      "feature halos): VTK's single-pass mapper cannot run them; create the mapper with "
                      "halo_vtk_mapper_new(), which draws it in depth segments (docs/hosts/vtk.md)");
        halo_program_destroy(program);
        return nullptr;
    }
    for (size_t i = 0; i < halo_program_reflection(program).host_uniform_count; i++) {
        const char *name = halo_program_reflection(program).host_uniforms[i].name;
        /* a segmentation is read only where the stage says so (halo_stage_info.labels_when) */
        int labels_unused = !strcmp(name, "halo_host_labels") && !halo_program_reflection(program).reads_labels;
        if (strcmp(name, "halo_host_screen_right") && strcmp(name, "halo_host_screen_up") && !labels_unused) {
            add_error(diag, HALO_MSG_ENGINE_UNSUPPORTED,
                      std::string("the scene's stages need the host uniform '") + name + "' (" +
                          halo_program_reflection(program).host_uniforms[i].meaning +
                          "): the VTK adapter does not provide it yet (docs/hosts/vtk.md)");
            halo_program_destroy(program);
            return nullptr;
        }
    }
    halo_validate_desc check{};
    check.program = program;
    if (halo_validate(&check, diag) != HALO_OK) {
        halo_program_destroy(program);
        return nullptr;
    }
    halo_vtk *h = new halo_vtk;
    h->mapper = mapper;
    h->volume = desc->volume;
    h->renderer = desc->renderer;
    h->property = property;
    h->program = program;
    h->diag = diag; /* the draws' diagnostics (GL errors, the adapter's textures) */
    h->own_gradient = desc->own_gradient != 0;
    h->field_max_bytes = desc->field_max_bytes;
    h->one_draw_linked = link.one_draw;
    h->image_scale = link.image_scale > 1 ? link.image_scale : 1;
    /* the value window, in VTK's normalisation over the input's range */
    double range[2];
    input->GetScalarRange(range);
    double w0 = desc->window[0], w1 = desc->window[1];
    if (!(w1 != w0)) {
        w0 = range[0];
        w1 = range[1];
    }
    h->window_data[0] = w0;
    h->window_data[1] = w1 != w0 ? w1 : w0 + 1.0;
    double span = range[1] > range[0] ? range[1] - range[0] : 1.0;
    float window[2] = {(float)((w0 - range[0]) / span), (float)((w1 - range[0]) / span)};
    if (window[1] == window[0])
        window[1] = window[0] + 1.0f;
    vtkUniforms *u = property->GetFragmentCustomUniforms();
    u->SetUniform2f("halo_vtk_window", window);
    h->uniforms.push_back("halo_vtk_window");
    vtkVolumeProperty *vp = desc->volume->GetProperty();
    double unit = vp ? vp->GetScalarOpacityUnitDistance() : 1.0;
    u->SetUniformf("halo_vtk_unit_distance", (float)(unit > 0.0 ? unit : 1.0));
    h->uniforms.push_back("halo_vtk_unit_distance");
    update_global(h);
    h->uniforms.push_back("halo_vtk_global_scale");
    h->uniforms.push_back("halo_vtk_global_offset");
    h->uniforms.push_back("halo_vtk_piece");
    h->uniforms.push_back("halo_vtk_box_lo");
    h->uniforms.push_back("halo_vtk_box_hi");
    upload_all(h, &h->uniforms);
    if (segmenting)
        segmenting->halo = h;
    take_program(h, program);
    /* drawn once: the same scene with smaller halo images, for a field over its cap */
    for (int k = 0, scale = h->image_scale * 2; h->one_draw && scale <= 4; k++, scale *= 2) {
        halo_link_desc smaller = link;
        smaller.image_scale = scale;
        halo_diagnostics *scratch = halo_diagnostics_create(); /* a failure here is only no fallback */
        h->smaller[k] = scratch ? halo_link(&smaller, scratch) : nullptr;
        halo_diagnostics_destroy(scratch);
    }
    h->mode = !segmenting ? SPLICE_OWN : names.segmented ? SPLICE_SEGMENTS : SPLICE_DRAWN_ONCE;
    replace_splices(h, true);
    h->observer = vtkSmartPointer<vtkCallbackCommand>::New();
    h->observer->SetCallback(on_render_end);
    h->observer->SetClientData(h);
    h->observer_tag = mapper->AddObserver(vtkCommand::VolumeMapperRenderEndEvent, h->observer);
    installs().push_back(h);
    h->start_observer = vtkSmartPointer<vtkCallbackCommand>::New();
    h->start_observer->SetCallback(on_render_start);
    h->start_observer->SetClientData(h);
    h->start_observer_tag = mapper->AddObserver(vtkCommand::VolumeMapperRenderStartEvent, h->start_observer);
    return h;
}

void halo_vtk_remove(halo_vtk *h)
{
    if (!installed(h))
        return; /* NULL, or removed already: nothing to do, silently */
    replace_splices(h, false);
    if (haloVTKMapper *m = haloVTKMapper::SafeDownCast(h->mapper))
        m->halo = nullptr;
    if (h->value_texture)
        glDeleteTextures(1, &h->value_texture);
    if (h->gradient_texture)
        glDeleteTextures(1, &h->gradient_texture);
    if (h->color)
        glDeleteTextures(1, &h->color);
    if (h->host_color)
        glDeleteTextures(1, &h->host_color);
    if (h->framebuffer)
        glDeleteFramebuffers(1, &h->framebuffer);
    if (h->host_color_framebuffer)
        glDeleteFramebuffers(1, &h->host_color_framebuffer);
    if (h->blit_program)
        glDeleteProgram(h->blit_program);
    if (h->blit_vao)
        glDeleteVertexArrays(1, &h->blit_vao);
    halo_gl_frame_destroy(h->frame);
    halo_gl_destroy(h->gl);
    vtkUniforms *u = h->property->GetFragmentCustomUniforms();
    for (const std::string &name : h->uniforms)
        u->RemoveUniform(name.c_str());
    h->mapper->RemoveObserver(h->observer_tag);
    h->mapper->RemoveObserver(h->start_observer_tag);
    halo_program_destroy(h->program);
    halo_program_destroy(h->smaller[0]);
    halo_program_destroy(h->smaller[1]);
    std::vector<halo_vtk *> &list = installs();
    for (size_t i = 0; i < list.size(); i++)
        if (list[i] == h)
            list.erase(list.begin() + (long)i);
    delete h;
}

halo_status halo_vtk_set(halo_vtk *h, const char *stage, const char *param, const double *values, int count,
                         halo_diagnostics *diag)
{
    if (!live_install(h, "halo_vtk_set", diag))
        return HALO_ERROR_INPUT;
    const halo_uniform_info *info = halo_program_find_uniform(h->program, stage, param);
    if (info && !info->live) {
        add_error(diag, HALO_MSG_USAGE,
                  "this parameter is a constant in the linked shader: mark it live in the scene "
                  "(\"live\") or install with all_live to change it without a rebuild");
        return HALO_ERROR_INPUT;
    }
    halo_status st = halo_program_set(h->program, stage, param, values, count, diag);
    if (st != HALO_OK)
        return st;
    upload_all(h, nullptr);
    return HALO_OK;
}

halo_status halo_vtk_check(halo_vtk *h, halo_diagnostics *diag)
{
    if (!live_install(h, "halo_vtk_check", diag))
        return HALO_ERROR_INPUT;
    if (h->last_source.empty()) {
        add_error(diag, HALO_MSG_ENGINE_UNSUPPORTED,
                  "VTK has not built its volume shader yet (render once before halo_vtk_check)");
        return HALO_ERROR_INPUT;
    }
    if (h->failed) {
        add_error(diag, HALO_MSG_GL_LINK,
                  "drawing the volume with libhalo's image passes failed (see the diagnostics above)");
        return HALO_ERROR_INPUT;
    }
    if (!h->took) {
        add_error(diag, HALO_MSG_ENGINE_UNSUPPORTED,
                  "the shader VTK built does not hold libhalo's stages: the splice point '" +
                      std::string(splice_point) +
                      "' was not in it (the blend mode or the inputs changed after the install, or this VTK "
                      "composes its shader differently)");
        return HALO_ERROR_INPUT;
    }
    if (getenv("HALO_VTK_DUMP")) {
        FILE *f = fopen(getenv("HALO_VTK_DUMP"), "w");
        if (f) {
            fputs(h->last_source.c_str(), f);
            fclose(f);
        }
    }
    /* every other replacement of the install's mode: what it adds to VTK's text is there */
    for (const splice &sp : splices) {
        if (!(sp.modes & h->mode) || sp.optional)
            continue;
        /* the parts of the replacement around VTK's own text (a tag VTK fills in later) */
        std::string text = replacement(h, sp);
        bool found = true;
        for (size_t from = 0; from <= text.size() && found;) {
            size_t at = text.find(sp.vtk_text, from);
            std::string part = text.substr(from, at == std::string::npos ? std::string::npos : at - from);
            from = at == std::string::npos ? text.size() + 1 : at + strlen(sp.vtk_text);
            while (!part.empty() && (part[0] == '\n' || part[0] == ' '))
                part.erase(0, 1);
            while (!part.empty() && (part.back() == '\n' || part.back() == ' '))
                part.pop_back();
            /* VTK's GLSL 150 names its output fragOutput0 after the replacements */
            for (size_t k; h->last_source.find("gl_FragData[0]") == std::string::npos &&
                           (k = part.find("gl_FragData[0]")) != std::string::npos;)
                part.replace(k, strlen("gl_FragData[0]"), "fragOutput0");
            found = part.empty() || h->last_source.find(part) != std::string::npos;
        }
        if (!found) {
            add_error(diag, HALO_MSG_ENGINE_UNSUPPORTED,
                      "the shader VTK built does not hold libhalo-vtk's replacement of '" + std::string(sp.vtk_text) +
                          "' (this VTK composes its shader differently: docs/hosts/vtk.md lists the replacements)");
            return HALO_ERROR_INPUT;
        }
    }
    halo_composer_piece pieces[] = {{"libhalo-vtk conversions", conversions}};
    halo_validate_desc check{};
    check.program = h->program;
    check.composed = h->last_source.c_str();
    check.composed_file = file_name;
    check.composer_pieces = pieces;
    check.composer_piece_count = 1;
    return halo_validate(&check, diag);
}

halo_status halo_vtk_set_whole_extent(halo_vtk *h, const int whole_extent[6])
{
    if (!whole_extent || !live_install(h, "halo_vtk_set_whole_extent", nullptr))
        return HALO_ERROR_INPUT;
    for (int k = 0; k < 6; k++)
        h->whole[k] = whole_extent[k];
    update_global(h);
    return HALO_OK;
}

void halo_vtk_set_exchange(halo_vtk *h, halo_vtk_exchange_fn exchange, void *user)
{
    if (!live_install(h, "halo_vtk_set_exchange", nullptr))
        return;
    h->exchange = exchange;
    h->exchange_user = user;
}

const halo_program *halo_vtk_program(const halo_vtk *h) { return installed(h) ? h->program : nullptr; }
int halo_vtk_build_count(const halo_vtk *h) { return installed(h) ? h->builds : 0; }
