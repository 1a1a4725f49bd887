/* Two volumes in one VTK renderer (issue 26): the adapter on either one keeps the depth
 * order VTK gives them. VTK draws separate volumes in its prop list's order, which its
 * culler sorts back to front when asked (vtkFrustumCoverageCuller::SetSortingStyle, what a
 * program with several volumes sets); each volume is composited over what is drawn
 * before it. A red ball in front of a blue one, overlapping on the screen; the window is
 * VTK's default one (multisampled). Checks, for both insertion orders, sorted and not:
 *  - VTK alone: the overlap shows the nearer ball (red) when sorted;
 *  - per-sample stages on VTK's mapper, volumetric halos drawn once and in depth
 *    segments, outlines (an at=post pass on VTK's image), each on the near ball and on
 *    the far one: every probe pixel has the colour (red, blue or background) of VTK
 *    alone's image with the same order.
 * Before the fix, outlines read VTK's multisampled framebuffer with glCopyTexSubImage2D
 * (GL_INVALID_OPERATION) and the whole image was black. Run by tests/adapters/vtk/vtk.sh on its X
 * server (77 without a display). */
#include "halo.h"
#include "halo_vtk.h"
#include "test_ball.h"

#include <vtkAutoInit.h>
#include <vtkColorTransferFunction.h>
#include <vtkCullerCollection.h>
#include <vtkFrustumCoverageCuller.h>
#include <vtkGPUVolumeRayCastMapper.h>
#include <vtkImageData.h>
#include <vtkPiecewiseFunction.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkVolume.h>
#include <vtkVolumeProperty.h>

#include <cstdio>
#include <cstdlib>
#include <string>

VTK_MODULE_INIT(vtkRenderingOpenGL2);
VTK_MODULE_INIT(vtkRenderingVolumeOpenGL2);

enum { size = 64 };
/* probe pixels on the centre row: the far ball alone, both (the near one in front), the near alone */
static const int probes[3] = {25, 31, 40};

static vtkSmartPointer<vtkVolume> ball(vtkGPUVolumeRayCastMapper *mapper, const double rgb[3], double x, double z)
{
    vtkSmartPointer<vtkImageData> image = test_ball(1);
    mapper->SetInputData(image);
    vtkSmartPointer<vtkColorTransferFunction> color = vtkSmartPointer<vtkColorTransferFunction>::New();
    color->AddRGBPoint(0.0, rgb[0], rgb[1], rgb[2]);
    color->AddRGBPoint(1.0, rgb[0], rgb[1], rgb[2]);
    vtkSmartPointer<vtkPiecewiseFunction> opacity = vtkSmartPointer<vtkPiecewiseFunction>::New();
    opacity->AddPoint(0.0, 0.0);
    opacity->AddPoint(0.5, 0.0);
    opacity->AddPoint(1.0, 0.9);
    vtkSmartPointer<vtkVolumeProperty> property = vtkSmartPointer<vtkVolumeProperty>::New();
    property->SetColor(color);
    property->SetScalarOpacity(opacity);
    vtkSmartPointer<vtkVolume> volume = vtkSmartPointer<vtkVolume>::New();
    volume->SetMapper(mapper);
    volume->SetProperty(property);
    volume->SetPosition(x, 0, z);
    return volume;
}

