/* Volumes from NIfTI and raw files, windowed and resampled for the example hosts
 * (see volume_io.h). */
#define _POSIX_C_SOURCE 200809L
#include "volume_io.h"

#include <nifti2_io.h>
#include <zlib.h>

#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const struct {
    const char *name;
    int bytes;
} voxel_types[HALO_VOXEL_TYPE_COUNT] = {
    [HALO_VOXEL_UINT8] = {"uint8", 1},
    [HALO_VOXEL_UINT16] = {"uint16", 2},
    [HALO_VOXEL_INT16] = {"int16", 2},
    [HALO_VOXEL_FLOAT32] = {"float32", 4},
};

halo_voxel_type halo_voxel_type_from_name(const char *name)
{
    for (int t = 0; t < HALO_VOXEL_TYPE_COUNT; ++t)
        if (name && !strcmp(name, voxel_types[t].name))
            return (halo_voxel_type)t;
    return HALO_VOXEL_TYPE_COUNT;
}

const char *halo_voxel_type_name(halo_voxel_type type)
{
    return type < HALO_VOXEL_TYPE_COUNT ? voxel_types[type].name : "?";
}

static halo_volume_status fail(halo_volume_status status, char *err, size_t err_size, const char *format, ...)
{
    if (err && err_size) {
        va_list args;
        va_start(args, format);
        vsnprintf(err, err_size, format, args);
        va_end(args);
    }
    return status;
}

void halo_volume_file_free(halo_volume_file *v)
{
    if (!v)
        return;
    free(v->data);
    v->data = NULL;
}

static int host_is_big_endian(void)
{
    const uint16_t one = 1;
    unsigned char first;
    memcpy(&first, &one, 1);
    return first == 0;
}

/* Checks dimensions against the limits; returns the voxel count or 0 with err set. */
static size_t checked_voxels(const char *path, const long long dims[3], char *err, size_t err_size)
{
    size_t voxels = 1;
    for (int a = 0; a < 3; ++a) {
        if (dims[a] < 1 || dims[a] > HALO_VOLUME_FILE_MAX_SIDE) {
            fail(HALO_VOLUME_INVALID, err, err_size, "%s: dimension %c is %lld, outside 1..%d", path, "xyz"[a], dims[a],
                 HALO_VOLUME_FILE_MAX_SIDE);
            return 0;
        }
        voxels *= (size_t)dims[a]; /* at most 8192^3 = 2^39: no overflow in 64 bits */
    }
    if (voxels > HALO_VOLUME_FILE_MAX_VOXELS) {
        fail(HALO_VOLUME_INVALID, err, err_size,
             "%s: %lldx%lldx%lld is %zu voxels, more than the %zu this renderer reads", path, dims[0], dims[1], dims[2],
             voxels, HALO_VOLUME_FILE_MAX_VOXELS);
        return 0;
    }
    return voxels;
}

/* Replaces NaN and infinite voxels by the smallest finite value; fails when there is none. */
static halo_volume_status replace_nonfinite(const char *path, halo_volume_file *v, size_t n, char *err, size_t err_size)
{
    float lowest = INFINITY;
    size_t bad = 0;
    for (size_t i = 0; i < n; ++i) {
        if (!isfinite(v->data[i]))
            ++bad;
        else if (v->data[i] < lowest)
            lowest = v->data[i];
    }
    if (bad == n)
        return fail(HALO_VOLUME_INVALID, err, err_size, "%s: no voxel has a finite value", path);
    if (bad)
        for (size_t i = 0; i < n; ++i)
            if (!isfinite(v->data[i]))
                v->data[i] = lowest;
    v->nonfinite = bad;
    return HALO_VOLUME_OK;
}

/* ---- Raw files ------------------------------------------------------------------- */

static float raw_value(const unsigned char *p, halo_voxel_type type, int swap)
{
    unsigned char b[4];
    int size = voxel_types[type].bytes;
    for (int i = 0; i < size; ++i)
        b[i] = p[swap ? size - 1 - i : i];
    switch (type) {
    case HALO_VOXEL_UINT8:
        return b[0];
    case HALO_VOXEL_UINT16: {
        uint16_t x;
        memcpy(&x, b, 2);
        return x;
    }
    case HALO_VOXEL_INT16: {
        int16_t x;
        memcpy(&x, b, 2);
        return x;
    }
    case HALO_VOXEL_FLOAT32: {
        float x;
        memcpy(&x, b, 4);
        return x;
    }
    default:
        return 0.0f;
    }
}

