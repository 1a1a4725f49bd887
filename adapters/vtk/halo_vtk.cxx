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
 * shading on, so the stages get their own (central differences of in_volume[0]). */
#include "halo_vtk.h"

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkGPUVolumeRayCastMapper.h>
#include <vtkImageData.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkOpenGLShaderCache.h>
#include <vtkOpenGLShaderProperty.h>
#include <vtkRenderer.h>
#include <vtkPointData.h>
#include <vtkShader.h>
#include <vtkShaderProgram.h>
#include <vtkSmartPointer.h>
#include <vtkUniforms.h>
#include <vtkVolume.h>
#include <vtkVolumeProperty.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

/* Where the sample piece goes: VTK's composite mode premultiplies the classified colour
 * here, just before compositing (one occurrence in a composite, one-component shader). */
const char splice_point[] = "g_srcColor.rgb *= g_srcColor.a;";
/* After VTK's base declarations: in_volume, the matrices, in_cameraPos. */
const char declarations_tag[] = "//VTK::Shading::Dec";
const char file_name[] = "(VTK volume shader)";

/* Our functions: VTK's conventions to the host contract's (docs/hosts/vtk.md). */
const char conversions[] =
    "// ---- libhalo-vtk: VTK's conventions to the host contract's ----\n"
    "// value: VTK's scalar is normalised over the input's range; halo_vtk_window maps the\n"
    "// window's ends (in that normalisation) to 0 and 1\n"
    "float halo_vtk_value(vec4 scalar) {\n"
    "    return (scalar.r - halo_vtk_window.x) / (halo_vtk_window.y - halo_vtk_window.x);\n"
    "}\n"
    "// the contract's gradient: central differences over +-1 voxel, halved, of the value\n"
    "vec3 halo_vtk_gradient(vec3 p) {\n"
    "    vec3 voxel = 1.0 / vec3(textureSize(in_volume[0], 0));\n"
    "    vec3 d = vec3(texture(in_volume[0], p + vec3(voxel.x, 0.0, 0.0)).r - texture(in_volume[0], p - vec3(voxel.x, 0.0, 0.0)).r,\n"
    "                  texture(in_volume[0], p + vec3(0.0, voxel.y, 0.0)).r - texture(in_volume[0], p - vec3(0.0, voxel.y, 0.0)).r,\n"
    "                  texture(in_volume[0], p + vec3(0.0, 0.0, voxel.z)).r - texture(in_volume[0], p - vec3(0.0, 0.0, voxel.z)).r);\n"
    "    return 0.5 * d * in_volume_scale[0].r / (halo_vtk_window.y - halo_vtk_window.x);\n"
    "}\n"
    "// the eye in texture space\n"
    "vec3 halo_vtk_eye() {\n"
    "    vec4 e = in_inverseTextureDatasetMatrix[0] * in_inverseVolumeMatrix[0] * vec4(in_cameraPos, 1.0);\n"
    "    return e.xyz / e.w;\n"
    "}\n"
    "// towards the eye, along the ray (perspective and parallel), per voxel step like the gradient\n"
    "vec3 halo_vtk_view() {\n"
    "    vec3 d = g_dirStep * vec3(textureSize(in_volume[0], 0));\n"
    "    float l = dot(d, d);\n"
    "    return l > 0.0 ? -d * inversesqrt(l) : vec3(0.0);\n"
    "}\n"
    "// 0 at the front of the volume's bounding sphere (texture space), 1 at its back\n"
    "float halo_vtk_depth(vec3 p) {\n"
    "    const float radius = 0.8660254037844386;\n"
    "    vec3 eye = halo_vtk_eye();\n"
    "    return clamp((distance(eye, p) - (distance(eye, vec3(0.5)) - radius)) / (2.0 * radius), 0.0, 1.0);\n"
    "}\n"
    "// VTK's opacity is corrected for the sample distance: a = 1 - (1 - a_unit)^e\n"
    "float halo_vtk_exponent() { return in_sampleDistance / halo_vtk_unit_distance; }\n"
    "float halo_vtk_correct(float a, float e) {\n"
    "    float t = 1.0 - clamp(a, 0.0, 1.0);\n"
    "    return 1.0 - (t > 0.0 ? pow(t, e) : 0.0);\n"
    "}\n";

const halo_pieces_desc vtk_names = {
    /* position */ "g_dataPos",
    /* value */ "halo_vtk_value(scalar)",
    /* gradient */ "halo_vtk_gradient(g_dataPos)",
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
    vtkGPUVolumeRayCastMapper *mapper = nullptr;
    vtkVolume *volume = nullptr;
    vtkOpenGLShaderProperty *property = nullptr;
    vtkRenderer *renderer = nullptr;
    halo_program *program = nullptr;
    std::string sample;       /* the replacement at the splice point */
    std::string declarations; /* the replacement at the declarations tag */
    std::vector<std::string> uniforms;
    vtkSmartPointer<vtkCallbackCommand> observer;
    unsigned long observer_tag = 0;
    std::string last_source; /* the fragment shader VTK built last */
    int last_handle = -1;
    int builds = 0;
    int took = 0;
};

