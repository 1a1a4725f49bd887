/* vtkHaloVolumeRepresentation (vtkHaloVolumeRepresentation.h, docs/distributed.md). */
#include "vtkHaloVolumeRepresentation.h"

#include "halo.h"
#include "halo_vtk.h"

#include <vtkCommunicator.h>
#include <vtkDataArray.h>
#include <vtkDataObject.h>
#include <vtkGPUVolumeRayCastMapper.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkMultiProcessController.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkRenderer.h>
#include <vtkSmartVolumeMapper.h>
#include <vtkVolume.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace
{
/* ParaView's smart volume mapper with libhalo-vtk's segmented GPU mapper in place of
 * VTK's, which tells the representation before each render. */
class haloSmartVolumeMapper : public vtkSmartVolumeMapper
{
  public:
    static haloSmartVolumeMapper *New();
    vtkTypeMacro(haloSmartVolumeMapper, vtkSmartVolumeMapper);
    vtkHaloVolumeRepresentation *Owner = nullptr;

    void Render(vtkRenderer *ren, vtkVolume *vol) override
    {
        if (this->Owner) {
            /* every rank samples as one renderer of the whole volume would: VTK's distance
       * locked to the input's spacing depends on the input's extent (a brick's differs
       * from the whole's), and the automatic one on each rank's frame time */
            vtkImageData *image = vtkImageData::SafeDownCast(this->GetInput());
            int whole[6];
            this->Owner->GetWholeExtentOfPieces(whole);
            if (image && whole[1] >= whole[0]) {
                double spacing[3];
                image->GetSpacing(spacing);
                this->SetSampleDistance(static_cast<float>(this->SpacingAdjustedSampleDistance(spacing, whole)));
            }
            this->ComputeRenderMode(ren, vol); /* connects the GPU mapper's input */
            this->Owner->PrepareHalo(ren, vol);
        }
        this->vtkSmartVolumeMapper::Render(ren, vol);
        if (this->Owner)
            this->Owner->CheckHalo();
    }
    /* the GPU mapper that renders, or null when another one does (CPU, low resolution) */
    vtkGPUVolumeRayCastMapper *HaloMapper()
    {
        return this->CurrentRenderMode == vtkSmartVolumeMapper::GPURenderMode && !this->LowResGPUNecessary
                   ? this->GPUMapper
                   : nullptr;
    }

  protected:
    haloSmartVolumeMapper()
    {
        this->GPUMapper->Delete();
        this->GPUMapper = halo_vtk_mapper_new();
        /* the sample distance is set for the whole volume before each render (Render) */
        this->GPUMapper->LockSampleDistanceToInputSpacingOff();
        this->AutoAdjustSampleDistancesOff();
        this->InteractiveAdjustSampleDistancesOff();
    }
};
vtkStandardNewMacro(haloSmartVolumeMapper);

/* halo_vtk_set_exchange: one image combined over all ranks */
void exchange_over_ranks(void *user, float *values, size_t count, halo_blend blend)
{
    vtkMultiProcessController *c = static_cast<vtkMultiProcessController *>(user);
    int op = blend == HALO_BLEND_MIN   ? vtkCommunicator::MIN_OP
             : blend == HALO_BLEND_ADD ? vtkCommunicator::SUM_OP
                                       : vtkCommunicator::MAX_OP;
    std::vector<float> mine(values, values + count);
    c->AllReduce(mine.data(), values, static_cast<vtkIdType>(count), op);
}

/* HaloExchange 0, for comparison: each rank's halos from its own brick's seeds alone */
void exchange_nothing(void *, float *, size_t, halo_blend) {}

/* HALO_PARAVIEW_LOCAL=1, for tests and measurements: each rank's stages in its own
 * piece's space, as libhalo-vtk installed on each rank without the whole extent would
 * be (docs/distributed.md) */
int piece_space_only()
{
    const char *v = getenv("HALO_PARAVIEW_LOCAL");
    return v && *v && strcmp(v, "0") != 0;
}

int rank_count()
{
    vtkMultiProcessController *c = vtkMultiProcessController::GetGlobalController();
    return c ? c->GetNumberOfProcesses() : 1;
}
} // namespace