halo_volume_status halo_volume_read_raw(const char *path, const halo_raw_desc *desc, halo_volume_file *out, char *err,
                                        size_t err_size)
{
    memset(out, 0, sizeof *out);
    out->reduced = 1;
    if (!desc || desc->type >= HALO_VOXEL_TYPE_COUNT || desc->offset < 0)
        return fail(HALO_VOLUME_IO, err, err_size, "%s: invalid raw description", path);
    long long dims[3] = {desc->dims[0], desc->dims[1], desc->dims[2]};
    size_t voxels = checked_voxels(path, dims, err, err_size);
    if (!voxels)
        return HALO_VOLUME_INVALID;
    const int bytes = voxel_types[desc->type].bytes;
    const unsigned long long needed = (unsigned long long)desc->offset + (unsigned long long)voxels * (unsigned)bytes;

    FILE *f = fopen(path, "rb");
    if (!f)
        return fail(HALO_VOLUME_IO, err, err_size, "%s: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        fclose(f);
        return fail(HALO_VOLUME_IO, err, err_size, "%s: not a regular file", path);
    }
    unsigned long long have = (unsigned long long)st.st_size;
    if (have < needed) {
        fclose(f);
        return fail(HALO_VOLUME_IO, err, err_size,
                    "%s: truncated: %llu bytes, but %lldx%lldx%lld %s voxels after %lld header bytes need %llu", path,
                    have, dims[0], dims[1], dims[2], voxel_types[desc->type].name, desc->offset, needed);
    }
    if (have > needed) {
        fclose(f);
        return fail(HALO_VOLUME_INVALID, err, err_size,
                    "%s: %llu bytes, more than the %llu that %lldx%lldx%lld %s voxels after %lld header bytes need "
                    "(check --raw-dims, --raw-type and --raw-offset)",
                    path, have, needed, dims[0], dims[1], dims[2], voxel_types[desc->type].name, desc->offset);
    }
    out->data = malloc(voxels * sizeof *out->data);
    if (!out->data) {
        fclose(f);
        return fail(HALO_VOLUME_IO, err, err_size, "%s: out of memory for %zu voxels", path, voxels);
    }
    if (desc->offset > 0 && fseeko(f, (off_t)desc->offset, SEEK_SET) != 0) {
        fclose(f);
        halo_volume_file_free(out);
        return fail(HALO_VOLUME_IO, err, err_size, "%s: cannot seek: %s", path, strerror(errno));
    }
    const int swap = bytes > 1 && desc->big_endian != host_is_big_endian();
    unsigned char chunk[1 << 16];
    size_t done = 0;
    while (done < voxels) {
        size_t want = voxels - done;
        if (want > sizeof chunk / (size_t)bytes)
            want = sizeof chunk / (size_t)bytes;
        if (fread(chunk, (size_t)bytes, want, f) != want) {
            int e = ferror(f) ? errno : 0;
            fclose(f);
            halo_volume_file_free(out);
            return fail(HALO_VOLUME_IO, err, err_size, "%s: read failed after %zu voxels%s%s", path, done,
                        e ? ": " : " (file shrank?)", e ? strerror(e) : "");
        }
        for (size_t i = 0; i < want; ++i)
            out->data[done + i] = raw_value(chunk + i * (size_t)bytes, desc->type, swap);
        done += want;
    }
    fclose(f);

    for (int a = 0; a < 3; ++a) {
        out->dims[a] = (int)dims[a];
        double s = desc->spacing[a];
        out->spacing[a] = isfinite(s) && s > 0.0 ? s : 1.0;
        out->display_axis[a] = a;
        out->display_flip[a] = 0;
    }
    snprintf(out->description, sizeof out->description, "raw %s %s-endian, %dx%dx%d voxels of %gx%gx%g",
             voxel_types[desc->type].name, desc->big_endian ? "big" : "little", out->dims[0], out->dims[1],
             out->dims[2], out->spacing[0], out->spacing[1], out->spacing[2]);
    halo_volume_status status = replace_nonfinite(path, out, voxels, err, err_size);
    if (status != HALO_VOLUME_OK)
        halo_volume_file_free(out);
    return status;
}

/* ---- NIfTI --------------------------------------------------------------------------- */

static int nifti_type_supported(int datatype)
{
    switch (datatype) {
    case DT_UINT8:
    case DT_INT8:
    case DT_INT16:
    case DT_UINT16:
    case DT_INT32:
    case DT_UINT32:
    case DT_INT64:
    case DT_UINT64:
    case DT_FLOAT32:
    case DT_FLOAT64:
        return 1;
    default:
        return 0;
    }
}

static double nifti_value(const unsigned char *p, int datatype)
{
    switch (datatype) {
#define HALO_NIFTI_CASE(dt, type) \
    case dt: {                    \
        type x;                   \
        memcpy(&x, p, sizeof x);  \
        return (double)x;         \
    }
        HALO_NIFTI_CASE(DT_UINT8, uint8_t)
        HALO_NIFTI_CASE(DT_INT8, int8_t)
        HALO_NIFTI_CASE(DT_INT16, int16_t)
        HALO_NIFTI_CASE(DT_UINT16, uint16_t)
        HALO_NIFTI_CASE(DT_INT32, int32_t)
        HALO_NIFTI_CASE(DT_UINT32, uint32_t)
        HALO_NIFTI_CASE(DT_INT64, int64_t)
        HALO_NIFTI_CASE(DT_UINT64, uint64_t)
        HALO_NIFTI_CASE(DT_FLOAT32, float)
        HALO_NIFTI_CASE(DT_FLOAT64, double)
#undef HALO_NIFTI_CASE
    default:
        return 0.0;
    }
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && !strcmp(s + n - m, suffix);
}

/* Turns the NIfTI orientation (from the sform, else the qform) into display axes:
 * display +x towards the patient's left, +y superior, +z anterior. Returns 0 when
 * the file has no usable orientation. */
static int nifti_display_axes(const nifti_image *nim, int axis[3], int flip[3])
{
    nifti_dmat44 m;
    if (nim->sform_code > 0)
        m = nim->sto_xyz;
    else if (nim->qform_code > 0)
        m = nim->qto_xyz;
    else
        return 0;
    int code[3];
    nifti_dmat44_to_orientation(m, &code[0], &code[1], &code[2]);
    int seen[3] = {0, 0, 0};
    for (int a = 0; a < 3; ++a) {
        int d, backwards;
        switch (code[a]) {
        case NIFTI_L2R:
            d = 0;
            backwards = 1;
            break;
        case NIFTI_R2L:
            d = 0;
            backwards = 0;
            break;
        case NIFTI_I2S:
            d = 1;
            backwards = 0;
            break;
        case NIFTI_S2I:
            d = 1;
            backwards = 1;
            break;
        case NIFTI_P2A:
            d = 2;
            backwards = 0;
            break;
        case NIFTI_A2P:
            d = 2;
            backwards = 1;
            break;
        default:
            return 0;
        }
        if (seen[d]++)
            return 0;
        axis[d] = a;
        flip[d] = backwards;
    }
    return 1;
}

