/* NiiVue's frame drawn by libhalo's C runtime, for tests/adapters/web/browser.mjs:
 *
 *   niivue_reference SCENE DIR OUT
 *
 * draws examples/hosts/niivue_caster.frag (a host in the style of NiiVue's 3D render),
 * linked with SCENE (drawn once, host contract 3, where it has halos), with what the page
 * exported from NiiVue into DIR: view.txt (the canvas's size, the camera libhalo's adapter
 * gave its runtime, the background, the volume's size; the step is NiiVue's, a voxel along
 * the view), color.u8 (NiiVue's
 * classified volume, RGBA8, x fastest) and volume.f32 (the values the stages see, x
 * fastest; for feature halos libhalo's runtime splats their buffer from them, for the view
 * from the volume's centre to the eye in voxel space, as the adapter does), and optionally
 * jitter.f32 (each pixel's jitter as the page's GPU computed it,
 * width * height floats, rows bottom-up); and writes OUT: width * height RGBA floats, rows bottom-up as readPixels gives
 * them, the host's output blended over the background as NiiVue's framebuffer blends it
 * (source alpha, one minus source alpha; the output clamped to [0,1] first, as a fixed-point
 * framebuffer does). view.txt may also say `empty_space_pass 0` or `1` (default: NiiVue's,
 * off for halos), for a control. Only NiiVue's render layout (the 3D view at the canvas's
 * origin: the jitter's pixel coordinates). Exit 0, 1 for a failed draw (diagnostics on
 * stderr), 2 for bad input, 77 without an OpenGL context, 99 for a broken set-up. */
#include "../../gl_fixture.h"
#include "halo_feature.h"
#include "hosts/raycast.h"

#include <math.h>
#include <string.h>

typedef struct view {
    int width, height, dims[3];
    int empty_space_pass; /* -1: as the adapter (off with halos); 0 or 1: so (a test's control) */
    double inverse[16], step, background[3];
} view;

/* "word numbers..." lines of DIR/view.txt into v; 0 after a message. */
static int read_view(const char *dir, view *v)
{
    char path[4096], word[32];
    snprintf(path, sizeof path, "%s/view.txt", dir);
    FILE *in = fopen(path, "r");
    if (!in) {
        fprintf(stderr, "niivue_reference: cannot open %s\n", path);
        return 0;
    }
    int seen = 0;
    while (fscanf(in, "%31s", word) == 1) {
        int ok = 1;
        if (!strcmp(word, "size"))
            ok = fscanf(in, "%d %d", &v->width, &v->height) == 2, seen |= 1;
        else if (!strcmp(word, "dims"))
            ok = fscanf(in, "%d %d %d", &v->dims[0], &v->dims[1], &v->dims[2]) == 3, seen |= 2;
        else if (!strcmp(word, "background"))
            ok = fscanf(in, "%lf %lf %lf", &v->background[0], &v->background[1], &v->background[2]) == 3, seen |= 8;
        else if (!strcmp(word, "empty_space_pass"))
            ok = fscanf(in, "%d", &v->empty_space_pass) == 1 && v->empty_space_pass >= 0 && v->empty_space_pass <= 1;
        else if (!strcmp(word, "inverse")) {
            for (int i = 0; i < 16 && ok; ++i)
                ok = fscanf(in, "%lf", &v->inverse[i]) == 1;
            seen |= 16;
        } else
            ok = 0;
        if (!ok) {
            fprintf(stderr, "niivue_reference: %s: bad or unknown entry '%s'\n", path, word);
            fclose(in);
            return 0;
        }
    }
    fclose(in);
    if (seen != 27 || v->width < 1 || v->height < 1 || v->width > 4096 || v->height > 4096) {
        fprintf(stderr, "niivue_reference: %s: needs size, dims, background and inverse\n", path);
        return 0;
    }
    for (int c = 0; c < 3; ++c)
        if (v->dims[c] < 2 || v->dims[c] > 1024) {
            fprintf(stderr, "niivue_reference: %s: dims must be 2..1024\n", path);
            return 0;
        }
    /* the step NiiVue's rays take: a voxel along the ray, here the view axis's (the centre's
     * ray: clip (0, 0, -1) to (0, 0, 1)); libhalo's segments are on planes that far apart */
    double near[3], far[3], length = 0.0, voxels = 0.0;
    for (int c = 0; c < 3; ++c) {
        near[c] = (v->inverse[12 + c] - v->inverse[8 + c]) / (v->inverse[15] - v->inverse[11]);
        far[c] = (v->inverse[12 + c] + v->inverse[8 + c]) / (v->inverse[15] + v->inverse[11]);
        length += (far[c] - near[c]) * (far[c] - near[c]);
        voxels += (far[c] - near[c]) * v->dims[c] * (far[c] - near[c]) * v->dims[c];
    }
    v->step = sqrt(length / voxels);
    if (!(v->step > 0.0 && v->step < 1.0)) {
        fprintf(stderr, "niivue_reference: %s: the camera gives no step along its view\n", path);
        return 0;
    }
    return 1;
}

