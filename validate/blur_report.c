/* halo-validate blur: the Gaussian blur of the outline passes (docs/blur.md) measured
 * against direct 2D convolution, beside the anchors of Svakhine, Ebert & Andrews 2009
 * (Sec. 5: 5x5 kernel 33 fps GPU / 2.7 fps CPU, 33x33 kernel 9.5 / 0.07 fps).
 *
 * Kernel K x K (K = 2r + 1): sigma = r / 3, so the truncation is at exactly 3 sigma;
 * weights normalized over the taps inside the image (a constant image stays constant up
 * to the border; the 2D window's sum is the product of the axes' sums, so direct and
 * separable agree exactly in exact arithmetic). Variants, on a 512 x 512 RGBA32F image:
 *   gpu direct     one pass, K^2 texelFetch taps
 *   gpu separable  two passes (x then y), K taps each
 *   gpu linear     two passes, tap pairs merged into one bilinear fetch between the two
 *                  texels at offset i + w(i+1) / (w(i) + w(i+1)): (K + 1) / 2 fetches;
 *                  at the border a pair with one texel outside fetches that texel alone
 *   cpu direct     K^2 taps per pixel, one thread, float accumulation
 *   cpu separable  two passes, one thread
 * Errors: largest absolute difference from the double-precision direct 2D convolution.
 * Times: median wall time of one frame (GPU: draws until glFinish, without the read-back;
 * CPU: one thread), after one untimed warm-up run. */
#include "blur_report.h"

#include "halo_gl_loader.h"
#include "gl/headless.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_RADIUS 64

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void gauss_weights_sigma(int r, double sigma, double *w)
{
    for (int i = 0; i <= r; ++i)
        w[i] = exp(-0.5 * (i / sigma) * (i / sigma));
}

static void gauss_weights(int r, double *w) { gauss_weights_sigma(r, r / 3.0, w); }

/* The Gaussian of sigma truncated at radius r, separable in double (exact to rounding),
 * renormalized over the inside taps: the reference of the truncation table. */
static void reference_separable(int n, int r, double sigma, const float *in, double *scratch, double *out)
{
    double w[MAX_RADIUS + 1];
    gauss_weights_sigma(r, sigma, w);
    for (int pass = 0; pass < 2; ++pass)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                double sum[4] = {0, 0, 0, 0}, total = 0.0;
                for (int i = -r; i <= r; ++i) {
                    int px = pass ? x : x + i, py = pass ? y + i : y;
                    if (px < 0 || py < 0 || px >= n || py >= n)
                        continue;
                    size_t at = ((size_t)py * n + px) * 4;
                    for (int c = 0; c < 4; ++c)
                        sum[c] += w[abs(i)] * (pass ? scratch[at + c] : (double)in[at + c]);
                    total += w[abs(i)];
                }
                for (int c = 0; c < 4; ++c)
                    (pass ? out : scratch)[((size_t)y * n + x) * 4 + c] = sum[c] / total;
            }
}

/* Test image: noise over steps and a smooth ramp, values in [0, 1]. */
static void make_image(int n, float *rgba)
{
    unsigned long long z = 0x626c75722d726570ull;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            for (int c = 0; c < 4; ++c) {
                z = z * 6364136223846793005ull + 1442695040888963407ull;
                double noise = (double)(z >> 40) / (double)(1ull << 24);
                double step = ((x / 37 + y / 53 + c) % 2) ? 0.8 : 0.2;
                rgba[((size_t)y * n + x) * 4 + c] = (float)(0.5 * step + 0.3 * noise + 0.2 * x / n);
            }
}

/* The direct 2D blur of in (n x n RGBA), renormalized over the inside taps, with the
 * one-sided weights w[0..r], summed in the precision REAL: double for the reference,
 * float for the CPU's direct row. One body for both, so that they differ in precision
 * only. */