/* The header fields libnifti would repair or trust, as the file has them. */
typedef struct nifti_raw_header {
    int version;     /* 1 or 2; 0: not a NIfTI header (left to libnifti to say so) */
    int single_file; /* n+1/n+2: header and data in one file */
    long long dim[8];
    double pixdim[8];
    double vox_offset;
    char magic[4]; /* as in the file: "n+1", "ni1", "n+2", "ni2", anything else */
    int datatype, bitpix;
    double scl_slope, scl_inter;
} nifti_raw_header;

static uint64_t field_bits(const unsigned char *p, int size, int swap)
{
    uint64_t v = 0;
    for (int i = 0; i < size; ++i)
        v |= (uint64_t)p[swap ? size - 1 - i : i] << (8 * i);
    return v; /* the value, assembled from the bytes: the same on any host */
}

static long long field_int(const unsigned char *p, int size, int swap)
{
    uint64_t v = field_bits(p, size, swap);
    if (size < 8 && (v >> (8 * size - 1)) & 1) /* negative: two's complement of size bytes */
        return (long long)v - (1LL << (8 * size));
    int64_t x;
    memcpy(&x, &v, 8);
    return x;
}

static double field_real(const unsigned char *p, int size, int swap)
{
    uint64_t v = field_bits(p, size, swap);
    if (size == 4) {
        float x;
        uint32_t u = (uint32_t)v;
        memcpy(&x, &u, 4);
        return x;
    }
    double x;
    memcpy(&x, &v, 8);
    return x;
}

/* The header file of path: itself, or the .hdr beside an .img. */
static void nifti_header_path(const char *path, char *out, size_t out_size)
{
    snprintf(out, out_size, "%s", path);
    size_t n = strlen(out);
    if (ends_with(out, ".img"))
        memcpy(out + n - 4, ".hdr", 4);
    else if (ends_with(out, ".img.gz"))
        memcpy(out + n - 7, ".hdr", 4);
}

/* Reads the header's fields itself (NIfTI-1: 348 bytes, NIfTI-2: 540, either byte
 * order, through zlib for .gz). A file too short or without a NIfTI size is
 * version 0: libnifti then refuses it as it always did. */
static void nifti_read_raw_header(const char *path, nifti_raw_header *h)
{
    memset(h, 0, sizeof *h);
    char header_path[4096];
    nifti_header_path(path, header_path, sizeof header_path);
    gzFile gz = gzopen(header_path, "rb");
    if (!gz)
        return;
    unsigned char b[540];
    int got = gzread(gz, b, sizeof b);
    gzclose(gz);
    if (got < 348)
        return;
    int swap;
    for (swap = 0; swap < 2; ++swap) {
        long long size = field_int(b, 4, swap);
        if (size == 348 || (size == 540 && got >= 540))
            break;
    }
    if (swap == 2)
        return;
    h->version = field_int(b, 4, swap) == 348 ? 1 : 2;
    if (h->version == 1) {
        for (int i = 0; i < 8; ++i) {
            h->dim[i] = field_int(b + 40 + 2 * i, 2, swap);
            h->pixdim[i] = field_real(b + 76 + 4 * i, 4, swap);
        }
        h->vox_offset = field_real(b + 108, 4, swap);
        h->single_file = !memcmp(b + 344, "n+1", 4);
        memcpy(h->magic, b + 344, 4);
        h->datatype = (int)field_int(b + 70, 2, swap);
        h->bitpix = (int)field_int(b + 72, 2, swap);
        h->scl_slope = field_real(b + 112, 4, swap);
        h->scl_inter = field_real(b + 116, 4, swap);
    } else {
        for (int i = 0; i < 8; ++i) {
            h->dim[i] = field_int(b + 16 + 8 * i, 8, swap);
            h->pixdim[i] = field_real(b + 104 + 8 * i, 8, swap);
        }
        h->vox_offset = (double)field_int(b + 168, 8, swap);
        h->single_file = !memcmp(b + 4, "n+2", 4);
        memcpy(h->magic, b + 4, 4);
        h->datatype = (int)field_int(b + 12, 2, swap);
        h->bitpix = (int)field_int(b + 14, 2, swap);
        h->scl_slope = field_real(b + 176, 8, swap);
        h->scl_inter = field_real(b + 184, 8, swap);
    }
}

/* The checks libnifti does not make, or makes by silently changing the value: the
 * data offset, the dimension count against the dimensions, the voxel spacing. Each
 * message names the header field. */
