/* halo-vtk: renders a volume with a scene through VTK's GPU ray caster
 * (vtkGPUVolumeRayCastMapper) with libhalo's stages installed by the VTK adapter
 * (adapters/vtk/halo_vtk.h), to PNG or EXR. The volume, camera, transfer function and
 * step are halo-render's (the same display cube, the same orbit camera), so that the
 * two renderers can be compared. Needs an X display (xvfb-run). docs/hosts/vtk.md. */
#include "halo.h"
#include "halo_vtk.h"
#include "image_write.h"

#include <vtkWindowToImageFilter.h>
extern "C" {
#include "hosts/host_common.h"
#include "hosts/raycast.h"
#include "volume.h"
#include "volume_io.h"
}

#include <vtkAutoInit.h>
#include <vtkCamera.h>
#include <vtkColorTransferFunction.h>
#include <vtkFloatArray.h>
#include <vtkGPUVolumeRayCastMapper.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPiecewiseFunction.h>
#include <vtkPointData.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkVolume.h>
#include <vtkVolumeProperty.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

VTK_MODULE_INIT(vtkRenderingOpenGL2);
VTK_MODULE_INIT(vtkRenderingVolumeOpenGL2);

namespace
{

const char usage_text[] =
    "usage: halo-vtk [OPTIONS]\n"
    "Renders a volume with a scene's per-sample stages inside VTK's GPU ray caster.\n"
    "  --scene FILE        the scene (docs/scene.md); without one, VTK renders alone\n"
    "  --volume FILE       a NIfTI volume (default: the built-in volume)\n"
    "  --window LOW:HIGH   intensity window of the NIfTI volume (default: the scene's\n"
    "                      render.window, else the 1st..99th percentile)\n"
    "  --volume-size N     side of the display cube (default: 96 built-in, else from the file)\n"
    "  --size WxH          image size (default 256x256)\n"
    "  -o FILE             output image, .png or .exr (default halo-vtk.png)\n"
    "  --no-stages         the scene's volume, camera and transfer function, VTK alone\n"
    "  --plain-mapper      VTK's own vtkGPUVolumeRayCastMapper (one pass: per-sample stages\n"
    "                      only) instead of halo_vtk_mapper_new's\n"
    "  --segments          halo_vtk_mapper_new's mapper draws VTK's volume once per depth\n"
    "                      segment (host contract 2) instead of once over the halo field\n"
    "  --shade             VTK's own shading on (Phong, its headlight); the stages then read\n"
    "                      VTK's gradient instead of the adapter's (docs/hosts/vtk.md)\n"
    "  --own-gradient      the stages read the adapter's gradient even with --shade\n"
    "  --blend MODE        composite (default), mip or additive: VTK's blend mode\n"
    "  --set STAGE.PARAM=V[,V...]  after a first render, change a live parameter and\n"
    "                      render again (prints whether VTK rebuilt its shader)\n"
    "  --halo-scale S      halo images (and libhalo's march) at 1/S of the image per side:\n"
    "                      1 (default), 2 or 4\n"
    "  --field-max-mib N   drawn once: the cap on the frame's halo field in MiB (default 1024);\n"
    "                      a field over it is drawn at twice the scale, with a warning\n"
    "  --frames N          render N frames and print the mean frame time\n"
    "  --tile-scale N      write the image N times the size, rendered by VTK in N x N tiles\n"
    "                      (vtkWindowToImageFilter, as a screenshot larger than the window)\n"
    "  --export PREFIX     write the display cube (PREFIX.raw: float32, N^3, x fastest) and\n"
    "                      the scene's view (PREFIX.json: size, step, transfer function,\n"
    "                      camera, background) for another renderer (ParaView:\n"
    "                      docs/distributed.md), then exit; needs no display\n"
    "  --quiet             print only errors\n"
    "exit status: 0 success, 1 the input has errors, 2 usage or I/O, 77 no display\n";

int usage_error(const std::string &text)
{
    fprintf(stderr, "halo-vtk: error: %s\nTry 'halo-vtk --help'.\n", text.c_str());
    return 2;
}

struct options {
    const char *scene = nullptr, *volume = nullptr, *output = "halo-vtk.png", *blend = "composite",
               *export_to = nullptr;
    double window[2] = {0, 0};
    int have_window = 0, volume_size = 0, width = 256, height = 256, frames = 1, quiet = 0, no_stages = 0,
        plain_mapper = 0, shade = 0, own_gradient = 0;
    int segments = 0, tile_scale = 1, halo_scale = 1;
    double field_max_mib = 0.0;
    std::vector<std::string> sets;
};

int parse(int argc, char **argv, options *o)
{
    for (int i = 1; i < argc; i++) {
        std::string a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : nullptr;
        auto need = [&](void) { return v ? (i++, true) : false; };
        if (a == "--help" || a == "-h") {
            fputs(usage_text, stdout);
            exit(0);
        } else if (a == "--quiet") {
            o->quiet = 1;
        } else if (a == "--no-stages") {
            o->no_stages = 1;
        } else if (a == "--plain-mapper") {
            o->plain_mapper = 1;
        } else if (a == "--shade") {
            o->shade = 1;
        } else if (a == "--own-gradient") {
            o->own_gradient = 1;
        } else if (a == "--segments") {
            o->segments = 1;
        } else if (a == "--scene" && need()) {
            o->scene = v;
        } else if (a == "--volume" && need()) {
            o->volume = v;
        } else if ((a == "-o" || a == "--output") && need()) {
            o->output = v;
        } else if (a == "--blend" && need()) {
            o->blend = v;
            if (strcmp(v, "composite") && strcmp(v, "mip") && strcmp(v, "additive"))
                return usage_error(std::string("--blend takes composite, mip or additive, not '") + v + "'");
        } else if (a == "--export" && need()) {
            o->export_to = v;
        } else if (a == "--set" && need()) {
            o->sets.push_back(v);
        } else if (a == "--window" && need()) {
            if (sscanf(v, "%lf:%lf", &o->window[0], &o->window[1]) != 2 || !(o->window[1] > o->window[0]))
                return usage_error(std::string("--window takes LOW:HIGH with HIGH above LOW, not '") + v + "'");
            o->have_window = 1;
        } else if (a == "--volume-size" && need()) {
            char *end;
            long n = strtol(v, &end, 10);
            if (*end || n < HALO_VOLUME_MIN_SIZE || n > HALO_VOLUME_MAX_SIZE)
                return usage_error(std::string("--volume-size takes 8..512, not '") + v + "'");
            o->volume_size = (int)n;
        } else if (a == "--tile-scale" && need()) {
            char *end;
            long n = strtol(v, &end, 10);
            if (*end || n < 1 || n > 8)
                return usage_error(std::string("--tile-scale takes 1..8, not '") + v + "'");
            o->tile_scale = (int)n;
        } else if (a == "--halo-scale" && need()) {
            if (strcmp(v, "1") && strcmp(v, "2") && strcmp(v, "4"))
                return usage_error(std::string("--halo-scale takes 1, 2 or 4, not '") + v + "'");
            o->halo_scale = atoi(v);
        } else if (a == "--field-max-mib" && need()) {
            char *end;
            double n = strtod(v, &end);
            if (*end || !(n >= 0.01 && n <= 1048576.0))
                return usage_error(std::string("--field-max-mib takes 0.01..1048576, not '") + v + "'");
            o->field_max_mib = n;
        } else if (a == "--frames" && need()) {
            char *end;
            long n = strtol(v, &end, 10);
            if (*end || n < 1 || n > 1000)
                return usage_error(std::string("--frames takes 1..1000, not '") + v + "'");
            o->frames = (int)n;
        } else if (a == "--size" && need()) {
            if (sscanf(v, "%dx%d", &o->width, &o->height) != 2 || o->width < 1 || o->height < 1 || o->width > 8192 ||
                o->height > 8192)
                return usage_error(std::string("--size takes WxH (1..8192), not '") + v + "'");
        } else {
            return usage_error("unknown option or missing value: '" + a + "'");
        }
    }
    return 0;
}

/* The display cube: the built-in volume, or the NIfTI file through halo-render's window
 * and resampling. */
float *load_volume(const options &o, const halo_render_settings *settings, int *size)
{
    if (!o.volume) {
        *size = o.volume_size ? o.volume_size : HALO_VOLUME_DEFAULT_SIZE;
        float *v = halo_volume_create(*size);
        if (!v)
            fprintf(stderr, "halo-vtk: error: out of memory for the built-in volume\n");
        return v;
    }
    halo_volume_file file = {};
    char err[512];
    if (halo_volume_read_nifti(o.volume, &file, err, sizeof err) != HALO_VOLUME_OK) {
        fprintf(stderr, "halo-vtk: error: %s\n", err);
        return nullptr;
    }
    double window[2];
    if (o.have_window) {
        window[0] = o.window[0];
        window[1] = o.window[1];
    } else if (settings->window[0] != 0.0 || settings->window[1] != 1.0) {
        window[0] = settings->window[0];
        window[1] = settings->window[1];
    } else {
        halo_volume_percentile_window(&file, 1.0, 99.0, window);
    }
    *size = o.volume_size ? o.volume_size : halo_volume_display_size(&file, HALO_VOLUME_MAX_SIZE);
    float *cube = halo_volume_display_check(&file, *size, err, sizeof err) == HALO_VOLUME_OK
                      ? halo_volume_to_display(&file, window, *size)
                      : nullptr;
    if (!cube)
        fprintf(stderr, "halo-vtk: error: %s: %s\n", o.volume, err);
    halo_volume_file_free(&file);
    return cube;
}

/* --export: the cube and the view halo-vtk would render, for another renderer. */
int export_view(const options &o, const halo_render_settings *settings, const float *cube, int size)
{
    std::string raw = std::string(o.export_to) + ".raw", json = std::string(o.export_to) + ".json";
    FILE *f = fopen(raw.c_str(), "wb");
    size_t n = (size_t)size * size * size;
    int ok = f && fwrite(cube, sizeof(float), n, f) == n;
    ok = (f && fclose(f) == 0) && ok;
    if (!ok) {
        fprintf(stderr, "halo-vtk: error: %s: %s\n", raw.c_str(), strerror(errno));
        return 2;
    }
    std::vector<float> table(HALO_RAYCAST_TRANSFER_TEXELS * 4);
    halo_host_fill_transfer(table.data(), settings);
    halo_host_camera cam;
    halo_host_orbit_camera(settings->azimuth, settings->elevation, settings->zoom, o.width, o.height, &cam);
    f = fopen(json.c_str(), "w");
    if (!f) {
        fprintf(stderr, "halo-vtk: error: %s: %s\n", json.c_str(), strerror(errno));
        return 2;
    }
    fprintf(f, "{\n  \"size\": %d,\n  \"step\": %.9g,\n  \"image\": [%d, %d],\n", size, settings->step, o.width,
            o.height);
    fprintf(f, "  \"background\": [%.9g, %.9g, %.9g],\n", settings->background[0], settings->background[1],
            settings->background[2]);
    fprintf(f,
            "  \"camera\": {\"eye\": [%.9g, %.9g, %.9g], \"up\": [%.9g, %.9g, %.9g], \"focus\": [0.5, 0.5, 0.5], "
            "\"view_angle\": %.9g},\n",
            cam.eye[0], cam.eye[1], cam.eye[2], cam.up[0], cam.up[1], cam.up[2], (double)HALO_RAYCAST_FIELD_OF_VIEW);
    fprintf(f, "  \"transfer\": [");
    for (int i = 0; i < HALO_RAYCAST_TRANSFER_TEXELS; i++)
        fprintf(f, "%s\n    [%.9g, %.9g, %.9g, %.9g, %.9g]", i ? "," : "",
                (double)i / (HALO_RAYCAST_TRANSFER_TEXELS - 1), table[i * 4], table[i * 4 + 1], table[i * 4 + 2],
                table[i * 4 + 3]);
    fprintf(f, "\n  ]\n}\n");
    if (fclose(f) != 0) {
        fprintf(stderr, "halo-vtk: error: %s: %s\n", json.c_str(), strerror(errno));
        return 2;
    }
    if (!o.quiet)
        printf("halo-vtk: wrote %s and %s (%d^3)\n", raw.c_str(), json.c_str(), size);
    return 0;
}

} // namespace