#define DEFINE_DIRECT_BLUR(NAME, REAL)                                        \
    static void NAME(int n, int r, const REAL *w, const float *in, REAL *out) \
    {                                                                         \
        for (int y = 0; y < n; ++y)                                           \
            for (int x = 0; x < n; ++x) {                                     \
                REAL sum[4] = {0, 0, 0, 0}, total = 0;                        \
                for (int j = -r; j <= r; ++j) {                               \
                    int py = y + j;                                           \
                    if (py < 0 || py >= n)                                    \
                        continue;                                             \
                    for (int i = -r; i <= r; ++i) {                           \
                        int px = x + i;                                       \
                        if (px < 0 || px >= n)                                \
                            continue;                                         \
                        REAL wt = w[abs(i)] * w[abs(j)];                      \
                        const float *v = &in[((size_t)py * n + px) * 4];      \
                        for (int c = 0; c < 4; ++c)                           \
                            sum[c] += wt * v[c];                              \
                        total += wt;                                          \
                    }                                                         \
                }                                                             \
                for (int c = 0; c < 4; ++c)                                   \
                    out[((size_t)y * n + x) * 4 + c] = sum[c] / total;        \
            }                                                                 \
    }
DEFINE_DIRECT_BLUR(direct_blur_double, double)
DEFINE_DIRECT_BLUR(direct_blur_float, float)

/* Reference: direct 2D in double. */
static void reference(int n, int r, const float *in, double *out)
{
    double w[MAX_RADIUS + 1];
    gauss_weights(r, w);
    direct_blur_double(n, r, w, in, out);
}

static void cpu_direct(int n, int r, const float *in, float *out)
{
    double wd[MAX_RADIUS + 1];
    float w[MAX_RADIUS + 1];
    gauss_weights(r, wd);
    for (int i = 0; i <= r; ++i)
        w[i] = (float)wd[i];
    direct_blur_float(n, r, w, in, out);
}

static void cpu_axis(int n, int r, const float *w, const float *in, float *out, int dx, int dy)
{
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            float sum[4] = {0, 0, 0, 0}, total = 0.0f;
            for (int i = -r; i <= r; ++i) {
                int px = x + i * dx, py = y + i * dy;
                if (px < 0 || py < 0 || px >= n || py >= n)
                    continue;
                const float *v = &in[((size_t)py * n + px) * 4];
                for (int c = 0; c < 4; ++c)
                    sum[c] += w[abs(i)] * v[c];
                total += w[abs(i)];
            }
            for (int c = 0; c < 4; ++c)
                out[((size_t)y * n + x) * 4 + c] = sum[c] / total;
        }
}

static void cpu_separable(int n, int r, const float *in, float *scratch, float *out)
{
    double wd[MAX_RADIUS + 1];
    float w[MAX_RADIUS + 1];
    gauss_weights(r, wd);
    for (int i = 0; i <= r; ++i)
        w[i] = (float)wd[i];
    cpu_axis(n, r, w, in, scratch, 1, 0);
    cpu_axis(n, r, w, scratch, out, 0, 1);
}

/* ---- GPU ---- */

static const char vertex_source[] =
    "#version 330 core\n"
    "void main() {\n"
    "    vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);\n"
    "    gl_Position = vec4(p, 0.0, 1.0);\n"
    "}\n";

/* The blur shaders' interface: the image, the one-sided weights[0..radius] and the
 * axis of a separable pass. */
#define BLUR_SHADER_INTERFACE      \
    "#version 330 core\n"          \
    "uniform sampler2D image;\n"   \
    "uniform int radius;\n"        \
    "uniform float weights[65];\n" \
    "uniform ivec2 axis;\n"        \
    "out vec4 color;\n"

/* Direct 2D and one separable axis (axis = (0, 0): direct). */
static const char taps_source[] = BLUR_SHADER_INTERFACE
    "void main() {\n"
    "    ivec2 size = textureSize(image, 0), p = ivec2(gl_FragCoord.xy);\n"
    "    vec4 sum = vec4(0.0);\n"
    "    float total = 0.0;\n"
    "    if (axis == ivec2(0)) {\n"
    "        for (int j = -radius; j <= radius; ++j) {\n"
    "            if (p.y + j < 0 || p.y + j >= size.y) continue;\n"
    "            for (int i = -radius; i <= radius; ++i) {\n"
    "                if (p.x + i < 0 || p.x + i >= size.x) continue;\n"
    "                float w = weights[abs(i)] * weights[abs(j)];\n"
    "                sum += w * texelFetch(image, p + ivec2(i, j), 0);\n"
    "                total += w;\n"
    "            }\n"
    "        }\n"
    "    } else {\n"
    "        for (int i = -radius; i <= radius; ++i) {\n"
    "            ivec2 q = p + i * axis;\n"
    "            if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;\n"
    "            sum += weights[abs(i)] * texelFetch(image, q, 0);\n"
    "            total += weights[abs(i)];\n"
    "        }\n"
    "    }\n"
    "    color = sum / total;\n"
    "}\n";