static halo_volume_status nifti_check_header(const char *path, const nifti_raw_header *h, char *err, size_t err_size)
{
    if (!h->version)
        return HALO_VOLUME_OK;
    const double header_size = h->version == 1 ? 348.0 : 540.0;
    /* the magic says NIfTI (n+1 one file, ni1 a .hdr/.img pair); a pair may also be plain
     * ANALYZE 7.5 (no magic): anything else is not read as NIfTI-1 regardless */
    const char *one = h->version == 1 ? "n+1" : "n+2", *pair = h->version == 1 ? "ni1" : "ni2";
    static const char none[4] = {0, 0, 0, 0};
    int is_pair =
        ends_with(path, ".hdr") || ends_with(path, ".img") || ends_with(path, ".hdr.gz") || ends_with(path, ".img.gz");
    if (memcmp(h->magic, one, 4) && memcmp(h->magic, pair, 4) &&
        !(is_pair && h->version == 1 && !memcmp(h->magic, none, 4))) {
        char shown[17] = "";
        for (int i = 0; i < 4; ++i)
            snprintf(shown + strlen(shown), sizeof shown - strlen(shown),
                     h->magic[i] >= 32 && h->magic[i] < 127 ? "%c" : "\\x%02x", (unsigned char)h->magic[i]);
        return fail(HALO_VOLUME_INVALID, err, err_size,
                    "%s: header field magic is '%s': a NIfTI-%d file has '%s' (one file) or '%s' (.hdr/.img)", path,
                    shown, h->version, one, pair);
    }
    int nbyper = 0, swapsize = 0;
    nifti_datatype_sizes(h->datatype, &nbyper, &swapsize);
    if (nbyper > 0 && h->bitpix != 8 * nbyper)
        return fail(HALO_VOLUME_INVALID, err, err_size,
                    "%s: header field bitpix is %d, but datatype %d (%s) has %d bits per voxel", path, h->bitpix,
                    h->datatype, nifti_datatype_string(h->datatype), 8 * nbyper);
    /* libnifti replaces a non-finite scale silently (slope by 1, intercept by 0) */
    if (!isfinite(h->scl_slope))
        return fail(HALO_VOLUME_INVALID, err, err_size,
                    "%s: header field scl_slope is %g: the voxel scale must be finite (0 for none)", path,
                    h->scl_slope);
    if (!isfinite(h->scl_inter))
        return fail(HALO_VOLUME_INVALID, err, err_size,
                    "%s: header field scl_inter is %g: the voxel offset must be finite", path, h->scl_inter);
    if (!isfinite(h->vox_offset) || h->vox_offset < 0.0 || h->vox_offset != floor(h->vox_offset) ||
        h->vox_offset > 9007199254740992.0)
        return fail(HALO_VOLUME_INVALID, err, err_size,
                    "%s: header field vox_offset is %g: expected a whole number of bytes from 0 to the file's size",
                    path, h->vox_offset);
    if (h->single_file && h->vox_offset < header_size)
        return fail(HALO_VOLUME_INVALID, err, err_size,
                    "%s: header field vox_offset is %.0f, inside the %.0f-byte header of a single-file NIfTI-%d", path,
                    h->vox_offset, header_size, h->version);
    if (h->single_file && !ends_with(path, ".gz")) {
        struct stat st;
        if (stat(path, &st) == 0 && h->vox_offset > (double)st.st_size)
            return fail(HALO_VOLUME_INVALID, err, err_size,
                        "%s: header field vox_offset is %.0f, beyond the end of the %lld-byte file", path,
                        h->vox_offset, (long long)st.st_size);
    }
    if (h->dim[0] < 3 || h->dim[0] > 7)
        return fail(HALO_VOLUME_INVALID, err, err_size,
                    "%s: header field dim[0] is %lld: a volume has 3 to 7 dimensions (a %s is not one)", path,
                    h->dim[0], h->dim[0] >= 1 && h->dim[0] <= 2 ? "1-D or 2-D image" : "file of this kind");
    for (int i = 1; i <= h->dim[0]; ++i)
        if (h->dim[i] < 1)
            return fail(HALO_VOLUME_INVALID, err, err_size,
                        "%s: header field dim[%d] is %lld, but dim[0] = %lld makes it one of the file's "
                        "dimensions: each needs at least 1 voxel",
                        path, i, h->dim[i], h->dim[0]);
    for (int i = 1; i <= 3; ++i)
        if (!isfinite(h->pixdim[i]) || !(h->pixdim[i] > 0.0))
            return fail(HALO_VOLUME_INVALID, err, err_size,
                        "%s: header field pixdim[%d] is %g: the voxel size along %c must be positive and finite", path,
                        i, h->pixdim[i], "xyz"[i - 1]);
    return HALO_VOLUME_OK;
}

/* Reads `total` bytes at the data offset through zlib (which also reads uncompressed
 * files), growing the buffer as data arrives so that a short file never makes a
 * large allocation. */
/* What the voxels become while they are read, a z slice at a time: floats in the file's
 * units (scl_slope and scl_inter applied), in out->data, or, reduced by factor, each
 * block of factor^3 voxels as their mean (labels: the block's first voxel). */
typedef struct nifti_sink {
    const nifti_image *nim;
    int factor, labels, swap, scaled;
    double slope, intercept;
    long long dims[3];    /* the file's */
    long long reduced[3]; /* out->data's: ceil(dims / factor) */
    float *data;
} nifti_sink;

static void sink_slice(nifti_sink *k, unsigned char *slice, long long z)
{
    const long long nx = k->dims[0], ny = k->dims[1], rx = k->reduced[0], ry = k->reduced[1];
    const int bytes = k->nim->nbyper, f = k->factor;
    if (bytes > 1 && k->swap)
        nifti_swap_Nbytes((int64_t)(nx * ny), k->nim->swapsize > 1 ? k->nim->swapsize : bytes, slice);
    if (f > 1 && k->labels && z % f)
        return; /* labels: only each block's first slice */
    float *plane = k->data + (size_t)(z / f) * (size_t)rx * (size_t)ry;
    for (long long y = 0; y < ny; ++y) {
        if (f > 1 && k->labels && y % f)
            continue;
        const unsigned char *row = slice + (size_t)y * (size_t)nx * (size_t)bytes;
        float *out = plane + (size_t)(y / f) * (size_t)rx;
        for (long long x = 0; x < nx; ++x) {
            if (f > 1 && k->labels && x % f)
                continue;
            double v = nifti_value(row + (size_t)x * (size_t)bytes, k->nim->datatype);
            if (k->scaled)
                v = v * k->slope + k->intercept;
            if (f == 1 || k->labels)
                out[x / f] = (float)v; /* beyond float range: infinite, then replaced */
            else
                out[x / f] += (float)v;
        }
    }
}

/* The means of the reduced blocks (the last block along an axis may hold fewer voxels). */
static void sink_finish(nifti_sink *k)
{
    const int f = k->factor;
    if (f == 1 || k->labels)
        return;
    for (long long z = 0, i = 0; z < k->reduced[2]; ++z)
        for (long long y = 0; y < k->reduced[1]; ++y)
            for (long long x = 0; x < k->reduced[0]; ++x, ++i) {
                long long n = 1;
                const long long at[3] = {x, y, z};
                for (int a = 0; a < 3; ++a) {
                    long long first = at[a] * f, last = first + f < k->dims[a] ? first + f : k->dims[a];
                    n *= last - first;
                }
                k->data[i] /= (float)n;
            }
}