namespace {

void add_error(halo_diagnostics *diag, halo_message_id id, const std::string &text) {
    halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, id, nullptr, 0, 0, text.c_str());
}

/* Uploads one engine uniform as a VTK custom uniform; arrays padded to their size so that
 * VTK's declaration never changes (a change would rebuild the shader). */
void set_uniform(vtkUniforms *u, const halo_uniform_decl &d, std::vector<std::string> *names) {
    if (d.name) {
        int comps = d.components, n = d.array_size ? d.array_size : 1;
        if (!strcmp(d.glsl_type, "int")) {
            std::vector<int> v((size_t)n * comps, 0);
            for (int k = 0; k < n * comps; k++) v[(size_t)k] = (int)d.value[k < d.count * comps ? k : d.count * comps - 1];
            if (d.array_size) u->SetUniform1iv(d.name, n, v.data());
            else u->SetUniformi(d.name, v[0]);
        } else {
            std::vector<float> v((size_t)n * comps, 0.0f);
            for (int k = 0; k < n * comps; k++) {
                int from = k < d.count * comps ? k : (d.count - 1) * comps + k % comps;
                v[(size_t)k] = d.count > 0 ? (float)d.value[from] : 0.0f;
            }
            u->SetUniform(d.name, comps == 1 && !d.array_size ? vtkUniforms::TupleTypeScalar : vtkUniforms::TupleTypeVector,
                          comps, v);
        }
        if (names) names->push_back(d.name);
    }
    if (d.count_name) {
        u->SetUniformi(d.count_name, d.count);
        if (names) names->push_back(d.count_name);
    }
}

void upload_all(halo_vtk *h, std::vector<std::string> *names) {
    vtkUniforms *u = h->property->GetFragmentCustomUniforms();
    size_t cursor = 0;
    halo_uniform_decl d;
    while (halo_program_uniform_next(h->program, &cursor, &d)) set_uniform(u, d, names);
}

/* After the mapper's render, the ray-casting program is the one the render window's
 * shader cache bound last (VTK 9.1 sends no UpdateShaderEvent from the volume mapper):
 * note each new one and whether the stages are in it. */
void on_render_end(vtkObject *, unsigned long, void *client, void *) {
    halo_vtk *h = static_cast<halo_vtk *>(client);
    vtkOpenGLRenderWindow *window =
        h->renderer ? vtkOpenGLRenderWindow::SafeDownCast(h->renderer->GetRenderWindow()) : nullptr;
    vtkShaderProgram *program = window ? window->GetShaderCache()->GetLastShaderBound() : nullptr;
    if (!program || !program->GetFragmentShader()) return;
    if (program->GetFragmentShader()->GetSource().find("g_srcColor") == std::string::npos) return;
    int handle = program->GetHandle();
    if (handle == h->last_handle) return;
    h->last_handle = handle;
    h->last_source = program->GetFragmentShader()->GetSource();
    h->took = h->last_source.find(halo_program_piece(h->program, HALO_PIECE_SAMPLE)) != std::string::npos;
    h->builds++;
}

} // namespace