/* Linear sampling: the centre tap, then pairs (a, a+1) on each side with a = 1, 3, ...
 * merged into one bilinear fetch; a pair with its outer texel outside (or a lone last
 * tap) fetches the inner texel alone. */
static const char linear_source[] = BLUR_SHADER_INTERFACE
    "bool inside(int q, int n) { return q >= 0 && q < n; }\n"
    "void main() {\n"
    "    ivec2 size = textureSize(image, 0), p = ivec2(gl_FragCoord.xy);\n"
    "    int n = axis.x != 0 ? size.x : size.y, c = axis.x != 0 ? p.x : p.y;\n"
    "    vec2 texel = 1.0 / vec2(size), centre = (vec2(p) + 0.5) * texel;\n"
    "    vec4 sum = weights[0] * texelFetch(image, p, 0);\n"
    "    float total = weights[0];\n"
    "    for (int a = 1; a <= radius; a += 2) {\n"
    "        for (int s = -1; s <= 1; s += 2) {\n"
    "            int q0 = c + s * a, q1 = c + s * (a + 1);\n"
    "            if (!inside(q0, n)) continue;\n"
    "            float w0 = weights[a], w1 = a + 1 <= radius && inside(q1, n) ? weights[a + 1] : 0.0;\n"
    "            float offset = float(s) * (float(a) + w1 / (w0 + w1));\n"
    "            sum += (w0 + w1) * texture(image, centre + offset * vec2(axis) * texel);\n"
    "            total += w0 + w1;\n"
    "        }\n"
    "    }\n"
    "    color = sum / total;\n"
    "}\n";

typedef struct gpu {
    const halo_glfuncs *f;
    GLuint taps, linear, textures[3], framebuffer, vertex_array;
    int n;
} gpu;

static GLuint build(const halo_glfuncs *f, const char *fragment)
{
    GLuint shaders[2] = {f->CreateShader(GL_VERTEX_SHADER), f->CreateShader(GL_FRAGMENT_SHADER)};
    const char *sources[2] = {vertex_source, fragment};
    GLuint program = f->CreateProgram();
    for (int i = 0; i < 2; ++i) {
        f->ShaderSource(shaders[i], 1, &sources[i], NULL);
        f->CompileShader(shaders[i]);
        GLint ok = 0;
        f->GetShaderiv(shaders[i], GL_COMPILE_STATUS, &ok);
        if (!ok) {
            char log[2048];
            f->GetShaderInfoLog(shaders[i], sizeof log, NULL, log);
            fprintf(stderr, "halo-validate blur: shader: %s\n", log);
        }
        f->AttachShader(program, shaders[i]);
    }
    f->LinkProgram(program);
    GLint linked = 0;
    f->GetProgramiv(program, GL_LINK_STATUS, &linked);
    for (int i = 0; i < 2; ++i)
        f->DeleteShader(shaders[i]);
    if (!linked) {
        f->DeleteProgram(program);
        return 0;
    }
    return program;
}

/* Draws program into textures[dst] from textures[src] along axis. */
static void draw(gpu *g, GLuint program, int r, const float *w, int src, int dst, int ax, int ay)
{
    const halo_glfuncs *f = g->f;
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, g->textures[dst], 0);
    f->UseProgram(program);
    f->BindTexture(GL_TEXTURE_2D, g->textures[src]);
    f->Uniform1i(f->GetUniformLocation(program, "image"), 0);
    f->Uniform1i(f->GetUniformLocation(program, "radius"), r);
    f->Uniform1fv(f->GetUniformLocation(program, "weights"), r + 1, w);
    f->Uniform2i(f->GetUniformLocation(program, "axis"), ax, ay);
    f->DrawArrays(GL_TRIANGLES, 0, 3);
}

enum { V_GPU_DIRECT, V_GPU_SEPARABLE, V_GPU_LINEAR, V_CPU_DIRECT, V_CPU_SEPARABLE, V_COUNT };
static const char *const variant_names[V_COUNT] = {"gpu direct", "gpu separable", "gpu linear", "cpu direct",
                                                   "cpu separable"};