/* Reads the voxel data a z slice at a time into the sink: resident memory is one
 * slice beside the sink's floats, never the whole file's bytes. */
static halo_volume_status read_nifti_data(const char *path, nifti_sink *k, char *err, size_t err_size)
{
    const nifti_image *nim = k->nim;
    const size_t slice_bytes = (size_t)k->dims[0] * (size_t)k->dims[1] * (size_t)nim->nbyper;
    const size_t total = slice_bytes * (size_t)k->dims[2];
    const char *data_path = nim->iname ? nim->iname : path;
    if (!ends_with(data_path, ".gz")) {
        struct stat st;
        if (stat(data_path, &st) != 0)
            return fail(HALO_VOLUME_IO, err, err_size, "%s: %s", data_path, strerror(errno));
        unsigned long long needed = (unsigned long long)nim->iname_offset + total;
        if ((unsigned long long)st.st_size < needed)
            return fail(HALO_VOLUME_IO, err, err_size,
                        "%s: truncated: %llu bytes, but the header's %lldx%lldx%lld %s voxels at offset %lld need %llu",
                        data_path, (unsigned long long)st.st_size, (long long)nim->nx, (long long)nim->ny,
                        (long long)nim->nz, nifti_datatype_string(nim->datatype), (long long)nim->iname_offset, needed);
    }
    gzFile gz = gzopen(data_path, "rb");
    if (!gz)
        return fail(HALO_VOLUME_IO, err, err_size, "%s: %s", data_path, errno ? strerror(errno) : "cannot open");
    if (nim->iname_offset > 0 && gzseek(gz, (z_off_t)nim->iname_offset, SEEK_SET) != (z_off_t)nim->iname_offset) {
        gzclose(gz);
        return fail(HALO_VOLUME_IO, err, err_size, "%s: truncated: ends before the voxel data at offset %lld",
                    data_path, (long long)nim->iname_offset);
    }
    unsigned char *slice = malloc(slice_bytes);
    if (!slice) {
        gzclose(gz);
        return fail(HALO_VOLUME_IO, err, err_size, "%s: out of memory for a slice of %zu bytes", data_path,
                    slice_bytes);
    }
    size_t have = 0;
    char why[128] = "end of file"; /* gzerror's text lives in the gzFile: copy it before gzclose */
    for (long long z = 0; z < k->dims[2]; ++z) {
        size_t in_slice = 0;
        while (in_slice < slice_bytes) {
            size_t want = slice_bytes - in_slice;
            if (want > ((size_t)1 << 30))
                want = (size_t)1 << 30;
            int got = gzread(gz, slice + in_slice, (unsigned)want);
            if (got <= 0) {
                int code = Z_OK;
                const char *message = gzerror(gz, &code);
                if ((got < 0 || code != Z_OK) && message && message[0])
                    snprintf(why, sizeof why, "%s", message);
                break;
            }
            in_slice += (size_t)got;
        }
        have += in_slice;
        if (in_slice < slice_bytes)
            break;
        sink_slice(k, slice, z);
    }
    gzclose(gz);
    free(slice);
    if (have < total)
        return fail(HALO_VOLUME_IO, err, err_size, "%s: truncated: %s after %zu of the %zu bytes of voxel data",
                    data_path, why, have, total);
    sink_finish(k);
    return HALO_VOLUME_OK;
}

/* The reduction factor for a cube of the given side (0: none): the largest integer
 * that keeps at least twice the side along the longest axis, when the float copy
 * would pass HALO_VOLUME_FILE_STREAM_BYTES; else 1. */
static int reduction_factor(const long long dims[3], int side)
{
    long long longest = dims[0] > dims[1] ? dims[0] : dims[1];
    longest = longest > dims[2] ? longest : dims[2];
    double bytes = 4.0 * (double)dims[0] * (double)dims[1] * (double)dims[2];
    if (side <= 0 || bytes <= (double)HALO_VOLUME_FILE_STREAM_BYTES)
        return 1;
    long long f = longest / (2LL * side);
    return f > 1 ? (int)f : 1;
}

halo_volume_status halo_volume_read_nifti(const char *path, halo_volume_file *out, char *err, size_t err_size)
{
    return halo_volume_read_nifti_for(path, 0, 0, out, err, err_size);
}

