/* vtkHaloVolumeRepresentation: ParaView's volume representation of image data with
 * libhalo's stages (docs/distributed.md). The plugin adds it to image data as the
 * representation type "Halo Volume", with the properties HaloScene, HaloSettings,
 * HaloWindow and HaloExchange.
 *
 * Every rank draws its own piece with libhalo-vtk's segmented mapper; the stages see the
 * whole volume's positions and depth (halo_vtk_set_whole_extent), so that per-sample
 * stages give the same image at any number of ranks. Volumetric halos are seeded in one
 * rank's piece and spread in image space over the others': with HaloExchange on, the
 * seeds of each depth segment are combined over all ranks (a max, as within one rank)
 * before they spread, so every rank spreads the same halo field. */
#ifndef vtkHaloVolumeRepresentation_h
#define vtkHaloVolumeRepresentation_h

#include "HaloRepresentationsModule.h"
#include "vtkImageVolumeRepresentation.h"

class vtkRenderer;
class vtkVolume;

class HALOREPRESENTATIONS_EXPORT vtkHaloVolumeRepresentation : public vtkImageVolumeRepresentation
{
  public:
    static vtkHaloVolumeRepresentation *New();
    vtkTypeMacro(vtkHaloVolumeRepresentation, vtkImageVolumeRepresentation);
    void PrintSelf(ostream &os, vtkIndent indent) override;

    /* A libhalo scene file; empty: no stage (ParaView's own volume rendering). */
    void SetHaloScene(const char *path);
    /* "stage.param=v[,v...]" separated by ';': values over the scene's. */
    void SetHaloSettings(const char *settings);
    /* The data values mapped to 0 and 1; equal: the data's range over all ranks. */
    void SetHaloWindow(double low, double high);
    /* 1 (default): volumetric halos cross the ranks' pieces; 0: each rank's own. */
    void SetHaloExchange(int exchange);
    /* 1 (default), 2 or 4: the halo images (and libhalo's march) at 1/N of the view per side
     * (halo_vtk_desc.image_scale: cheaper, the error in docs/performance.md). */
    void SetHaloImageScale(int scale);
    /* After a render: 0 when the scene (if any) is installed and drawn as asked; 1 when it
   * was refused, failed to load or its draw failed (the reason went to stderr). Read by
   * scripts through the information property HaloStatus (halo_pvbatch.py exits 1). */
    int GetHaloStatus();

    /* The whole dataset's point extent (each rank draws a piece of it). */
    void GetWholeExtentOfPieces(int extent[6]);
    /* Called by the representation's mapper before each render of the volume. */
    void PrepareHalo(vtkRenderer *renderer, vtkVolume *volume);
    /* Called after it: after the first render of an install, halo_vtk_check. */
    void CheckHalo();

  protected:
    vtkHaloVolumeRepresentation();
    ~vtkHaloVolumeRepresentation() override;

    int RequestData(vtkInformation *, vtkInformationVector **, vtkInformationVector *) override;

  private:
    vtkHaloVolumeRepresentation(const vtkHaloVolumeRepresentation &) = delete;
    void operator=(const vtkHaloVolumeRepresentation &) = delete;

    class vtkInternals;
    vtkInternals *Internals;
};

#endif
