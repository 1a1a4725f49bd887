/* The VTK adapter's lifetimes and misuse (issue 26): what an application may do with a
 * halo_vtk and the VTK objects it was installed on, each case once. Run by
 * tests/adapters/vtk/vtk.sh on its X server (77 without a display). Checks:
 *  - a second install on the same mapper, or the same volume, is refused (USAGE) and
 *    leaves the first working; after halo_vtk_remove the mapper takes a new install;
 *  - the application deletes its mapper, volume, renderer and window before
 *    halo_vtk_remove: the install holds its own references, nothing is used after free
 *    (under AddressSanitizer in CI);
 *  - NULL arguments and a NULL diagnostics list: a NULL result or HALO_ERROR_INPUT, no crash;
 *  - halo_vtk_check before any render says so;
 *  - the texture units the adapter binds by number: held during the render, given back,
 *    a unit the application holds refused;
 *  - a halo field over its cap (field_max_bytes): the scene linked again at 1/2 keeps a
 *    vec3 live value set before the first render (the image of an install at 1/2 with
 *    the same value, exactly; without the value it differs). */
#include "halo.h"
#include "halo_vtk.h"
#include "test_ball.h"

#include <vtkAutoInit.h>
#include <vtkColorTransferFunction.h>
#include <vtkGPUVolumeRayCastMapper.h>
#include <vtkImageData.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkPiecewiseFunction.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTextureUnitManager.h>
#include <vtkVolume.h>
#include <vtkVolumeProperty.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

VTK_MODULE_INIT(vtkRenderingOpenGL2);
VTK_MODULE_INIT(vtkRenderingVolumeOpenGL2);

static int failures = 0;
#define CHECK(cond, what)                                                    \
    do {                                                                     \
        if (!(cond)) {                                                       \
            fprintf(stderr, "FAIL: %s (%s:%d)\n", what, __FILE__, __LINE__); \
            failures++;                                                      \
        }                                                                    \
    } while (0)

/* A small volume (a ball) in a mapper, a volume, a renderer and an offscreen window. */
struct scene_objects {
    vtkSmartPointer<vtkGPUVolumeRayCastMapper> mapper;
    vtkSmartPointer<vtkVolume> volume;
    vtkSmartPointer<vtkRenderer> renderer;
    vtkSmartPointer<vtkRenderWindow> window;
};

static scene_objects make_objects(int halo_mapper)
{
    vtkSmartPointer<vtkImageData> image = test_ball(0);
    scene_objects o;
    o.mapper.TakeReference(halo_mapper ? halo_vtk_mapper_new() : vtkGPUVolumeRayCastMapper::New());
    o.mapper->SetInputData(image);
    vtkSmartPointer<vtkColorTransferFunction> color = vtkSmartPointer<vtkColorTransferFunction>::New();
    color->AddRGBPoint(0.0, 0.0, 0.0, 0.0);
    color->AddRGBPoint(1.0, 1.0, 0.8, 0.6);
    vtkSmartPointer<vtkPiecewiseFunction> opacity = vtkSmartPointer<vtkPiecewiseFunction>::New();
    opacity->AddPoint(0.0, 0.0);
    opacity->AddPoint(1.0, 0.5);
    vtkSmartPointer<vtkVolumeProperty> property = vtkSmartPointer<vtkVolumeProperty>::New();
    property->SetColor(color);
    property->SetScalarOpacity(opacity);
    o.volume = vtkSmartPointer<vtkVolume>::New();
    o.volume->SetMapper(o.mapper);
    o.volume->SetProperty(property);
    o.renderer = vtkSmartPointer<vtkRenderer>::New();
    o.renderer->AddVolume(o.volume);
    o.window = vtkSmartPointer<vtkRenderWindow>::New();
    o.window->SetOffScreenRendering(1);
    o.window->SetSize(32, 32);
    o.window->AddRenderer(o.renderer);
    return o;
}

