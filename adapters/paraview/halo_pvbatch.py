"""halo_pvbatch.py: renders a volume with libhalo's stages in ParaView, on as many MPI
ranks as pvbatch runs on (docs/distributed.md).

    halo-vtk --scene S --volume-size 64 --size 256x256 --export /tmp/v   # the volume and view
    mpirun -np 4 pvbatch halo_pvbatch.py --plugin HaloVolume.so --view /tmp/v --scene S -o out.png

The volume (a float32 raw cube from halo-vtk --export) is read by ParaView's image
reader, which gives every rank its own brick; ParaView composites the ranks' images in
visibility order (IceT). The view (camera, transfer function, background) is halo-vtk's,
so the image can be compared with halo-vtk's and halo-render's.
"""
import argparse
import json
import sys
import time

from paraview.simple import (
    GetActiveViewOrCreate, GetColorTransferFunction, GetOpacityTransferFunction, ImageReader,
    LoadPlugin, Render, SaveScreenshot, Show)
from paraview import servermanager


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--plugin", required=True, help="the HaloVolume plugin (HaloVolume.so)")
    p.add_argument("--view", required=True, help="PREFIX of halo-vtk --export (PREFIX.raw, PREFIX.json)")
    p.add_argument("--scene", default="", help="libhalo scene file; none: ParaView's own volume rendering")
    p.add_argument("--settings", default="", help="stage.param=v[,v...];... over the scene's")
    p.add_argument("--exchange", type=int, default=1, help="1: halos cross the ranks' pieces; 0: each rank's own")
    p.add_argument("--image-scale", type=int, default=1, choices=[1, 2, 4],
                   help="halo images and libhalo's march at 1/N of the view per side")
    p.add_argument("--screenshot-scale", type=int, default=1, choices=range(1, 9), metavar="N",
                   help="save the image N times the view's size (ParaView renders it in N x N tiles, as the "
                        "GUI's Save Screenshot above the view's size)")
    p.add_argument("--frames", type=int, default=1, help="render this many frames and print the mean time")
    p.add_argument("--paraview-volume", action="store_true",
                   help="ParaView's own \"Volume\" representation instead of \"Halo Volume\" (no scene)")
    p.add_argument("--shade", action="store_true",
                   help="the representation's Shade on (VTK's lighting; the stages then take VTK's gradient)")
    p.add_argument("-o", "--output", help="the image (.png)")
    p.add_argument("--jobs", help="a file of renders, one a line: OUTPUT SCENE|- [EXCHANGE [SETTINGS]] "
                   "(one pvbatch start for many images)")
    a = p.parse_args()
    jobs = []
    if a.output:
        jobs.append((a.output, a.scene, a.exchange, a.settings))
    if a.jobs:
        with open(a.jobs) as f:
            for line in f:
                w = line.split()
                if not w or w[0].startswith("#"):
                    continue
                jobs.append((w[0], "" if len(w) < 2 or w[1] == "-" else w[1],
                             int(w[2]) if len(w) > 2 else 1, w[3] if len(w) > 3 else ""))
    if not jobs:
        p.error("-o or --jobs is required")

    with open(a.view + ".json") as f:
        view_desc = json.load(f)
    n = view_desc["size"]
    LoadPlugin(a.plugin, remote=False, ns=globals())

    # the display cube on VTK's point grid at voxel centres: world = texture coordinates
    reader = ImageReader(FileNames=[a.view + ".raw"])
    reader.DataScalarType = "float"
    reader.DataByteOrder = "LittleEndian"
    reader.DataExtent = [0, n - 1, 0, n - 1, 0, n - 1]
    reader.DataSpacing = [1.0 / n] * 3
    reader.DataOrigin = [0.5 / n] * 3

    view = GetActiveViewOrCreate("RenderView")
    width, height = view_desc["image"]
    view.ViewSize = [width, height]
    view.OrientationAxesVisibility = 0
    view.Background = view_desc["background"]
    try:  # ParaView 5.10+: the background is the palette's unless told otherwise
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass

    rep = Show(reader, view)
    rep.ColorArrayName = ["POINTS", "ImageFile"]
    rep.SetRepresentationType("Volume" if a.paraview_volume else "Halo Volume")
    if a.paraview_volume and any(scene for _, scene, _, _ in jobs):
        p.error("--paraview-volume draws ParaView's own volume: no scene")
    ctf = GetColorTransferFunction("ImageFile")
    otf = GetOpacityTransferFunction("ImageFile")
    rgb, points = [], []
    for x, r, g, b, alpha in view_desc["transfer"]:
        rgb += [x, r, g, b]
        points += [x, alpha, 0.5, 0.0]
    ctf.RGBPoints = rgb
    ctf.ColorSpace = "RGB"
    ctf.AutomaticRescaleRangeMode = "Never"
    otf.Points = points
    rep.LookupTable = ctf
    rep.ScalarOpacityFunction = otf
    rep.ScalarOpacityUnitDistance = 1.0 / n
    rep.Shade = 1 if a.shade else 0
    if not a.paraview_volume:
        rep.HaloWindow = [0.0, 1.0]

    cam = view_desc["camera"]
    view.CameraPosition = cam["eye"]
    view.CameraFocalPoint = cam["focus"]
    view.CameraViewUp = cam["up"]
    view.CameraViewAngle = cam["view_angle"]
    view.CameraParallelProjection = 0

    status = 0
    for output, scene, exchange, settings in jobs:
        if not a.paraview_volume:
            rep.HaloScene = scene
            rep.HaloSettings = settings
            rep.HaloExchange = exchange
            rep.HaloImageScale = a.image_scale
        render(view, output, a.frames, width, height, a.screenshot_scale)
        # a refused or failed scene (its reason is on stderr): the script's exit status says so
        if a.paraview_volume:
            continue
        rep.UpdatePropertyInformation()
        if scene and rep.GetPropertyValue("HaloStatus"):
            print("halo_pvbatch: %s: the scene %s was not drawn (see the errors above)" % (output, scene),
                  file=sys.stderr)
            status = 1
    return status


def render(view, output, frames, width, height, scale=1):
    Render(view)
    if frames > 1:
        # the camera turning 0.001 degrees back and forth, as a user turns the volume: the
        # halo field is computed every frame (drawn again with an unchanged view, libhalo
        # reuses it); the view is put back after
        camera = view.GetActiveCamera()
        kept = (camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp())
        t0 = time.time()
        for f in range(frames):
            camera.Azimuth(-1e-3 if f % 2 else 1e-3)
            view.StillRender()
        ms = (time.time() - t0) * 1000.0 / frames
        camera.SetPosition(kept[0])
        camera.SetFocalPoint(kept[1])
        camera.SetViewUp(kept[2])
        ranks = servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
        print("halo_pvbatch: %s: %.1f ms per frame (%d frames, %dx%d, %d rank%s)" %
              (output, ms, frames, width, height, ranks, "" if ranks == 1 else "s"))
    SaveScreenshot(output, view, ImageResolution=[width * scale, height * scale], TransparentBackground=0)


# no sys.exit on success: pvbatch tears its render window down after the script, and an
# exit from inside the script closes the X display first (GLXBadContext)
if main() != 0:
    sys.exit(1)