/* DIR/NAME's bytes, exactly size of them, into a new buffer; NULL after a message (none
 * for a file that is not there when optional). */
static void *read_exact(const char *dir, const char *name, size_t size, int optional)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *in = fopen(path, "rb");
    if (!in) {
        if (!optional)
            fprintf(stderr, "niivue_reference: cannot open %s\n", path);
        return NULL;
    }
    void *data = malloc(size + 1);
    size_t got = data ? fread(data, 1, size + 1, in) : 0;
    fclose(in);
    if (!data)
        fprintf(stderr, "niivue_reference: out of memory for %s\n", path);
    else if (got != size) {
        fprintf(stderr, "niivue_reference: %s: not %zu bytes\n", path, size);
        free(data);
        return NULL;
    }
    return data;
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: niivue_reference SCENE DIR OUT\n");
        return 2;
    }
    view v = {.empty_space_pass = -1};
    if (!read_view(argv[2], &v))
        return 2;
    size_t voxels = (size_t)v.dims[0] * v.dims[1] * v.dims[2], pixels = (size_t)v.width * v.height;
    unsigned char *bytes = read_exact(argv[2], "color.u8", voxels * 4, 0);
    float *values = read_exact(argv[2], "volume.f32", voxels * sizeof(float), 0);
    float *color = malloc(voxels * 4 * sizeof *color), *rgba = malloc(pixels * 4 * sizeof *rgba);
    if (!bytes || !values || !color || !rgba) {
        if (bytes && values && (!color || !rgba))
            fprintf(stderr, "niivue_reference: out of memory\n");
        free(bytes), free(values), free(color), free(rgba);
        return 2;
    }
    for (size_t i = 0; i < voxels * 4; ++i)
        color[i] = (float)bytes[i] / 255.0f;
    free(bytes);
    char jitter_path[4096];
    snprintf(jitter_path, sizeof jitter_path, "%s/jitter.f32", argv[2]);
    FILE *probe = fopen(jitter_path, "rb");
    if (probe)
        fclose(probe);
    float *jitter = probe ? read_exact(argv[2], "jitter.f32", pixels * sizeof(float), 0) : NULL;
    if (probe && !jitter) {
        free(values), free(color), free(rgba);
        return 2;
    }

    gl_fixture fx;
    int status = gl_fixture_open(&fx, v.width > v.height ? v.width : v.height, 0);
    if (status) {
        free(values), free(color), free(rgba), free(jitter);
        return status;
    }
    status = 1;
    halo_scene *scene = halo_scene_load(argv[1], NULL, fx.lib, fx.diag);
    char *host = halo_host_load("niivue_caster.frag", NULL, fx.diag);
    halo_program *program = scene && host ? halo_link(&(halo_link_desc){.library = fx.lib,
                                                                        .scene = scene,
                                                                        .host_source = host,
                                                                        .host_file = "niivue_caster.frag",
                                                                        .target = HALO_TARGET_GLSL330,
                                                                        .one_draw = 1},
                                                      fx.diag)
                                          : NULL;
    halo_feature_buffer *buffer = NULL; /* feature halos: their buffer */
    halo_raycast *r =
        program ? halo_raycast_create(
                      &(halo_host_desc){
                          .gl = fx.gl, .runtime = fx.runtime, .program = program, .width = v.width, .height = v.height},
                      fx.diag)
                : NULL;
    if (r && halo_raycast_set_volume(r, values, v.dims[0], v.dims[1], v.dims[2], fx.diag) == HALO_OK &&
        halo_raycast_set_classified(r, color, v.dims[0], v.dims[1], v.dims[2], fx.diag) == HALO_OK) {
        halo_raycast_set_view(r, v.inverse, v.step);
        /* NiiVue's pass to the first opaque sample, which the adapter turns off for halos */
        unsigned gl_program = halo_raycast_gl_program(r);
        fx.gl->UseProgram(gl_program);
        fx.gl->Uniform1f(fx.gl->GetUniformLocation(gl_program, "empty_space_pass"),
                         v.empty_space_pass >= 0                  ? (float)v.empty_space_pass
                         : halo_program_reflection(program).march ? 0.0f
                                                                  : 1.0f);
        /* the page's jitter, on unit 4 (the ray caster's textures are on 0-3, libhalo's from 8) */
        unsigned jitter_texture = 0;
        fx.gl->Uniform1f(fx.gl->GetUniformLocation(gl_program, "jitter_from_image"), jitter ? 1.0f : 0.0f);
        fx.gl->Uniform1i(fx.gl->GetUniformLocation(gl_program, "jitter_image"), 4);
        fx.gl->UseProgram(0);
        if (jitter) {
            fx.gl->GenTextures(1, &jitter_texture);
            fx.gl->ActiveTexture(GL_TEXTURE4);
            fx.gl->BindTexture(GL_TEXTURE_2D, jitter_texture);
            fx.gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            fx.gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            fx.gl->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
            fx.gl->TexImage2D(GL_TEXTURE_2D, 0, GL_R32F, v.width, v.height, 0, GL_RED, GL_FLOAT, jitter);
            fx.gl->ActiveTexture(GL_TEXTURE0);
        }
        halo_feature_desc fd;
        int feature_failed = 0;
        if (halo_feature_desc_from_program(program, &fd) == HALO_OK) {
            /* the view as the adapter's (halo.featureView): from the centre to the eye, in
             * voxels; an orthographic camera's direction towards the viewer */
            const double *e = v.inverse + 8;
            double view[3], length = 0.0;
            for (int c = 0; c < 3; ++c) {
                view[c] = (e[3] != 0.0 ? e[c] / e[3] - 0.5 : -e[c]) * v.dims[c];
                length += view[c] * view[c];
            }
            for (int c = 0; c < 3; ++c)
                view[c] /= length > 0.0 ? sqrt(length) : 1.0;
            buffer = halo_feature_buffer_create(fx.runtime, values, v.dims, &fd, fx.diag);
            if (buffer && halo_feature_buffer_build(buffer, view) == HALO_OK) {
                fx.gl->UseProgram(gl_program);
                fx.gl->Uniform1i(fx.gl->GetUniformLocation(gl_program, "halo_host_feature_buffer"), 5);
                fx.gl->UseProgram(0);
                fx.gl->ActiveTexture(GL_TEXTURE5);
                fx.gl->BindTexture(GL_TEXTURE_3D, halo_feature_buffer_describe(buffer).texture);
                fx.gl->ActiveTexture(GL_TEXTURE0);
            } else
                feature_failed = 1; /* the diagnostics say why */
        }
        if (feature_failed)
            fprintf(stderr, "niivue_reference: no buffer for the feature halos\n");
        else if (jitter && fx.gl->GetError() != GL_NO_ERROR)
            fprintf(stderr, "niivue_reference: cannot upload the %dx%d jitter image\n", v.width, v.height);
        else if (halo_raycast_render(r, rgba, fx.diag) == HALO_OK)
            status = 0;
        if (buffer) {
            fx.gl->ActiveTexture(GL_TEXTURE5);
            fx.gl->BindTexture(GL_TEXTURE_3D, 0);
            fx.gl->ActiveTexture(GL_TEXTURE0);
        }
        if (jitter_texture) {
            fx.gl->ActiveTexture(GL_TEXTURE4);
            fx.gl->BindTexture(GL_TEXTURE_2D, 0);
            fx.gl->ActiveTexture(GL_TEXTURE0);
            fx.gl->DeleteTextures(1, &jitter_texture);
        }
    }
    if (status == 0) {
        for (size_t p = 0; p < pixels; ++p) {
            float *px = rgba + 4 * p;
            double a = px[3] > 0.0f ? (px[3] < 1.0f ? px[3] : 1.0) : 0.0;
            for (int c = 0; c < 3; ++c) {
                double s = px[c] > 0.0f ? (px[c] < 1.0f ? px[c] : 1.0) : 0.0;
                px[c] = (float)(s * a + v.background[c] * (1.0 - a));
            }
            px[3] = (float)(a * a + (1.0 - a)); /* over the opaque clear colour */
        }
        FILE *out = fopen(argv[3], "wb");
        if (!out || fwrite(rgba, sizeof *rgba, pixels * 4, out) != pixels * 4) {
            fprintf(stderr, "niivue_reference: cannot write %s\n", argv[3]);
            status = 2;
        }
        if (out && fclose(out) != 0)
            status = 2;
    } else
        halo_diagnostics_print(fx.diag, stderr);
    halo_feature_buffer_destroy(buffer);
    halo_raycast_destroy(r);
    halo_program_destroy(program);
    free(host);
    halo_scene_destroy(scene);
    gl_fixture_close(&fx);
    free(values), free(color), free(rgba), free(jitter);
    return status;
}
