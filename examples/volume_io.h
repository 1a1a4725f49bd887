/* Volumes from files for the example renderers: NIfTI-1/NIfTI-2 (.nii, .nii.gz,
 * .hdr/.img) through Debian's nifti2_io, and raw files with explicit dimensions and
 * voxel type. Everything is checked before memory is allocated for it: sizes that
 * overflow, dimensions beyond the limits below, files shorter than their header or
 * dimensions say. Then the volume is windowed to [0,1] and resampled into the cube
 * the example hosts render (docs/halo-render.md, "Volumes").
 *
 * Every function that can fail returns a halo_volume_status (the same numbers as
 * halo-render's exit status) and writes one line naming the file into err. */
#ifndef HALO_EXAMPLE_VOLUME_IO_H
#define HALO_EXAMPLE_VOLUME_IO_H

#include <stddef.h>

typedef enum halo_volume_status {
    HALO_VOLUME_OK = 0,
    HALO_VOLUME_INVALID = 1, /* the file's contents are wrong: not NIfTI, unsupported type, absurd dimensions */
    HALO_VOLUME_IO = 2       /* missing, unreadable or truncated file, out of memory, bad arguments */
} halo_volume_status;

/* Limits: at most this many voxels per side and in all (the first 3-D volume of a
 * 4-D file counts), so that the float copy stays below 2 GiB. */
#define HALO_VOLUME_FILE_MAX_SIDE     8192
#define HALO_VOLUME_FILE_MAX_VOXELS   ((size_t)1 << 29)
/* Above this float copy, halo_volume_read_nifti_for reduces while it reads (256 MiB). */
#define HALO_VOLUME_FILE_STREAM_BYTES ((size_t)256 << 20)

typedef enum halo_voxel_type {
    HALO_VOXEL_UINT8 = 0,
    HALO_VOXEL_UINT16,
    HALO_VOXEL_INT16,
    HALO_VOXEL_FLOAT32,
    HALO_VOXEL_TYPE_COUNT
} halo_voxel_type;

/* "uint8" -> HALO_VOXEL_UINT8 ...; HALO_VOXEL_TYPE_COUNT when unknown. */
halo_voxel_type halo_voxel_type_from_name(const char *name);
const char *halo_voxel_type_name(halo_voxel_type type);

/* A raw file: dims[0]*dims[1]*dims[2] voxels, x fastest, after offset bytes; the
 * file must hold exactly offset + voxels * voxel size bytes. spacing 0 means 1. */
typedef struct halo_raw_desc {
    long dims[3];
    halo_voxel_type type;
    int big_endian;
    double spacing[3];
    long long offset;
} halo_raw_desc;

/* A volume read from a file, in the file's own units (NIfTI scl_slope and scl_inter
 * applied), x fastest. */
typedef struct halo_volume_file {
    int dims[3];
    double spacing[3]; /* voxel size along each file axis (mm for NIfTI; 1 when unknown) */
    /* The file axis shown along each display axis (0 x: the image's right at azimuth 0;
     * 1 y: up; 2 z: towards the camera at azimuth 0) and whether it runs backwards.
     * NIfTI files with an orientation are turned so that the patient's superior is
     * up and anterior faces the camera (patient left on the image's right); other
     * files keep their axes. */
    int display_axis[3];
    int display_flip[3];
    float *data;
    size_t nonfinite;      /* NaN or infinite voxels, replaced by the smallest finite value */
    int discarded_volumes; /* a 4-D file's volumes after the first, not read */
    int reduced;           /* 1, or the factor halo_volume_read_nifti_for reduced each axis by */
    char description[256]; /* "NIfTI-1, uint8, 301x370x316, 0.5x0.5x0.5 mm, L->R P->A I->S" */
} halo_volume_file;

halo_volume_status halo_volume_read_nifti(const char *path, halo_volume_file *out, char *err, size_t err_size);
/* Reads for a cube of a known side (halo_volume_to_display's size; 0: unknown, the same
 * as halo_volume_read_nifti). The voxels are read a z slice at a time, so resident
 * memory is the float copy and one slice, never the file's bytes beside them; and a
 * volume whose float copy would pass HALO_VOLUME_FILE_STREAM_BYTES is reduced while it
 * is read, by the largest integer factor that keeps at least twice the side along its
 * longest axis: each block of factor^3 voxels becomes their mean (labels != 0: the
 * block's first voxel, never a blend of ids), the spacing grows by the factor, and
 * out->reduced and the description say so. A volume and its labels read for the same
 * side are reduced alike. */
halo_volume_status halo_volume_read_nifti_for(const char *path, int side, int labels, halo_volume_file *out, char *err,
                                              size_t err_size);
halo_volume_status halo_volume_read_raw(const char *path, const halo_raw_desc *desc, halo_volume_file *out, char *err,
                                        size_t err_size);
void halo_volume_file_free(halo_volume_file *v);

/* The values at the given percentiles (0..100) of the voxels, through a histogram
 * (exact for 8- and 16-bit integer data); falls back to minimum..maximum when the
 * two coincide, and to [v, v+1] for a constant volume. */
void halo_volume_percentile_window(const halo_volume_file *v, double low_percent, double high_percent,
                                   double window[2]);

/* Maps the values through the window to [0,1] (clamped) and resamples them into a
 * size^3 cube in display orientation, keeping the physical proportions given by the
 * spacing (the longest side fills the cube, the others are centred with zero around
 * them); a separable tent filter, as wide as the scale when shrinking. Returns NULL
 * when memory runs out; free() the result. */
float *halo_volume_to_display(const halo_volume_file *v, const double window[2], int size);

/* A segmentation (label ids) resampled into the same cube as halo_volume_to_display
 * puts the volume it was drawn on: each output voxel takes the label of the source
 * voxel nearest its centre (never a blend of two labels), 0 outside the source.
 * Returns NULL when memory runs out; free() the result. */
float *halo_volume_labels_to_display(const halo_volume_file *v, int size);

/* The cube side that keeps the finest spacing of the file's longest physical side,
 * limited to max_size, and bounded by the input: the cube holds at most
 * HALO_VOLUME_DISPLAY_AMPLIFICATION times the file's voxels (so a tiny file with an
 * extreme aspect ratio or spacing is not blown up into a 512^3 cube). */
#define HALO_VOLUME_DISPLAY_AMPLIFICATION 64
int halo_volume_display_size(const halo_volume_file *v, int max_size);

/* The cap on the memory that resampling into the display cube may take (the cube,
 * the two intermediate passes and the filter taps): HALO_VOLUME_DISPLAY_MAX_BYTES, or
 * HALO_VOLUME_DISPLAY_INPUT_FACTOR times the file's own float copy when that is more
 * (a large scan may take what its size calls for). docs/halo-render.md, "Memory". */
#define HALO_VOLUME_DISPLAY_MAX_BYTES    ((size_t)2 << 30)
#define HALO_VOLUME_DISPLAY_INPUT_FACTOR 4

/* Bytes that halo_volume_to_display(v, window, size) allocates (a double: it may be
 * far beyond size_t's range for absurd shapes), and the cap above for this file. */
double halo_volume_display_bytes(const halo_volume_file *v, int size);
double halo_volume_display_cap(const halo_volume_file *v);

/* Checks, before anything is allocated, that resampling v into a size^3 cube stays
 * within the cap: HALO_VOLUME_INVALID with "would need N GiB; the cap is M GiB"
 * otherwise. halo_volume_to_display and halo_volume_labels_to_display return NULL
 * without allocating for such a size. */
halo_volume_status halo_volume_display_check(const halo_volume_file *v, int size, char *err, size_t err_size);

#endif