halo_volume_status halo_volume_read_nifti_for(const char *path, int side, int labels, halo_volume_file *out, char *err,
                                              size_t err_size)
{
    memset(out, 0, sizeof *out);
    FILE *probe = fopen(path, "rb");
    if (!probe)
        return fail(HALO_VOLUME_IO, err, err_size, "%s: %s", path, strerror(errno));
    fclose(probe);

    nifti_raw_header header;
    nifti_read_raw_header(path, &header);
    halo_volume_status checked = nifti_check_header(path, &header, err, err_size);
    if (checked != HALO_VOLUME_OK)
        return checked;

    nifti_set_debug_level(0);                     /* its messages are ours to write, once, naming the field */
    nifti_image *nim = nifti_image_read(path, 0); /* the header only */
    if (!nim)
        return fail(HALO_VOLUME_INVALID, err, err_size, "%s: not a NIfTI file, or its header is incomplete or invalid",
                    path);
    if (header.version)
        nim->iname_offset = (int64_t)header.vox_offset; /* the checked value, never a repaired one */
    halo_volume_status status = HALO_VOLUME_OK;
    long long dims[3] = {nim->nx, nim->ny, nim->nz};
    size_t voxels = 0;
    if (nim->ndim < 1 || nim->ndim > 7) {
        status = fail(HALO_VOLUME_INVALID, err, err_size, "%s: %lld dimensions, expected 1 to 7", path,
                      (long long)nim->ndim);
        goto done;
    }
    if (!nifti_type_supported(nim->datatype)) {
        status = fail(HALO_VOLUME_INVALID, err, err_size,
                      "%s: voxel type %s is not supported (integers of 8 to 64 bits, float32, float64)", path,
                      nifti_datatype_string(nim->datatype));
        goto done;
    }
    voxels = checked_voxels(path, dims, err, err_size);
    if (!voxels) {
        status = HALO_VOLUME_INVALID;
        goto done;
    }
    for (int d = 4; d <= 7 && d <= nim->ndim; ++d)
        if (nim->dim[d] < 1) {
            status =
                fail(HALO_VOLUME_INVALID, err, err_size, "%s: dimension %d is %lld", path, d, (long long)nim->dim[d]);
            goto done;
        }
    nifti_sink sink = {nim,
                       reduction_factor(dims, side),
                       labels,
                       0,
                       0,
                       nim->scl_slope,
                       nim->scl_inter,
                       {dims[0], dims[1], dims[2]},
                       {0, 0, 0},
                       NULL};
    sink.swap = nim->byteorder != nifti_short_order();
    sink.scaled = isfinite(sink.slope) && sink.slope != 0.0 && isfinite(sink.intercept) &&
                  (sink.slope != 1.0 || sink.intercept != 0.0);
    size_t kept = 1;
    for (int a = 0; a < 3; ++a) {
        sink.reduced[a] = (dims[a] + sink.factor - 1) / sink.factor;
        kept *= (size_t)sink.reduced[a];
    }
    out->data = sink.data = calloc(kept, sizeof *out->data);
    if (!out->data) {
        status = fail(HALO_VOLUME_IO, err, err_size, "%s: out of memory for %zu voxels", path, kept);
        goto done;
    }
    status = read_nifti_data(path, &sink, err, err_size);
    if (status != HALO_VOLUME_OK)
        goto done;

    double spacing[3] = {nim->dx, nim->dy, nim->dz};
    for (int a = 0; a < 3; ++a) {
        out->dims[a] = (int)sink.reduced[a];
        out->spacing[a] = (isfinite(spacing[a]) && fabs(spacing[a]) > 1e-9 ? fabs(spacing[a]) : 1.0) * sink.factor;
        out->display_axis[a] = a;
        out->display_flip[a] = 0;
    }
    out->reduced = sink.factor;
    int oriented = nifti_display_axes(nim, out->display_axis, out->display_flip);
    long long extra = 1;
    for (int d = 4; d <= 7 && d <= nim->ndim; ++d)
        extra = extra > INT_MAX / nim->dim[d] ? INT_MAX : extra * nim->dim[d];
    out->discarded_volumes = extra - 1 > INT_MAX ? INT_MAX : (int)(extra - 1);
    const char *units = nim->xyz_units ? nifti_units_string(nim->xyz_units) : "";
    char reduced[96] = "";
    if (sink.factor > 1)
        snprintf(reduced, sizeof reduced, ", read reduced by %d to %dx%dx%d (%s)", sink.factor, out->dims[0],
                 out->dims[1], out->dims[2], labels ? "each block's first voxel" : "block means");
    snprintf(out->description, sizeof out->description, "NIfTI-%d, %s, %lldx%lldx%lld voxels of %gx%gx%g%s%s%s%s",
             nim->nifti_type >= NIFTI_FTYPE_NIFTI2_1 ? 2 : 1, nifti_datatype_string(nim->datatype), dims[0], dims[1],
             dims[2], out->spacing[0] / sink.factor, out->spacing[1] / sink.factor, out->spacing[2] / sink.factor,
             units[0] ? " " : "", units, oriented ? "" : ", no orientation (axes kept)", reduced);
    status = replace_nonfinite(path, out, kept, err, err_size);

done:
    if (status != HALO_VOLUME_OK)
        halo_volume_file_free(out);
    nifti_image_free(nim);
    return status;
}

/* ---- Window ------------------------------------------------------------------------ */

void halo_volume_percentile_window(const halo_volume_file *v, double low_percent, double high_percent, double window[2])
{
    size_t n = (size_t)v->dims[0] * (size_t)v->dims[1] * (size_t)v->dims[2];
    double lo = INFINITY, hi = -INFINITY;
    int integral = 1;
    for (size_t i = 0; i < n; ++i) {
        double x = v->data[i];
        if (x < lo)
            lo = x;
        if (x > hi)
            hi = x;
        if (integral && x != floor(x))
            integral = 0;
    }
    if (!(hi > lo)) {
        window[0] = lo;
        window[1] = lo + 1.0;
        return;
    }
    /* Integer data spanning at most 65536 values get one bin per value (exact). */
    enum { FLOAT_BINS = 65536 };
    const int exact = integral && hi - lo < FLOAT_BINS;
    const size_t bins = exact ? (size_t)(hi - lo) + 1 : FLOAT_BINS;
    const double bin_width = exact ? 1.0 : (hi - lo) / FLOAT_BINS;
    size_t *histogram = calloc(bins, sizeof *histogram);
    if (!histogram) {
        window[0] = lo;
        window[1] = hi;
        return;
    }
    for (size_t i = 0; i < n; ++i) {
        size_t b = (size_t)((v->data[i] - lo) / bin_width);
        histogram[b < bins ? b : bins - 1]++;
    }
    double percent[2] = {low_percent, high_percent};
    for (int k = 0; k < 2; ++k) {
        double rank = percent[k] / 100.0 * (double)(n - 1);
        size_t count = 0, b = 0;
        for (; b < bins; ++b) {
            count += histogram[b];
            if ((double)count > rank)
                break;
        }
        if (b == bins)
            b = bins - 1;
        window[k] = exact ? lo + (double)b : lo + ((double)b + 0.5) * bin_width;
    }
    free(histogram);
    if (!(window[1] > window[0])) {
        window[0] = lo;
        window[1] = hi;
    }
}

