#define _DEFAULT_SOURCE /* mkstemps */
/* Fuzz target: the volume loaders of the examples (examples/volume_io.c) on arbitrary
 * files. The input is written to a temporary file and read
 *   - as NIfTI (.nii; .nii.gz when it starts with the gzip magic 1f 8b), and
 *   - as raw, with the dimensions, voxel type and byte order taken from its first 5
 *     bytes (each side 1..16) and the rest of the input as the file.
 * A volume that loads is windowed (percentiles) and resampled to an 8^3 cube, and its
 * values as labels too. Nothing may crash, leak or allocate what the file cannot hold. */
#include "fuzz.h"
#include "volume_io.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int write_file(char *path, int suffix, const uint8_t *data, size_t size)
{
    int fd = mkstemps(path, suffix);
    if (fd < 0)
        return 0;
    size_t done = 0;
    while (done < size) {
        ssize_t n = write(fd, data + done, size - done);
        if (n <= 0)
            break;
        done += (size_t)n;
    }
    close(fd);
    return done == size;
}

static void use(halo_volume_file *v)
{
    double window[2];
    halo_volume_percentile_window(v, 1.0, 99.0, window);
    free(halo_volume_to_display(v, window, 8));
    free(halo_volume_labels_to_display(v, 8));
    halo_volume_file_free(v);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *dir = getenv("TMPDIR") && *getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    char err[512];
    halo_volume_file v;
    int gz = size >= 2 && data[0] == 0x1f && data[1] == 0x8b;
    char path[4096];
    snprintf(path, sizeof path, "%s/halo-fuzz-XXXXXX%s", dir, gz ? ".nii.gz" : ".nii");
    if (write_file(path, gz ? 7 : 4, data, size)) {
        if (halo_volume_read_nifti(path, &v, err, sizeof err) == HALO_VOLUME_OK)
            use(&v);
        unlink(path);
    }
    if (size >= 5) {
        halo_raw_desc raw = {.dims = {1 + (data[0] & 15), 1 + (data[1] & 15), 1 + (data[2] & 15)},
                             .type = (halo_voxel_type)(data[3] % HALO_VOXEL_TYPE_COUNT),
                             .big_endian = data[4] & 1,
                             .spacing = {1.0, 1.0 + (data[4] >> 4), 0.5},
                             .offset = (data[4] >> 1) & 7};
        snprintf(path, sizeof path, "%s/halo-fuzz-XXXXXX.raw", dir);
        if (write_file(path, 4, data + 5, size - 5)) {
            if (halo_volume_read_raw(path, &raw, &v, err, sizeof err) == HALO_VOLUME_OK)
                use(&v);
            unlink(path);
        }
    }
    return 0;
}