class vtkHaloVolumeRepresentation::vtkInternals
{
  public:
    std::string ScenePath, Settings;
    double Window[2] = {0, 0};
    int Exchange = 1;
    int ImageScale = 1;       /* halo_vtk_desc.image_scale */
    double Range[2] = {0, 1}; /* the drawn array's range over all ranks */
    int Dirty = 1;            /* a property changed: install again */
    int Failed = 0;           /* the last install failed (said once) */
    int FrameFailed = 0;      /* a render since the install reported an error (a tiled screenshot) */
    int Checked = 0;          /* halo_vtk_check ran after the install's first render */
    haloSmartVolumeMapper *Mapper = nullptr;
    halo_diagnostics *Diag = nullptr;
    halo_library *Library = nullptr;
    halo_scene *Scene = nullptr;
    halo_vtk *Halo = nullptr;
    vtkGPUVolumeRayCastMapper *On = nullptr;
    vtkVolume *Volume = nullptr;

    /* diagnostics on stderr, prefixed with the rank (ParaView's ranks share a terminal) */
    void Flush()
    {
        if (halo_diagnostics_describe(this->Diag).count) {
            vtkMultiProcessController *c = vtkMultiProcessController::GetGlobalController();
            fprintf(stderr, "HaloVolume (rank %d):\n", c ? c->GetLocalProcessId() : 0);
            halo_diagnostics_print(this->Diag, stderr);
            halo_diagnostics_clear(this->Diag);
        }
    }
    void Remove()
    {
        halo_vtk_remove(this->Halo);
        this->Halo = nullptr;
        this->On = nullptr;
    }
    /* "stage.param=v[,v...]; ..." onto the scene */
    int ApplySettings()
    {
        size_t at = 0;
        const std::string &s = this->Settings;
        while (at < s.size()) {
            size_t end = s.find(';', at);
            std::string item = s.substr(at, end == std::string::npos ? std::string::npos : end - at);
            at = end == std::string::npos ? s.size() : end + 1;
            size_t first = item.find_first_not_of(" \t"), last = item.find_last_not_of(" \t");
            if (first == std::string::npos)
                continue;
            item = item.substr(first, last - first + 1);
            size_t dot = item.find('.'), eq = item.find('=');
            std::vector<double> v;
            const char *p = eq == std::string::npos ? nullptr : item.c_str() + eq + 1;
            while (p && *p) {
                char *stop;
                double x = strtod(p, &stop);
                if (stop == p) {
                    v.clear();
                    break;
                }
                v.push_back(x);
                p = *stop == ',' ? stop + 1 : (*stop ? nullptr : stop);
                if (!p)
                    v.clear();
            }
            if (dot == std::string::npos || eq == std::string::npos || dot > eq || v.empty()) {
                halo_diagnostics_report(
                    this->Diag, HALO_SEVERITY_ERROR, HALO_MSG_USAGE, "HaloSettings", 0, 0, nullptr, "%s",
                    ("HaloSettings takes stage.param=v[,v...] separated by ';', not '" + item + "'").c_str());
                return 0;
            }
            std::string stage = item.substr(0, dot), param = item.substr(dot + 1, eq - dot - 1);
            const halo_module *module = halo_library_find(this->Library, stage.c_str());
            const halo_param_info *info = module ? halo_module_find_param(module, param.c_str()) : nullptr;
            int components = info ? info->components : 1;
            if (v.size() % static_cast<size_t>(components)) {
                halo_diagnostics_report(this->Diag, HALO_SEVERITY_ERROR, HALO_MSG_USAGE, "HaloSettings", 0, 0, nullptr,
                                        "%s",
                                        ("HaloSettings: " + stage + "." + param + " takes " +
                                         std::to_string(components) + " values per element, not '" + item + "'")
                                            .c_str());
                return 0;
            }
            if (halo_scene_set(this->Scene, stage.c_str(), param.c_str(), v.data(),
                               static_cast<int>(v.size()) / components, 0, this->Diag) != HALO_OK)
                return 0;
        }
        return 1;
    }
};

vtkStandardNewMacro(vtkHaloVolumeRepresentation);

vtkHaloVolumeRepresentation::vtkHaloVolumeRepresentation() : Internals(new vtkInternals)
{
    halo_setup_desc setup = {};
    halo_setup(&setup);
    this->Internals->Diag = halo_diagnostics_create();
    vtkNew<haloSmartVolumeMapper> mapper;
    mapper->Owner = this;
    this->Internals->Mapper = mapper;
    this->VolumeMapper = mapper.GetPointer();
}

vtkHaloVolumeRepresentation::~vtkHaloVolumeRepresentation()
{
    vtkInternals *I = this->Internals;
    I->Mapper->Owner = nullptr;
    I->Remove();
    halo_scene_destroy(I->Scene);
    halo_library_destroy(I->Library);
    halo_diagnostics_destroy(I->Diag);
    delete I;
    halo_shutdown();
}