/* ---- Resampling into the display cube ------------------------------------------------ */

/* The source positions and weights of each output position along one axis. */
typedef struct taps {
    int count_max;
    int *first, *count;
    float *weight; /* count_max per output */
} taps;

static void taps_free(taps *t)
{
    free(t->first);
    free(t->count);
    free(t->weight);
}

/* Output voxel u (of size, each `out_size` long) sits at physical (u + 0.5) * out_size
 * - margin from the source axis's start; source voxel i at (i + 0.5) * spacing. A tent
 * of radius max(1, out_size / spacing) source voxels; positions outside the source
 * count as 0, so the volume's edges fade over one output voxel. */
static int taps_make(taps *t, int size, double out_size, double margin, int n, double spacing)
{
    double radius = out_size / spacing;
    if (radius < 1.0)
        radius = 1.0;
    /* a tent wider than the axis covers all of it: no wider (absurd spacings, e.g. a
     * NIfTI header with pixdim 1e-30 beside 1, would overflow the tap count) */
    if (!(radius <= n + 1.0))
        radius = n + 1.0;
    t->count_max = 2 * (int)ceil(radius) + 2;
    t->first = malloc((size_t)size * sizeof *t->first);
    t->count = malloc((size_t)size * sizeof *t->count);
    t->weight = malloc((size_t)size * (size_t)t->count_max * sizeof *t->weight);
    if (!t->first || !t->count || !t->weight)
        return 0;
    for (int u = 0; u < size; ++u) {
        double x = ((u + 0.5) * out_size - margin) / spacing - 0.5;
        /* far outside the axis (extreme anisotropy): no tap; keeps the ints in range */
        if (!(x > -2.0 * radius - 2.0 && x < n + 2.0 * radius + 2.0))
            x = x > 0.0 ? n + 2.0 * radius + 2.0 : -2.0 * radius - 2.0;
        int i0 = (int)ceil(x - radius), i1 = (int)floor(x + radius);
        double total = 0.0;
        for (int i = i0; i <= i1; ++i)
            total += 1.0 - fabs(i - x) / radius;
        int first = i0 < 0 ? 0 : i0, last = i1 > n - 1 ? n - 1 : i1;
        if (last - first + 1 > t->count_max)
            last = first + t->count_max - 1;
        t->first[u] = first;
        t->count[u] = last >= first ? last - first + 1 : 0;
        for (int i = first; i <= last; ++i) {
            double w = 1.0 - fabs(i - x) / radius;
            t->weight[(size_t)u * (size_t)t->count_max + (size_t)(i - first)] =
                (float)(total > 0.0 && w > 0.0 ? w / total : 0.0);
        }
    }
    return 1;
}

int halo_volume_display_size(const halo_volume_file *v, int max_size)
{
    double extent = 0.0, finest = INFINITY;
    for (int a = 0; a < 3; ++a) {
        double e = v->dims[a] * v->spacing[a];
        if (e > extent)
            extent = e;
        if (v->spacing[a] < finest)
            finest = v->spacing[a];
    }
    double size = ceil(extent / finest - 1e-6);
    if (size > max_size)
        size = max_size;
    /* bounded by the input: size^3 <= amplification * voxels */
    double voxels = (double)v->dims[0] * v->dims[1] * v->dims[2];
    double bound = floor(cbrt(HALO_VOLUME_DISPLAY_AMPLIFICATION * voxels) + 1e-9);
    if (size > bound)
        size = bound;
    if (!(size >= 8))
        size = 8;
    return (int)size;
}

/* The file's axes in display order: sizes, spacings, physical extents, strides through
 * the data (negative where the axis runs backwards) and the offset of display voxel 0. */
typedef struct display_axes {
    int n[3];
    double spacing[3], extent[3], longest;
    ptrdiff_t stride[3], base;
} display_axes;

static void display_axes_of(const halo_volume_file *v, display_axes *g)
{
    const ptrdiff_t file_stride[3] = {1, v->dims[0], (ptrdiff_t)v->dims[0] * v->dims[1]};
    g->longest = 0.0;
    g->base = 0;
    for (int d = 0; d < 3; ++d) {
        int a = v->display_axis[d];
        g->n[d] = v->dims[a];
        g->spacing[d] = v->spacing[a];
        g->extent[d] = g->n[d] * g->spacing[d];
        if (g->extent[d] > g->longest)
            g->longest = g->extent[d];
        g->stride[d] = v->display_flip[d] ? -file_stride[a] : file_stride[a];
        if (v->display_flip[d])
            g->base += (ptrdiff_t)(g->n[d] - 1) * file_stride[a];
    }
}

double halo_volume_display_bytes(const halo_volume_file *v, int size)
{
    display_axes g;
    display_axes_of(v, &g);
    const double s = size, f = sizeof(float);
    /* pass 1 (s x n1 x n2), pass 2 (s x s x n2), the cube, and per axis the taps of
     * taps_make: two ints and at most 2 * (n + 2) + 2 weights per output position */
    double bytes = f * (s * g.n[1] * g.n[2] + s * s * g.n[2] + s * s * s);
    for (int d = 0; d < 3; ++d)
        bytes += s * (2.0 * sizeof(int) + f * (2.0 * (g.n[d] + 2.0) + 2.0));
    return bytes;
}

double halo_volume_display_cap(const halo_volume_file *v)
{
    double input = (double)sizeof(float) * v->dims[0] * v->dims[1] * v->dims[2];
    double cap = (double)HALO_VOLUME_DISPLAY_MAX_BYTES;
    return HALO_VOLUME_DISPLAY_INPUT_FACTOR * input > cap ? HALO_VOLUME_DISPLAY_INPUT_FACTOR * input : cap;
}