halo_vtk *halo_vtk_install(const halo_vtk_desc *desc, halo_diagnostics *diag) {
    if (!desc || !desc->mapper || !desc->volume || !desc->renderer || !desc->library) {
        add_error(diag, HALO_MSG_USAGE, "halo_vtk_install: mapper, volume, renderer and library are required");
        return nullptr;
    }
    vtkGPUVolumeRayCastMapper *mapper = desc->mapper;
    vtkOpenGLShaderProperty *property = vtkOpenGLShaderProperty::SafeDownCast(desc->volume->GetShaderProperty());
    if (!property) {
        add_error(diag, HALO_MSG_USAGE, "halo_vtk_install: the volume has no OpenGL shader property (VTK's OpenGL2 "
                                        "rendering module is not initialised: VTK_MODULE_INIT(vtkRenderingOpenGL2))");
        return nullptr;
    }
    /* What VTK's shader can take: one splice point, in composite mode with one component. */
    static const char *const modes[] = {"composite", "maximum intensity", "minimum intensity", "average intensity",
                                        "additive", "isosurface", "slice"};
    int mode = mapper->GetBlendMode();
    if (mode != vtkVolumeMapper::COMPOSITE_BLEND) {
        add_error(diag, HALO_MSG_ENGINE_UNSUPPORTED,
                  std::string("the VTK mapper's blend mode is ") +
                      (mode >= 0 && mode < 7 ? modes[mode] : "unknown") +
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
    halo_link_desc link = {};
    link.library = desc->library;
    link.scene = desc->scene;
    link.all_live = desc->all_live;
    link.target = HALO_TARGET_GLSL150;
    link.engine_uniforms = 1;
    link.pieces = &vtk_names;
    halo_program *program = halo_link(&link, diag);
    if (!program) return nullptr;
    if (halo_program_output_count(program) || halo_program_pass_count(program)) {
        std::string stages;
        for (size_t i = 0; i < halo_program_stage_count(program); i++)
            stages += (stages.empty() ? "" : ", ") + std::string(halo_program_stage(program, i));
        add_error(diag, HALO_MSG_HOST_SINGLE_PASS,
                  "the scene's stages (" + stages +
                      ") include some that write extra outputs or run image passes (volumetric halos, outlines, "
                      "feature halos): VTK's single-pass ray caster cannot run them through this adapter yet "
                      "(docs/hosts/vtk.md)");
        halo_program_destroy(program);
        return nullptr;
    }
    if (halo_program_validate(program, diag) != HALO_OK) {
        halo_program_destroy(program);
        return nullptr;
    }
    halo_vtk *h = new halo_vtk;
    h->mapper = mapper;
    h->volume = desc->volume;
    h->renderer = desc->renderer;
    h->property = property;
    h->program = program;
    /* the value window, in VTK's normalisation over the input's range */
    double range[2];
    input->GetScalarRange(range);
    double w0 = desc->window[0], w1 = desc->window[1];
    if (!(w1 != w0)) {
        w0 = range[0];
        w1 = range[1];
    }
    double span = range[1] > range[0] ? range[1] - range[0] : 1.0;
    float window[2] = {(float)((w0 - range[0]) / span), (float)((w1 - range[0]) / span)};
    if (window[1] == window[0]) window[1] = window[0] + 1.0f;
    vtkUniforms *u = property->GetFragmentCustomUniforms();
    u->SetUniform2f("halo_vtk_window", window);
    h->uniforms.push_back("halo_vtk_window");
    vtkVolumeProperty *vp = desc->volume->GetProperty();
    double unit = vp ? vp->GetScalarOpacityUnitDistance() : 1.0;
    u->SetUniformf("halo_vtk_unit_distance", (float)(unit > 0.0 ? unit : 1.0));
    h->uniforms.push_back("halo_vtk_unit_distance");
    upload_all(h, &h->uniforms);
    /* the pieces */
    h->declarations = std::string(declarations_tag) + "\n" + conversions +
                      halo_program_piece(program, HALO_PIECE_DECLARATIONS);
    h->sample = std::string("// ---- libhalo-vtk: the stages, on the opacity per unit distance ----\n"
                            "g_srcColor.a = halo_vtk_correct(g_srcColor.a, 1.0 / halo_vtk_exponent());\n") +
                halo_program_piece(program, HALO_PIECE_SAMPLE) +
                "g_srcColor.a = halo_vtk_correct(g_srcColor.a, halo_vtk_exponent());\n" + splice_point;
    property->AddFragmentShaderReplacement(declarations_tag, true, h->declarations, false);
    property->AddFragmentShaderReplacement(splice_point, false, h->sample, false);
    h->observer = vtkSmartPointer<vtkCallbackCommand>::New();
    h->observer->SetCallback(on_render_end);
    h->observer->SetClientData(h);
    h->observer_tag = mapper->AddObserver(vtkCommand::VolumeMapperRenderEndEvent, h->observer);
    return h;
}

void halo_vtk_remove(halo_vtk *h) {
    if (!h) return;
    h->property->ClearFragmentShaderReplacement(declarations_tag, true);
    h->property->ClearFragmentShaderReplacement(splice_point, false);
    vtkUniforms *u = h->property->GetFragmentCustomUniforms();
    for (const std::string &name : h->uniforms) u->RemoveUniform(name.c_str());
    h->mapper->RemoveObserver(h->observer_tag);
    halo_program_destroy(h->program);
    delete h;
}

halo_status halo_vtk_set(halo_vtk *h, const char *stage, const char *param, const double *values, int count,
                         halo_diagnostics *diag) {
    if (!h) return HALO_ERROR_INPUT;
    const halo_uniform_info *info = halo_program_find_uniform(h->program, stage, param);
    if (info && !info->live) {
        add_error(diag, HALO_MSG_USAGE,
                                   "this parameter is a constant in the linked shader: mark it live in the scene "
                                   "(\"live\") or install with all_live to change it without a rebuild");
        return HALO_ERROR_INPUT;
    }
    halo_status st = halo_program_set(h->program, stage, param, values, count, diag);
    if (st != HALO_OK) return st;
    upload_all(h, nullptr);
    return HALO_OK;
}

halo_status halo_vtk_check(halo_vtk *h, halo_diagnostics *diag) {
    if (!h) return HALO_ERROR_INPUT;
    if (h->last_source.empty()) {
        add_error(diag, HALO_MSG_ENGINE_UNSUPPORTED,
                  "VTK has not built its volume shader yet (render once before halo_vtk_check)");
        return HALO_ERROR_INPUT;
    }
    if (!h->took) {
        add_error(diag, HALO_MSG_ENGINE_UNSUPPORTED,
                  "the shader VTK built does not hold libhalo's stages: the splice point '" + std::string(splice_point) +
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
    halo_composer_piece pieces[] = {{"libhalo-vtk conversions", conversions}};
    return halo_program_validate_composed(h->program, h->last_source.c_str(), file_name, pieces, 1, diag);
}

const halo_program *halo_vtk_program(const halo_vtk *h) { return h ? h->program : nullptr; }
int halo_vtk_build_count(const halo_vtk *h) { return h ? h->builds : 0; }