static halo_vtk_desc desc_for(const scene_objects &o, const halo_library *lib, const halo_scene *scene)
{
    halo_vtk_desc desc = {};
    desc.mapper = o.mapper;
    desc.volume = o.volume;
    desc.renderer = o.renderer;
    desc.library = lib;
    desc.scene = scene;
    return desc;
}

static halo_vtk *install(const scene_objects &o, const halo_library *lib, const halo_scene *scene,
                         halo_diagnostics *diag)
{
    halo_vtk_desc desc = desc_for(o, lib, scene);
    return halo_vtk_install(&desc, diag);
}

/* An install of the halos scene with every parameter live, halo images at 1/image_scale and
 * the field capped at max_bytes; color_near (NULL: the scene's) set before the first
 * render. The window's pixels after one render (empty when the install failed), the
 * program's image scale then. */
static std::vector<unsigned char> capped_render(const halo_library *lib, const halo_scene *scene, int image_scale,
                                                size_t max_bytes, const double *color_near, int *scale_after,
                                                halo_diagnostics *diag)
{
    scene_objects o = make_objects(1);
    halo_vtk_desc desc = desc_for(o, lib, scene);
    desc.all_live = 1;
    desc.image_scale = image_scale;
    desc.field_max_bytes = max_bytes;
    halo_vtk *h = halo_vtk_install(&desc, diag);
    std::vector<unsigned char> pixels;
    if (!h)
        return pixels;
    if (!color_near || halo_vtk_set(h, "halo_map", "color_near", color_near, 1, diag) == HALO_OK) {
        o.window->Render();
        unsigned char *data = o.window->GetRGBACharPixelData(0, 0, 31, 31, 0);
        if (data)
            pixels.assign(data, data + 32 * 32 * 4);
        delete[] data;
    }
    *scale_after = halo_program_reflection(halo_vtk_program(h)).image_scale;
    halo_vtk_remove(h);
    return pixels;
}