/* 'R', 'B' or '.' (neither) at each probe; on failure, a message and "" */
static std::string render(const halo_library *lib, const halo_scene *scene, int halo_mapper, int on_far, int segments,
                          int far_first, int sorted)
{
    static const double red[3] = {1, 0, 0}, blue[3] = {0, 0, 1};
    vtkSmartPointer<vtkGPUVolumeRayCastMapper> near_mapper, far_mapper;
    near_mapper.TakeReference(halo_mapper && !on_far ? halo_vtk_mapper_new() : vtkGPUVolumeRayCastMapper::New());
    far_mapper.TakeReference(halo_mapper && on_far ? halo_vtk_mapper_new() : vtkGPUVolumeRayCastMapper::New());
    vtkSmartPointer<vtkVolume> near_volume = ball(near_mapper, red, 3, 20);
    vtkSmartPointer<vtkVolume> far_volume = ball(far_mapper, blue, -3, -20);
    vtkSmartPointer<vtkRenderer> renderer = vtkSmartPointer<vtkRenderer>::New();
    renderer->AddVolume(far_first ? far_volume : near_volume);
    renderer->AddVolume(far_first ? near_volume : far_volume);
    if (sorted) {
        renderer->GetCullers()->InitTraversal();
        vtkFrustumCoverageCuller *culler =
            vtkFrustumCoverageCuller::SafeDownCast(renderer->GetCullers()->GetNextItem());
        if (culler)
            culler->SetSortingStyleToBackToFront();
    }
    vtkSmartPointer<vtkRenderWindow> window = vtkSmartPointer<vtkRenderWindow>::New();
    window->SetOffScreenRendering(1);
    window->SetSize(size, size);
    window->AddRenderer(renderer);
    renderer->ResetCamera();
    halo_diagnostics *diag = halo_diagnostics_create();
    halo_vtk *h = nullptr;
    if (scene) {
        halo_vtk_desc desc = {};
        desc.mapper = on_far ? far_mapper : near_mapper;
        desc.volume = on_far ? far_volume : near_volume;
        desc.renderer = renderer;
        desc.library = lib;
        desc.scene = scene;
        desc.segments = segments;
        h = halo_vtk_install(&desc, diag);
    }
    std::string out;
    if (!scene || h) {
        window->Render();
        if (h && halo_vtk_check(h, diag) != HALO_OK)
            h = (halo_vtk_remove(h), nullptr);
        else {
            vtkSmartPointer<vtkUnsignedCharArray> px = vtkSmartPointer<vtkUnsignedCharArray>::New();
            window->GetRGBACharPixelData(0, 0, size - 1, size - 1, 0, px);
            for (int x : probes) {
                const unsigned char *p = px->GetPointer(((size / 2) * size + x) * 4);
                out += p[0] > p[2] + 40 ? 'R' : p[2] > p[0] + 40 ? 'B' : '.';
            }
        }
    }
    if (out.empty())
        halo_diagnostics_print(diag, stderr);
    if (h)
        halo_vtk_remove(h);
    halo_diagnostics_destroy(diag);
    return out;
}

int main(void)
{
    if (!getenv("DISPLAY")) {
        fprintf(stderr, "SKIP: VTK's renderer needs an X display\n");
        return 77;
    }
    halo_setup_desc setup = {};
    halo_setup(&setup);
    halo_diagnostics *diag = halo_diagnostics_create();
    halo_library *lib = halo_library_create(diag);
    struct {
        const char *name, *json;
        int halo_mapper, segments; /* halo_vtk_mapper_new's mapper; drawn in depth segments */
    } cases[] = {
        {"tone shading", "[{\"tone_shading\": {}}]", 0, 0},
        {"halos drawn once", "[{\"halo_seed\": {}}, {\"halo_generate\": {}}, {\"halo_map\": {}}]", 1, 0},
        {"halos in segments", "[{\"halo_seed\": {}}, {\"halo_generate\": {}}, {\"halo_map\": {}}]", 1, 1},
        {"outlines", "[{\"outline_feature\": {\"value_min\": 0.5, \"value_max\": 1}}, {\"outlines\": {}}]", 1, 0},
    };
    int failures = 0;
    for (int far_first = 0; far_first < 2; far_first++)
        for (int sorted = 0; sorted < 2; sorted++) {
            std::string vtk = render(lib, nullptr, 0, 0, 0, far_first, sorted);
            printf("%s added first, %s: VTK alone %s\n", far_first ? "far" : "near", sorted ? "sorted" : "unsorted",
                   vtk.c_str());
            if (sorted && vtk != "BRR") {
                fprintf(stderr, "FAIL: VTK alone, sorted, gives %s, not BRR: the test's set-up is wrong\n",
                        vtk.c_str());
                failures++;
            }
            for (const auto &c : cases)
                for (int on_far = 0; on_far < 2; on_far++) {
                    std::string json = std::string("{\"halo_scene\": 1, \"stages\": ") + c.json + "}";
                    halo_scene *scene = halo_scene_load(c.name, json.c_str(), lib, diag);
                    std::string got =
                        scene ? render(lib, scene, c.halo_mapper, on_far, c.segments, far_first, sorted) : "";
                    halo_scene_destroy(scene);
                    int ok = got == vtk;
                    printf("  %-18s on the %s ball: %s%s\n", c.name, on_far ? "far" : "near", got.c_str(),
                           ok ? "" : "  FAIL");
                    failures += !ok;
                }
        }
    halo_diagnostics_print(diag, stderr);
    halo_library_destroy(lib);
    halo_diagnostics_destroy(diag);
    halo_shutdown();
    if (failures)
        fprintf(stderr, "test_vtk_two_volumes: %d failed\n", failures);
    else
        printf("test_vtk_two_volumes: all passed\n");
    return failures ? 1 : 0;
}