int main(int argc, char **argv)
{
    options o;
    if (int st = parse(argc, argv, &o))
        return st;
    if (!o.export_to && !getenv("DISPLAY")) {
        fprintf(stderr, "halo-vtk: VTK's renderer needs an X display (run under xvfb-run)\n");
        return 77;
    }
    halo_setup_desc setup = {};
    halo_setup(&setup);
    halo_diagnostics *diag = halo_diagnostics_create();
    halo_library *lib = halo_library_create(diag);
    halo_scene *scene = lib && o.scene ? halo_scene_load(o.scene, nullptr, lib, diag)
                        : lib          ? halo_scene_create(lib)
                                       : nullptr;
    int status = 0;
    if (!scene) {
        halo_diagnostics_print(diag, stderr);
        return 1;
    }
    const halo_render_settings *settings = halo_scene_describe(scene).render;
    int size = 0;
    float *cube = load_volume(o, settings, &size);
    if (!cube)
        return 1;
    if (o.export_to) {
        status = export_view(o, settings, cube, size);
        free(cube);
        halo_scene_destroy(scene);
        halo_library_destroy(lib);
        halo_diagnostics_destroy(diag);
        return status;
    }

    /* The cube in VTK: point i at (i + 0.5) / size, so that VTK's world coordinates are
     * halo-render's texture coordinates. */
    vtkNew<vtkImageData> image;
    image->SetDimensions(size, size, size);
    image->SetSpacing(1.0 / size, 1.0 / size, 1.0 / size);
    image->SetOrigin(0.5 / size, 0.5 / size, 0.5 / size);
    vtkNew<vtkFloatArray> values;
    values->SetNumberOfComponents(1);
    values->SetArray(cube, (vtkIdType)size * size * size, 1); /* 1: VTK does not free it */
    image->GetPointData()->SetScalars(values);

    /* halo-render's transfer function: value in [0,1] (the window), opacity per voxel step */
    vtkNew<vtkColorTransferFunction> color;
    vtkNew<vtkPiecewiseFunction> opacity;
    std::vector<float> table(HALO_RAYCAST_TRANSFER_TEXELS * 4);
    halo_host_fill_transfer(table.data(), settings);
    for (int i = 0; i < HALO_RAYCAST_TRANSFER_TEXELS; i++) {
        double x = (double)i / (HALO_RAYCAST_TRANSFER_TEXELS - 1);
        color->AddRGBPoint(x, table[i * 4], table[i * 4 + 1], table[i * 4 + 2]);
        opacity->AddPoint(x, table[i * 4 + 3]);
    }
    vtkNew<vtkVolumeProperty> property;
    property->SetColor(color);
    property->SetScalarOpacity(opacity);
    property->SetInterpolationTypeToLinear();
    if (o.shade)
        property->ShadeOn();
    else
        property->ShadeOff();
    property->SetScalarOpacityUnitDistance(1.0 / size);

    /* libhalo-vtk's mapper: VTK's own, drawn in depth segments when the scene has halos */
    vtkSmartPointer<vtkGPUVolumeRayCastMapper> mapper;
    mapper.TakeReference(o.plain_mapper ? vtkGPUVolumeRayCastMapper::New() : halo_vtk_mapper_new());
    mapper->SetInputData(image);
    mapper->AutoAdjustSampleDistancesOff();
    mapper->SetSampleDistance((float)(settings->step / size));
    mapper->SetBlendMode(!strcmp(o.blend, "mip")        ? vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND
                         : !strcmp(o.blend, "additive") ? vtkVolumeMapper::ADDITIVE_BLEND
                                                        : vtkVolumeMapper::COMPOSITE_BLEND);
    vtkNew<vtkVolume> volume;
    volume->SetMapper(mapper);
    volume->SetProperty(property);

    vtkNew<vtkRenderer> renderer;
    renderer->AddVolume(volume);
    renderer->SetBackground(settings->background[0], settings->background[1], settings->background[2]);
    vtkNew<vtkRenderWindow> window;
    window->SetOffScreenRendering(1);
    window->SetSize(o.width, o.height);
    window->SetMultiSamples(0);
    window->AddRenderer(renderer);

    /* halo-render's orbit camera, in the same coordinates */
    halo_host_camera cam;
    halo_host_orbit_camera(settings->azimuth, settings->elevation, settings->zoom, o.width, o.height, &cam);
    vtkCamera *camera = renderer->GetActiveCamera();
    camera->SetPosition(cam.eye);
    camera->SetFocalPoint(0.5, 0.5, 0.5);
    camera->SetViewUp(cam.up);
    double fov = HALO_RAYCAST_FIELD_OF_VIEW;
    if (o.width < o.height) /* VTK's view angle spans the height; halo-render's the smaller side */
        fov = 2.0 * std::atan(std::tan(fov * M_PI / 360.0) * o.height / o.width) * 180.0 / M_PI;
    camera->SetViewAngle(fov);
    double distance =
        std::sqrt(std::pow(cam.eye[0] - 0.5, 2) + std::pow(cam.eye[1] - 0.5, 2) + std::pow(cam.eye[2] - 0.5, 2));
    camera->SetClippingRange(std::max(distance - 0.87, 0.01), distance + 1.87);

    halo_vtk *h = nullptr;
    if (o.scene && !o.no_stages) {
        halo_vtk_desc desc = {};
        desc.mapper = mapper;
        desc.volume = volume;
        desc.renderer = renderer;
        desc.library = lib;
        desc.scene = scene;
        desc.window[0] = 0.0;
        desc.window[1] = 1.0;
        desc.all_live = !o.sets.empty();
        desc.segments = o.segments;
        desc.image_scale = o.halo_scale;
        desc.field_max_bytes = (size_t)(o.field_max_mib * 1048576.0);
        desc.own_gradient = o.own_gradient;
        h = halo_vtk_install(&desc, diag);
        if (!h)
            status = 1; /* the diagnostics are printed at the end */
    }
    if (!status) {
        window->Render();
        if (h && halo_vtk_check(h, diag) != HALO_OK)
            status = 1;
        else if (h && !o.quiet)
            printf("halo-vtk: the stages are in VTK's shader (%zu stage%s, validated)\n",
                   halo_program_reflection(halo_vtk_program(h)).stage_count,
                   halo_program_reflection(halo_vtk_program(h)).stage_count == 1 ? "" : "s");
    }
    for (size_t i = 0; !status && i < o.sets.size(); i++) {
        std::string s = o.sets[i];
        size_t dot = s.find('.'), eq = s.find('=');
        std::vector<double> v;
        for (size_t at = eq == std::string::npos ? std::string::npos : eq + 1;
             at != std::string::npos && at < s.size();) {
            char *end;
            v.push_back(strtod(s.c_str() + at, &end));
            at = *end == ',' ? (size_t)(end - s.c_str()) + 1 : std::string::npos;
        }
        if (!h || dot == std::string::npos || eq == std::string::npos || dot > eq || v.empty()) {
            status = usage_error("--set takes STAGE.PARAM=V[,V...] (with --scene), not '" + s + "'");
            break;
        }
        std::string stage = s.substr(0, dot), param = s.substr(dot + 1, eq - dot - 1);
        const halo_uniform_info *u = halo_program_find_uniform(halo_vtk_program(h), stage.c_str(), param.c_str());
        int components = u ? u->info->components : 1;
        if (v.size() % (size_t)components) {
            status = usage_error("--set " + stage + "." + param + " takes " + std::to_string(components) +
                                 " values per element");
            break;
        }
        int before = halo_vtk_build_count(h);
        if (halo_vtk_set(h, stage.c_str(), param.c_str(), v.data(), (int)v.size() / components, diag) != HALO_OK) {
            status = 1;
            break;
        }
        window->Render();
        printf("halo-vtk: --set %s: %s\n", s.c_str(),
               halo_vtk_build_count(h) == before ? "no shader rebuild" : "VTK rebuilt its shader");
    }
    if (!status && o.frames > 1) {
        auto t0 = std::chrono::steady_clock::now();
        /* the camera turning 0.001 degrees back and forth, as a user turns the volume: the
         * halo field is computed every frame (drawn again with an unchanged view, libhalo
         * reuses it); the view is put back after */
        double position[3], focal[3], up[3];
        camera->GetPosition(position);
        camera->GetFocalPoint(focal);
        camera->GetViewUp(up);
        for (int f = 0; f < o.frames; f++) {
            camera->Azimuth(f % 2 ? -1e-3 : 1e-3);
            window->Render();
        }
        window->WaitForCompletion();
        double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        printf("halo-vtk: %.2f ms per frame (%d frames, %dx%d)\n", ms / o.frames, o.frames, o.width, o.height);
        camera->SetPosition(position);
        camera->SetFocalPoint(focal);
        camera->SetViewUp(up);
    }
    std::vector<float> rgba;
    int out_width = o.width, out_height = o.height;
    if (!status && o.tile_scale > 1) {
        /* VTK renders the larger image tile by tile (its window's TileScale and TileViewport) */
        vtkNew<vtkWindowToImageFilter> grab;
        grab->SetInput(window);
        grab->SetScale(o.tile_scale);
        grab->SetInputBufferTypeToRGBA();
        grab->ReadFrontBufferOff();
        grab->Update();
        if (h && halo_vtk_check(h, diag) != HALO_OK) {
            status = 1;
        } else {
            vtkDataArray *bytes = grab->GetOutput()->GetPointData()->GetScalars();
            out_width = o.width * o.tile_scale;
            out_height = o.height * o.tile_scale;
            rgba.resize((size_t)out_width * (size_t)out_height * 4);
            for (size_t i = 0; bytes && i < rgba.size(); i++)
                rgba[i] = (float)(bytes->GetComponent((vtkIdType)(i / 4), (int)(i % 4)) / 255.0);
        }
    } else if (!status) {
        vtkNew<vtkFloatArray> pixels;
        window->GetRGBAPixelData(0, 0, o.width - 1, o.height - 1, 0, pixels, 0);
        rgba.assign(pixels->GetPointer(0), pixels->GetPointer(0) + (size_t)o.width * o.height * 4);
    }
    if (!status) {
        for (size_t i = 3; i < rgba.size(); i += 4)
            rgba[i] = 1.0f; /* over the opaque background, as halo-render */
        char err[512];
        if (halo_image_write(o.output, out_width, out_height, rgba.data(), err, sizeof err)) {
            fprintf(stderr, "halo-vtk: error: %s\n", err);
            status = 2;
        } else if (!o.quiet) {
            printf("halo-vtk: wrote %s\n", o.output);
        }
    }
    halo_diagnostics_print(diag, stderr);
    halo_vtk_remove(h);
    halo_scene_destroy(scene);
    halo_library_destroy(lib);
    halo_diagnostics_destroy(diag);
    halo_shutdown();
    free(cube);
    return status;
}
