/* The bench's memory column (bench_memory.h). */
#include "bench_memory.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

/* halo-render beside this program (installed), or in the build tree's tools/. */
static int find_halo_render(char *path, size_t size)
{
    char self[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n <= 0)
        return 0;
    self[n] = 0;
    char *slash = strrchr(self, '/');
    if (!slash)
        return 0;
    *slash = 0;
    static const char *const places[] = {"%s/halo-render", "%s/../tools/halo-render"};
    for (size_t k = 0; k < sizeof places / sizeof places[0]; ++k) {
        snprintf(path, size, places[k], self);
        if (access(path, X_OK) == 0)
            return 1;
    }
    return 0;
}

/* The child's peak resident set in KiB, or -1 when it failed. Only exec-safe calls
 * between fork and exec: the parent holds a GL context with driver threads. */
static long peak_kib(char *const argv[])
{
    pid_t pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        int null = open("/dev/null", O_WRONLY);
        if (null >= 0) {
            dup2(null, STDOUT_FILENO);
            dup2(null, STDERR_FILENO);
        }
        execv(argv[0], argv);
        _exit(127);
    }
    int status = 0;
    struct rusage usage;
    while (wait4(pid, &status, 0, &usage) < 0)
        if (errno != EINTR)
            return -1;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? usage.ru_maxrss : -1;
}

static double per_voxel(const char *render, const char *scene, const char *gradient, int size, const char *output)
{
    long peak[2];
    const int sides[2] = {32, size};
    for (int k = 0; k < 2; ++k) {
        char side[16];
        snprintf(side, sizeof side, "%d", sides[k]);
        char *argv[16];
        int n = 0;
        argv[n++] = (char *)render;
        argv[n++] = "--host";
        argv[n++] = "slice";
        argv[n++] = "--size";
        argv[n++] = "64x64";
        argv[n++] = "--quiet";
        argv[n++] = "--volume-size";
        argv[n++] = side;
        argv[n++] = "--scene";
        argv[n++] = (char *)scene;
        if (gradient) {
            argv[n++] = "--gradient-format";
            argv[n++] = (char *)gradient;
        }
        argv[n++] = "-o";
        argv[n++] = (char *)output;
        argv[n] = NULL;
        peak[k] = peak_kib(argv);
        if (peak[k] < 0)
            return NAN;
    }
    double voxels = (double)size * size * size - 32.0 * 32.0 * 32.0;
    return (double)(peak[1] - peak[0]) * 1024.0 / voxels;
}

static int write_text(const char *path, const char *text)
{
    FILE *out = fopen(path, "w");
    if (!out)
        return 0;
    int ok = fputs(text, out) >= 0;
    return fclose(out) == 0 && ok;
}

int halo_bench_memory_measure(const char *scene_path, const char *scene_text, int size, halo_bench_memory *out,
                              FILE *progress)
{
    for (int h = 0; h < 2; ++h)
        for (int g = 0; g < HALO_GRADIENT_FORMAT_COUNT; ++g)
            out->bytes_per_voxel[h][g] = NAN;
    out->size = 0;
    char render[PATH_MAX + 64];
    if (!find_halo_render(render, sizeof render)) {
        fprintf(stderr, "halo-validate: bench: no halo-render beside this program: no memory column\n");
        return 0;
    }
    char folder[] = "/tmp/halo-bench-memory-XXXXXX";
    if (!mkdtemp(folder)) {
        fprintf(stderr, "halo-validate: bench: no temporary folder (%s): no memory column\n", strerror(errno));
        return 0;
    }
    char plain[sizeof folder + 32], scene[sizeof folder + 32], image[sizeof folder + 32];
    snprintf(plain, sizeof plain, "%s/plain.json", folder);
    snprintf(scene, sizeof scene, "%s/scene.json", folder);
    snprintf(image, sizeof image, "%s/image.png", folder);
    int ok = write_text(plain, "{\"halo_scene\": 1, \"stages\": []}\n") &&
             (scene_path || write_text(scene, scene_text ? scene_text : ""));
    if (ok) {
        if (progress)
            fprintf(progress, "bench: memory: %s at %d^3 and 32^3...\n", render, size);
        out->size = size;
        out->bytes_per_voxel[0][0] = per_voxel(render, plain, NULL, size, image);
        for (int g = HALO_GRADIENT_FLOAT; g < HALO_GRADIENT_FORMAT_COUNT; ++g)
            out->bytes_per_voxel[1][g] = per_voxel(render, scene_path ? scene_path : scene,
                                                   halo_gradient_format_name((halo_gradient_format)g), size, image);
    }
    unlink(image);
    unlink(plain);
    unlink(scene);
    rmdir(folder);
    return ok;
}

void halo_bench_memory_cell(const halo_bench_memory *m, int halos, int gradient, char *out, size_t size)
{
    int g = halos
                ? (halo_gradient_format_name((halo_gradient_format)gradient) ? gradient : HALO_GRADIENT_FORMAT_DEFAULT)
                : 0;
    double v = m && m->size ? m->bytes_per_voxel[halos ? 1 : 0][g] : NAN;
    if (isnan(v))
        snprintf(out, size, "-");
    else
        snprintf(out, size, "%.1f", v);
}