namespace
{
/* A string property set from ParaView (NULL: empty); true when it changed. */
bool ChangeString(std::string &property, const char *value)
{
    std::string v = value ? value : "";
    if (v == property)
        return false;
    property = v;
    return true;
}
} // namespace

void vtkHaloVolumeRepresentation::SetHaloScene(const char *path)
{
    if (ChangeString(this->Internals->ScenePath, path)) {
        this->Internals->Dirty = 1;
        this->Modified();
    }
}

void vtkHaloVolumeRepresentation::SetHaloSettings(const char *settings)
{
    if (ChangeString(this->Internals->Settings, settings)) {
        this->Internals->Dirty = 1;
        this->Modified();
    }
}

void vtkHaloVolumeRepresentation::SetHaloWindow(double low, double high)
{
    if (low == this->Internals->Window[0] && high == this->Internals->Window[1])
        return;
    this->Internals->Window[0] = low;
    this->Internals->Window[1] = high;
    this->Internals->Dirty = 1;
    this->Modified();
}

void vtkHaloVolumeRepresentation::SetHaloExchange(int exchange)
{
    if ((exchange != 0) == (this->Internals->Exchange != 0))
        return;
    this->Internals->Exchange = exchange != 0;
    this->Internals->Dirty = 1;
    this->Modified();
}

void vtkHaloVolumeRepresentation::SetHaloImageScale(int scale)
{
    if (scale == this->Internals->ImageScale)
        return;
    this->Internals->ImageScale = scale; /* 1, 2 or 4 (the XML's domain; libhalo refuses others) */
    this->Internals->Dirty = 1;
    this->Modified();
}

int vtkHaloVolumeRepresentation::RequestData(vtkInformation *request, vtkInformationVector **inputVector,
                                             vtkInformationVector *outputVector)
{
    int result = this->Superclass::RequestData(request, inputVector, outputVector);
    /* the drawn array's range over all ranks: the default window, the same on every rank */
    double local[2] = {VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX}, global[2];
    if (vtkImageData *image = vtkImageData::SafeDownCast(this->Cache)) {
        vtkDataArray *array = image->GetPointData()->GetScalars();
        vtkInformation *info = this->GetInputArrayInformation(0);
        if (info && info->Has(vtkDataObject::FIELD_NAME()))
            if (vtkDataArray *named = image->GetPointData()->GetArray(info->Get(vtkDataObject::FIELD_NAME())))
                array = named;
        if (array && array->GetNumberOfTuples() > 0)
            array->GetRange(local, 0);
    }
    global[0] = local[0];
    global[1] = local[1];
    if (vtkMultiProcessController *c = vtkMultiProcessController::GetGlobalController()) {
        c->AllReduce(&local[0], &global[0], 1, vtkCommunicator::MIN_OP);
        c->AllReduce(&local[1], &global[1], 1, vtkCommunicator::MAX_OP);
    }
    if (global[1] >= global[0] && (global[0] != this->Internals->Range[0] || global[1] != this->Internals->Range[1])) {
        this->Internals->Range[0] = global[0];
        this->Internals->Range[1] = global[1];
        this->Internals->Dirty = 1;
    }
    return result;
}