/* Runs variant v once; the result in out (RGBA floats). */
static void run_variant(gpu *g, int v, int r, const float *w, const float *in, float *scratch, float *out)
{
    int n = g->n;
    const halo_glfuncs *f = g->f;
    if (v == V_CPU_DIRECT) {
        cpu_direct(n, r, in, out);
        return;
    }
    if (v == V_CPU_SEPARABLE) {
        cpu_separable(n, r, in, scratch, out);
        return;
    }
    f->BindFramebuffer(GL_FRAMEBUFFER, g->framebuffer);
    f->Viewport(0, 0, n, n);
    f->BindVertexArray(g->vertex_array);
    f->ActiveTexture(GL_TEXTURE0);
    int last;
    if (v == V_GPU_DIRECT) {
        draw(g, g->taps, r, w, 0, 2, 0, 0);
        last = 2;
    } else {
        GLuint program = v == V_GPU_LINEAR ? g->linear : g->taps;
        draw(g, program, r, w, 0, 1, 1, 0);
        draw(g, program, r, w, 1, 2, 0, 1);
        last = 2;
    }
    f->Finish(); /* the time ends when the GPU has drawn; the read-back is not timed */
    if (out) {
        f->ReadBuffer(GL_COLOR_ATTACHMENT0);
        f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, g->textures[last], 0);
        f->ReadPixels(0, 0, n, n, GL_RGBA, GL_FLOAT, out);
    }
    f->BindTexture(GL_TEXTURE_2D, 0);
    f->UseProgram(0);
    f->BindVertexArray(0);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int halo_blur_report_main(int argc, char **argv)
{
    int n = 512, repeat = 3;
    int sizes[8] = {5, 33}, size_count = 2;
    const char *csv_path = NULL;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--csv") && i + 1 < argc)
            csv_path = argv[++i];
        else if (!strcmp(argv[i], "--size") && i + 1 < argc)
            n = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--repeat") && i + 1 < argc)
            repeat = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--kernels") && i + 1 < argc) {
            /* every size given is run: an empty list, a stray comma or a ninth size is an error */
            const char *list = argv[++i];
            char *end = NULL;
            size_count = 0;
            for (const char *s = list;; s = end + 1) {
                long k = strtol(s, &end, 10);
                if (end == s || (*end && *end != ',') || size_count == 8)
                    return fprintf(stderr,
                                   "halo-validate blur: --kernels takes 1 to 8 odd sizes K1,K2,... (3..%d), "
                                   "not '%s'\n",
                                   2 * MAX_RADIUS + 1, list),
                           2;
                sizes[size_count++] = k < 0 || k > 1 << 20 ? 0 : (int)k;
                if (!*end)
                    break;
            }
        } else if (!strcmp(argv[i], "--help")) {
            printf(
                "Usage: halo-validate blur [--size N] [--repeat R] [--kernels K1,K2,...] [--csv FILE]\n"
                "Gaussian blur of the outline passes (docs/blur.md): K x K kernels (K odd, default 5,33;\n"
                "sigma = (K-1)/6, truncated at 3 sigma, weights renormalized inside the image) on an\n"
                "N x N RGBA32F image (default 512): time (median of R, default 3) and largest error\n"
                "against a double-precision direct 2D convolution, for GPU direct / separable /\n"
                "linear-sampled (bilinear tap pairs) and CPU direct / separable, beside the paper's\n"
                "anchors (Svakhine et al. 2009: 5x5 33 fps GPU, 2.7 fps CPU; 33x33 9.5 / 0.07); then the\n"
                "separable GPU blur of the largest kernel's sigma truncated at 1..4 sigma against the\n"
                "Gaussian cut at 6 sigma. --csv FILE: every row as CSV as well.\n"
                "Exit status: 0; 1 an error above 1e-5; 2 usage or no OpenGL context.\n");
            return 0;
        } else {
            fprintf(stderr, "halo-validate blur: unknown option '%s' (try --help)\n", argv[i]);
            return 2;
        }
    }
    if (n < 16 || n > 4096 || repeat < 1 || repeat > 50)
        return fprintf(stderr, "halo-validate blur: --size 16..4096, --repeat 1..50\n"), 2;
    for (int k = 0; k < size_count; ++k)
        if (sizes[k] < 3 || sizes[k] % 2 == 0 || sizes[k] > 2 * MAX_RADIUS + 1)
            return fprintf(stderr, "halo-validate blur: kernel sizes odd, 3..%d\n", 2 * MAX_RADIUS + 1), 2;
    FILE *csv = NULL;
    if (csv_path) {
        csv = fopen(csv_path, "w");
        if (!csv)
            return fprintf(stderr, "halo-validate blur: cannot write %s\n", csv_path), 2;
        fprintf(csv, "table,kernel,variant,sigma,truncation_sigmas,radius,ms,fps,max_abs,rmse\n");
    }
    char err[256];
    halo_headless *context = halo_headless_create(16, 16, err, sizeof err);
    if (!context) {
        if (csv)
            fclose(csv);
        return fprintf(stderr, "halo-validate blur: no OpenGL context: %s\n", err), 2;
    }
    halo_glfuncs funcs;
    const char *missing = NULL;
    if (!halo_glfuncs_load(&funcs, sizeof funcs, halo_headless_get_proc_address, &missing)) {
        fprintf(stderr, "halo-validate blur: missing GL function %s\n", missing ? missing : "?");
        halo_headless_destroy(context);
        return 2;
    }
    gpu g = {.f = &funcs, .n = n};
    const halo_glfuncs *f = &funcs;
    size_t count = (size_t)n * n * 4;
    float *in = malloc(count * sizeof *in), *out = malloc(count * sizeof *out),
          *scratch = malloc(count * sizeof *scratch);
    double *ref = malloc(count * sizeof *ref);
    int status = 0;
    g.taps = build(f, taps_source);
    g.linear = build(f, linear_source);
    if (!in || !out || !scratch || !ref || !g.taps || !g.linear) {
        fprintf(stderr, "halo-validate blur: setup failed\n");
        status = 2;
        goto done;
    }
    make_image(n, in);
    f->GenTextures(3, g.textures);
    for (int t = 0; t < 3; ++t) {
        f->BindTexture(GL_TEXTURE_2D, g.textures[t]);
        f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, n, n, 0, GL_RGBA, GL_FLOAT, t == 0 ? in : NULL);
    }
    f->BindTexture(GL_TEXTURE_2D, 0);
    f->GenFramebuffers(1, &g.framebuffer);
    f->GenVertexArrays(1, &g.vertex_array);
    FILE *load = fopen("/proc/loadavg", "r");
    char loadavg[64] = "unknown";
    if (load) {
        if (!fgets(loadavg, sizeof loadavg, load))
            snprintf(loadavg, sizeof loadavg, "unknown");
        loadavg[strcspn(loadavg, "\n")] = '\0';
        fclose(load);
    }
    printf("blur: %dx%d RGBA32F, %s backend, %s, median of %d; load average %s\n", n, n, halo_headless_backend(context),
           halo_headless_renderer(context), repeat, loadavg);
    printf("%-7s %-14s %12s %10s %12s %s\n", "kernel", "variant", "ms/frame", "fps", "max_abs_err", "paper (fps)");
    for (int k = 0; k < size_count; ++k) {
        int r = (sizes[k] - 1) / 2;
        double wd[MAX_RADIUS + 1];
        float w[MAX_RADIUS + 1];
        gauss_weights(r, wd);
        for (int i = 0; i <= r; ++i)
            w[i] = (float)wd[i];
        reference(n, r, in, ref);
        for (int v = 0; v < V_COUNT; ++v) {
            double times[50];
            run_variant(&g, v, r, w, in, scratch, out); /* warm-up: llvmpipe compiles shader variants on first use */
            for (int rep = 0; rep < repeat; ++rep) {
                f->Finish();
                double t0 = now();
                run_variant(&g, v, r, w, in, scratch, v < V_CPU_DIRECT ? NULL : out);
                times[rep] = now() - t0;
            }
            qsort(times, (size_t)repeat, sizeof *times, compare_doubles);
            double t = times[repeat / 2], worst = 0.0;
            for (size_t i = 0; i < count; ++i) {
                double e = isfinite(out[i]) ? fabs(out[i] - ref[i]) : INFINITY;
                worst = e > worst ? e : worst;
            }
            const char *paper = "";
            if (sizes[k] == 5)
                paper = v == V_GPU_DIRECT ? "33 (8800 GTX, 2009)" : v == V_CPU_DIRECT ? "2.7 (CPU, 2009)" : "";
            else if (sizes[k] == 33)
                paper = v == V_GPU_DIRECT ? "9.5 (8800 GTX, 2009)" : v == V_CPU_DIRECT ? "0.07 (CPU, 2009)" : "";
            char label[16];
            snprintf(label, sizeof label, "%dx%d", sizes[k], sizes[k]);
            printf("%-7s %-14s %12.2f %10.2f %12.2e %s\n", label, variant_names[v], 1e3 * t, 1.0 / t, worst, paper);
            if (csv)
                fprintf(csv, "variants,%d,%s,%.6g,3,%d,%.3f,%.3f,%.6e,\n", sizes[k], variant_names[v], r / 3.0, r,
                        1e3 * t, 1.0 / t, worst);
            fflush(stdout);
            if (!(worst <= 1e-5))
                status = 1;
        }
    }
    /* Truncation: the sigma of the largest kernel, the separable GPU blur cut at t sigma,
     * against the same Gaussian cut at 6 sigma (exp(-18): nothing left to cut). */
    double *exact = malloc(count * sizeof *exact), *exact_scratch = malloc(count * sizeof *exact_scratch);
    int r_max = (sizes[size_count - 1] - 1) / 2;
    double sigma = r_max / 3.0;
    int r_exact = (int)ceil(6.0 * sigma);
    if (exact && exact_scratch && r_exact <= MAX_RADIUS) {
        reference_separable(n, r_exact, sigma, in, exact_scratch, exact);
        printf(
            "truncation: sigma %.3g px (the %dx%d kernel's), gpu separable cut at t sigma, against the Gaussian cut "
            "at 6 sigma (radius %d) in double\n",
            sigma, sizes[size_count - 1], sizes[size_count - 1], r_exact);
        printf("%-7s %-7s %12s %10s %12s %12s\n", "t", "radius", "ms/frame", "fps", "max_abs_err", "rmse");
        static const double cuts[] = {1.0, 1.5, 2.0, 2.5, 3.0, 4.0};
        for (size_t c = 0; c < sizeof cuts / sizeof cuts[0]; ++c) {
            int r = (int)ceil(cuts[c] * sigma - 1e-9);
            double wd[MAX_RADIUS + 1];
            float w[MAX_RADIUS + 1];
            gauss_weights_sigma(r, sigma, wd);
            for (int i = 0; i <= r; ++i)
                w[i] = (float)wd[i];
            double times[50];
            run_variant(&g, V_GPU_SEPARABLE, r, w, in, scratch, out);
            for (int rep = 0; rep < repeat; ++rep) {
                f->Finish();
                double t0 = now();
                run_variant(&g, V_GPU_SEPARABLE, r, w, in, scratch, NULL);
                times[rep] = now() - t0;
            }
            qsort(times, (size_t)repeat, sizeof *times, compare_doubles);
            double t = times[repeat / 2], worst = 0.0, squares = 0.0;
            for (size_t i = 0; i < count; ++i) {
                double e = isfinite(out[i]) ? fabs(out[i] - exact[i]) : INFINITY;
                worst = e > worst ? e : worst;
                squares += e * e;
            }
            printf("%-7.1f %-7d %12.2f %10.2f %12.2e %12.2e%s\n", cuts[c], r, 1e3 * t, 1.0 / t, worst,
                   sqrt(squares / (double)count), cuts[c] == 3.0 ? "  (libhalo's outlines)" : "");
            if (csv)
                fprintf(csv, "truncation,%d,gpu separable,%.6g,%g,%d,%.3f,%.3f,%.6e,%.6e\n", 2 * r + 1, sigma, cuts[c],
                        r, 1e3 * t, 1.0 / t, worst, sqrt(squares / (double)count));
            fflush(stdout);
        }
    }
    free(exact);
    free(exact_scratch);
    if (f->GetError() != GL_NO_ERROR) {
        fprintf(stderr, "halo-validate blur: OpenGL error\n");
        status = 2;
    }
done:
    if (g.framebuffer)
        f->DeleteFramebuffers(1, &g.framebuffer);
    if (g.textures[0])
        f->DeleteTextures(3, g.textures);
    if (g.vertex_array)
        f->DeleteVertexArrays(1, &g.vertex_array);
    if (g.taps)
        f->DeleteProgram(g.taps);
    if (g.linear)
        f->DeleteProgram(g.linear);
    free(in);
    free(out);
    free(scratch);
    free(ref);
    halo_headless_destroy(context);
    if (csv && fclose(csv) != 0) {
        fprintf(stderr, "halo-validate blur: cannot write %s\n", csv_path);
        status = 2;
    }
    return status;
}