halo_volume_status halo_volume_display_check(const halo_volume_file *v, int size, char *err, size_t err_size)
{
    double need = halo_volume_display_bytes(v, size), cap = halo_volume_display_cap(v);
    if (need <= cap)
        return HALO_VOLUME_OK;
    return fail(HALO_VOLUME_INVALID, err, err_size,
                "resampling the %dx%dx%d volume into a %d^3 cube would need %.1f GiB; the cap is %.1f GiB "
                "(2 GiB, or 4 times the volume's own float copy): choose a smaller --volume-size",
                v->dims[0], v->dims[1], v->dims[2], size, need / (1 << 30), cap / (1 << 30));
}

float *halo_volume_labels_to_display(const halo_volume_file *v, int size)
{
    if (halo_volume_display_check(v, size, NULL, 0) != HALO_VOLUME_OK)
        return NULL;
    display_axes g;
    display_axes_of(v, &g);
    const double out_size = g.longest / size;
    const size_t s = (size_t)size;
    /* the source voxel nearest each output voxel's centre along each axis, -1 outside */
    int *nearest = malloc(3 * s * sizeof *nearest);
    float *out = malloc(s * s * s * sizeof *out);
    if (!nearest || !out) {
        free(nearest);
        free(out);
        return NULL;
    }
    for (int d = 0; d < 3; ++d)
        for (int u = 0; u < size; ++u) {
            double x = floor(((u + 0.5) * out_size - 0.5 * (g.longest - g.extent[d])) / g.spacing[d]);
            nearest[(size_t)d * s + (size_t)u] = x >= 0.0 && x < g.n[d] ? (int)x : -1;
        }
    for (size_t z = 0; z < s; ++z)
        for (size_t y = 0; y < s; ++y)
            for (size_t x = 0; x < s; ++x) {
                int i = nearest[x], j = nearest[s + y], k = nearest[2 * s + z];
                out[(z * s + y) * s + x] = i < 0 || j < 0 || k < 0
                                               ? 0.0f
                                               : v->data[g.base + i * g.stride[0] + j * g.stride[1] + k * g.stride[2]];
            }
    free(nearest);
    return out;
}

float *halo_volume_to_display(const halo_volume_file *v, const double window[2], int size)
{
    if (halo_volume_display_check(v, size, NULL, 0) != HALO_VOLUME_OK)
        return NULL; /* refused before allocating: the caller checked and said why */
    display_axes g;
    display_axes_of(v, &g);
    const int *n = g.n;
    const double *spacing = g.spacing, *extent = g.extent, longest = g.longest;
    const ptrdiff_t *stride = g.stride, base = g.base;
    const double out_size = longest / size;
    const double lo = window[0], scale = 1.0 / (window[1] - window[0]);
    const size_t s = (size_t)size;

    taps t[3] = {{0}};
    float *pass1 = NULL, *pass2 = NULL, *out = NULL;
    int ok = 1;
    for (int d = 0; d < 3; ++d)
        ok &= taps_make(&t[d], size, out_size, 0.5 * (longest - extent[d]), n[d], spacing[d]);
    if (ok) {
        pass1 = calloc(s * (size_t)n[1] * (size_t)n[2], sizeof *pass1);
        pass2 = calloc(s * s * (size_t)n[2], sizeof *pass2);
        out = calloc(s * s * s, sizeof *out);
    }
    if (!ok || !pass1 || !pass2 || !out) {
        free(out);
        out = NULL;
        goto done;
    }
    /* Along display x, windowing each source value on the way. */
    for (int z = 0; z < n[2]; ++z)
        for (int y = 0; y < n[1]; ++y) {
            const float *row = v->data + (base + (ptrdiff_t)y * stride[1] + (ptrdiff_t)z * stride[2]);
            float *dst = pass1 + ((size_t)z * (size_t)n[1] + (size_t)y) * s;
            for (int u = 0; u < size; ++u) {
                const float *w = t[0].weight + (size_t)u * (size_t)t[0].count_max;
                double sum = 0.0;
                for (int k = 0; k < t[0].count[u]; ++k) {
                    double x = (row[(ptrdiff_t)(t[0].first[u] + k) * stride[0]] - lo) * scale;
                    sum += w[k] * (x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x);
                }
                dst[u] = (float)sum;
            }
        }
    /* Along y. */
    for (int z = 0; z < n[2]; ++z)
        for (int u = 0; u < size; ++u) {
            float *dst = pass2 + ((size_t)z * s + (size_t)u) * s;
            const float *w = t[1].weight + (size_t)u * (size_t)t[1].count_max;
            for (int k = 0; k < t[1].count[u]; ++k) {
                const float *src = pass1 + ((size_t)z * (size_t)n[1] + (size_t)(t[1].first[u] + k)) * s;
                for (size_t x = 0; x < s; ++x)
                    dst[x] += w[k] * src[x];
            }
        }
    /* Along z. */
    for (int u = 0; u < size; ++u) {
        float *dst = out + (size_t)u * s * s;
        const float *w = t[2].weight + (size_t)u * (size_t)t[2].count_max;
        for (int k = 0; k < t[2].count[u]; ++k) {
            const float *src = pass2 + (size_t)(t[2].first[u] + k) * s * s;
            for (size_t i = 0; i < s * s; ++i)
                dst[i] += w[k] * src[i];
        }
    }
    for (size_t i = 0; i < s * s * s; ++i)
        out[i] = out[i] < 0.0f ? 0.0f : out[i] > 1.0f ? 1.0f : out[i];
done:
    free(pass1);
    free(pass2);
    for (int d = 0; d < 3; ++d)
        taps_free(&t[d]);
    return out;
}