void vtkHaloVolumeRepresentation::PrepareHalo(vtkRenderer *renderer, vtkVolume *volume)
{
    vtkInternals *I = this->Internals;
    vtkGPUVolumeRayCastMapper *gpu = I->Mapper->HaloMapper();
    if (I->Halo && !I->Dirty && I->On == gpu && I->Volume == volume) {
        if (!piece_space_only())
            halo_vtk_set_whole_extent(I->Halo, this->WholeExtent);
        return;
    }
    if (!I->Dirty && I->Failed)
        return;
    I->Remove();
    I->Dirty = 0;
    I->Failed = 1; /* until the install below succeeds */
    if (I->ScenePath.empty()) {
        I->Failed = 0;
        return;
    }
    if (!gpu) {
        vtkWarningMacro(
            "HaloVolume: ParaView renders this volume without the GPU ray caster (a CPU or "
            "low-resolution mapper): libhalo's stages are not drawn");
        return;
    }
    if (!I->Library)
        I->Library = halo_library_create(I->Diag);
    halo_scene_destroy(I->Scene);
    I->Scene = I->Library ? halo_scene_load(I->ScenePath.c_str(), nullptr, I->Library, I->Diag) : nullptr;
    if (!I->Scene || !I->ApplySettings()) {
        vtkErrorMacro("HaloVolume: the scene '" << I->ScenePath << "' was not loaded (diagnostics on stderr)");
        I->Flush();
        return;
    }
    halo_vtk_desc desc = {};
    desc.mapper = gpu;
    desc.volume = volume;
    desc.renderer = renderer;
    desc.library = I->Library;
    desc.scene = I->Scene;
    int window = I->Window[1] != I->Window[0];
    desc.window[0] = window ? I->Window[0] : I->Range[0];
    desc.window[1] = window ? I->Window[1] : I->Range[1];
    /* VTK's volume drawn once over the halo field (host contract 3): each rank's march reads
   * its brick, the seeds of every depth segment combined over the ranks in one collective a
   * frame; HALO_PARAVIEW_SEGMENTS=1: each rank's brick drawn in depth segments, one
   * collective a segment (host contract 2, for comparison: docs/distributed.md) */
    const char *segments = getenv("HALO_PARAVIEW_SEGMENTS");
    desc.segments = segments && *segments && strcmp(segments, "0") != 0;
    desc.image_scale = I->ImageScale;
    I->Halo = halo_vtk_install(&desc, I->Diag);
    if (I->Halo && rank_count() > 1) {
        const halo_program *p = halo_vtk_program(I->Halo);
        for (size_t i = 0; i < halo_program_reflection(p).pass_count; i++)
            if (halo_program_reflection(p).passes[i].at) {
                halo_diagnostics_report(
                    I->Diag, HALO_SEVERITY_ERROR, HALO_MSG_ENGINE_UNSUPPORTED, nullptr, 0, 0, nullptr, "%s",
                    (std::string("the scene's stage ") + halo_program_reflection(p).passes[i].stage +
                     " runs image passes on the finished image (outlines): across ranks they need the composited "
                     "image, which ParaView makes after the volume mapper; run it on one rank (docs/distributed.md)")
                        .c_str());
                I->Remove();
                break;
            }
    }
    if (!I->Halo) {
        vtkErrorMacro("HaloVolume: libhalo's stages could not be installed (diagnostics on stderr)");
        I->Flush();
        return;
    }
    I->Failed = 0;
    I->FrameFailed = 0;
    I->Checked = 0;
    I->On = gpu;
    I->Volume = volume;
    if (!piece_space_only())
        halo_vtk_set_whole_extent(I->Halo, this->WholeExtent);
    if (I->Exchange && rank_count() > 1)
        halo_vtk_set_exchange(I->Halo, exchange_over_ranks, vtkMultiProcessController::GetGlobalController());
    else if (rank_count() > 1)
        halo_vtk_set_exchange(I->Halo, exchange_nothing, nullptr);
    I->Flush();
}

void vtkHaloVolumeRepresentation::GetWholeExtentOfPieces(int extent[6])
{
    for (int k = 0; k < 6; k++)
        extent[k] = this->WholeExtent[k];
}

void vtkHaloVolumeRepresentation::CheckHalo()
{
    vtkInternals *I = this->Internals;
    if (!I->Halo)
        return;
    if (!I->Checked) {
        I->Checked = 1;
        if (halo_vtk_check(I->Halo, I->Diag) != HALO_OK) {
            vtkErrorMacro(
                "HaloVolume: the shader VTK built does not hold libhalo's stages as installed "
                "(diagnostics on stderr)");
            I->Failed = 1;
        }
    }
    /* what the adapter refused during a render (an image larger than the view, drawn in
     * tiles: the volume is not drawn) is said on stderr and kept in the status until the
     * scene is installed again: ParaView renders the view once more after a screenshot */
    if (halo_diagnostics_describe(I->Diag).errors > 0)
        I->FrameFailed = 1;
    I->Flush();
}

int vtkHaloVolumeRepresentation::GetHaloStatus() { return this->Internals->Failed || this->Internals->FrameFailed; }

void vtkHaloVolumeRepresentation::PrintSelf(ostream &os, vtkIndent indent)
{
    this->Superclass::PrintSelf(os, indent);
    os << indent << "HaloScene: " << this->Internals->ScenePath << "\n";
    os << indent << "HaloSettings: " << this->Internals->Settings << "\n";
    os << indent << "HaloWindow: " << this->Internals->Window[0] << " " << this->Internals->Window[1] << "\n";
    os << indent << "HaloExchange: " << this->Internals->Exchange << "\n";
    os << indent << "HaloImageScale: " << this->Internals->ImageScale << "\n";
}