static int max_difference(const std::vector<unsigned char> &a, const std::vector<unsigned char> &b)
{
    int worst = a.size() == b.size() && !a.empty() ? 0 : 256;
    for (size_t i = 0; i < a.size() && i < b.size(); i++)
        worst = abs(a[i] - b[i]) > worst ? abs(a[i] - b[i]) : worst;
    return worst;
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
    halo_scene *plain =
        halo_scene_load("plain", "{\"halo_scene\": 1, \"stages\": [{\"tone_shading\": {}}]}", lib, diag);
    halo_scene *halos = halo_scene_load("halos",
                                        "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {}}, {\"halo_generate\": "
                                        "{}}, {\"halo_map\": {}}]}",
                                        lib, diag);
    CHECK(lib && plain && halos, "the library and scenes");
    if (!lib || !plain || !halos) {
        halo_diagnostics_print(diag, stderr);
        return 99;
    }

    /* a second install on the same mapper and volume is refused; the first keeps working */
    {
        scene_objects o = make_objects(1);
        halo_vtk *first = install(o, lib, halos, diag);
        CHECK(first, "the first install");
        halo_diagnostics_clear(diag);
        CHECK(!install(o, lib, plain, diag), "a second install on the same mapper is refused");
        CHECK(halo_diagnostics_has(diag, HALO_MSG_USAGE), "... with USAGE");
        halo_diagnostics_clear(diag);
        CHECK(halo_vtk_check(first, diag) != HALO_OK && halo_diagnostics_describe(diag).count > 0,
              "halo_vtk_check before a render says so");
        halo_diagnostics_clear(diag);
        o.window->Render();
        CHECK(halo_vtk_check(first, diag) == HALO_OK, "the first install still draws after the refusal");
        halo_diagnostics_print(diag, stderr);
        halo_diagnostics_clear(diag);
        halo_vtk_remove(first);
        halo_vtk *again = install(o, lib, plain, diag);
        CHECK(again, "after halo_vtk_remove the mapper takes a new install");
        o.window->Render();
        CHECK(again && halo_vtk_check(again, diag) == HALO_OK, "... and draws with it");
        halo_diagnostics_print(diag, stderr);
        halo_diagnostics_clear(diag);
        halo_vtk_remove(again);
        /* a removed handle: a second remove does nothing, set and check say USAGE (the
         * address is compared with the live installs, never read: ASan would see a read) */
        halo_vtk_remove(again);
        double v = 0.5;
        CHECK(halo_vtk_set(again, "tone_shading", "k_ta", &v, 1, diag) == HALO_ERROR_INPUT &&
                  halo_diagnostics_has(diag, HALO_MSG_USAGE),
              "halo_vtk_set after halo_vtk_remove: USAGE");
        halo_diagnostics_clear(diag);
        CHECK(halo_vtk_check(again, diag) == HALO_ERROR_INPUT && halo_diagnostics_has(diag, HALO_MSG_USAGE),
              "halo_vtk_check after halo_vtk_remove: USAGE");
        halo_diagnostics_clear(diag);
        CHECK(halo_vtk_set(nullptr, "tone_shading", "k_ta", &v, 1, diag) == HALO_ERROR_INPUT &&
                  halo_diagnostics_has(diag, HALO_MSG_USAGE),
              "halo_vtk_set(NULL, ..., diag): a diagnostic");
        halo_diagnostics_clear(diag);
    }

    /* the application's references go before the install: halo_vtk_remove after them */
    for (int halo_mapper = 0; halo_mapper < 2; halo_mapper++) {
        halo_vtk *h;
        {
            scene_objects o = make_objects(halo_mapper);
            h = install(o, lib, halo_mapper ? halos : plain, diag);
            CHECK(h, "an install to outlive its objects");
            o.window->Render();
            CHECK(h && halo_vtk_check(h, diag) == HALO_OK, "it draws");
            halo_diagnostics_print(diag, stderr);
            halo_diagnostics_clear(diag);
        } /* the mapper, volume, renderer and window: the application's references dropped */
        halo_vtk_remove(h);
    }

    /* the texture units the adapter binds by number are held in VTK's texture unit manager
     * during the volume's render and given back after; one already held is refused */
    for (int halo_mapper = 0; halo_mapper < 2; halo_mapper++) {
        scene_objects o = make_objects(halo_mapper);
        halo_vtk *h = install(o, lib, halo_mapper ? halos : plain, diag);
        o.window->Render();
        vtkTextureUnitManager *units = vtkOpenGLRenderWindow::SafeDownCast(o.window)->GetTextureUnitManager();
        CHECK(h && halo_vtk_check(h, diag) == HALO_OK, "the units: a render");
        CHECK(units && !units->IsAllocated(19) && !units->IsAllocated(20), "the units are given back after the render");
        halo_diagnostics_print(diag, stderr);
        halo_diagnostics_clear(diag);
        halo_vtk_remove(h);
        h = install(o, lib, halo_mapper ? halos : plain, diag);
        if (units)
            units->Allocate(19);
        o.window->Render();
        CHECK(h && halo_vtk_check(h, diag) != HALO_OK && halo_diagnostics_has(diag, HALO_MSG_ENGINE_UNSUPPORTED),
              "a texture unit held by the application is refused with ENGINE_UNSUPPORTED");
        halo_diagnostics_clear(diag);
        if (units)
            units->Free(19);
        halo_vtk_remove(h);
    }

    /* a field over its cap, linked again at 1/2: a vec3 live value set before the first
     * render stays. The cap: 1.25 x the field at 1/2, from the field at 1/4 (8 x 8 pixels
     * a layer, 1/4 of 16 x 16) that an install at 1/4 over a cap of one byte reports */
    halo_scene *seen =
        halo_scene_load("seen halos", /* halos seeded on the ramp ball's edge (|grad| 0.2 a voxel) */
                        "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {\"gradient_scale\": 6, \"alpha\": 1}}, "
                        "{\"halo_generate\": {}}, {\"halo_map\": {\"full_at\": 0.25}}]}",
                        lib, diag);
    CHECK(seen, "the scene of visible halos");
    if (seen) {
        int scale = 0, layers = 0;
        size_t bytes = 0;
        capped_render(lib, seen, 4, 1, nullptr, &scale, diag);
        for (size_t i = 0; i < halo_diagnostics_describe(diag).count; i++) {
            const char *text = halo_diagnostics_get(diag, i)->text, *at = strstr(text, "field of ");
            const char *per = strstr(text, " MiB (");
            if (halo_diagnostics_get(diag, i)->id == HALO_MSG_FIELD_MEMORY && at && per)
                sscanf(at, "field of %d layers", &layers), sscanf(per, " MiB (%zu bytes a layer", &bytes);
        }
        CHECK(layers > 0 && bytes > 0, "a field at 1/4 over a cap of one byte: FIELD_MEMORY with its layers and bytes");
        halo_diagnostics_clear(diag);
        size_t cap = (size_t)layers * bytes * 4 * 5 / 4;
        static const double red[3] = {1.0, 0.0, 0.0};
        int capped_scale = 0, half_scale = 0;
        std::vector<unsigned char> capped = capped_render(lib, seen, 0, cap, red, &capped_scale, diag);
        CHECK(halo_diagnostics_has(diag, HALO_MSG_FIELD_MEMORY) && capped_scale == 2,
              "a field over its cap: linked again at 1/2, with a warning");
        halo_diagnostics_clear(diag);
        std::vector<unsigned char> half = capped_render(lib, seen, 2, 0, red, &half_scale, diag);
        std::vector<unsigned char> plain_half = capped_render(lib, seen, 2, 0, nullptr, &half_scale, diag);
        halo_diagnostics_print(diag, stderr);
        halo_diagnostics_clear(diag);
        int kept = max_difference(capped, half), value = max_difference(half, plain_half);
        printf(
            "a field over a cap of %zu bytes, linked again at 1/%d: color_near set before it, against an install at "
            "1/2 with it: max abs %d/255; the value's effect %d/255\n",
            cap, capped_scale, kept, value);
        CHECK(kept == 0, "the live value set before the relink is kept");
        CHECK(value > 0 && value < 256, "color_near changes the image (else the check above sees nothing)");
    }
    halo_scene_destroy(seen);

    /* NULL arguments, NULL diagnostics */
    CHECK(!halo_vtk_install(nullptr, nullptr), "halo_vtk_install(NULL, NULL)");
    halo_vtk_desc empty = {};
    CHECK(!halo_vtk_install(&empty, nullptr), "an empty desc, NULL diag");
    halo_vtk_remove(nullptr);
    double one = 1.0;
    CHECK(halo_vtk_set(nullptr, "tone_shading", "k_ta", &one, 1, nullptr) == HALO_ERROR_INPUT, "halo_vtk_set(NULL)");
    CHECK(halo_vtk_check(nullptr, nullptr) == HALO_ERROR_INPUT, "halo_vtk_check(NULL)");
    CHECK(halo_vtk_set_whole_extent(nullptr, nullptr) == HALO_ERROR_INPUT, "halo_vtk_set_whole_extent(NULL)");
    CHECK(!halo_vtk_program(nullptr) && halo_vtk_build_count(nullptr) == 0, "the getters on NULL");
    {
        scene_objects o = make_objects(0);
        halo_vtk *h = install(o, lib, plain, nullptr);
        CHECK(h, "an install with a NULL diagnostics list");
        CHECK(halo_vtk_set(h, "no_such_stage", "k", &one, 1, nullptr) != HALO_OK, "a bad set with NULL diag");
        CHECK(!install(o, lib, plain, nullptr), "a second install with NULL diag is refused");
        halo_vtk_remove(h);
    }

    halo_scene_destroy(plain);
    halo_scene_destroy(halos);
    halo_library_destroy(lib);
    halo_diagnostics_destroy(diag);
    halo_shutdown();
    if (failures)
        fprintf(stderr, "%d failed\n", failures);
    else
        printf("test_vtk_lifetimes: all passed\n");
    return failures ? 1 : 0;
}
