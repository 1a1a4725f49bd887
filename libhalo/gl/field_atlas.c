/* Host contract 3's generations in a constant number of draws (issue 25): the generation
 * passes' images (the seeds, H_0, the field) as atlases of one tile per depth segment, and
 * each repetition of each pass one draw over the tiles, instead of six draws a segment.
 *
 * A tile is an image of its own: the passes' tiled variant (link.c, HALO_PASS_TILES) reads
 * 0 outside the fragment's tile, as the per-segment images read 0 outside the image. Each
 * tile keeps its support box as gl/frame.c keeps an image's (outside it the texture holds
 * 0; a pass writes the tile where its inputs' support grown by its reach can be nonzero,
 * and where the target held a nonzero from before), so the draw covers a rectangle a tile,
 * in one vertex buffer. A running=associative pass (O_t = O_(t-1) op I_t: the occlusion
 * image's running maximum) is a prefix scan over the tiles in log2 draws, or a tile a draw
 * where the frame reads back (a software renderer: the pixels are the cost). What the
 * generations compute is the per-segment path's: the same programs, the same floats
 * (conformance: `halo-validate conform --stage segments`). */
#include "gl/field_atlas.h"

#include "diag.h"
#include "gl/runtime.h"

#include <stdlib.h>
#include <string.h>

#define ATLAS_MAX_IMAGES 8
#define ATLAS_MAX_PASSES 16

typedef struct atlas_image {
    const char *name;
    GLint internal_format;
    GLenum format;
    GLuint texture[2]; /* [1] only where `count` is 2 */
    int count;         /* textures: 2 where a pass reads the image it writes, or it is written
                        * more than once a generation (the field); else 1 (the seeds, H_0) */
    int current;
    int alternate;        /* tile t's content in texture t % 2 (a running pass a tile a draw) */
    int (*support[2])[4]; /* per tile, in the tile's pixels */
} atlas_image;

typedef struct atlas_pass {
    const halo_pass_info *info;
    GLuint program;
    GLint index_location, count_location, tile_location;
    GLint columns_location, back_location; /* a running pass's scan (link.c) */
    int inputs[HALO_MAX_PASS_INPUTS];      /* image index; -1: previous */
    int output, first;                     /* first: -1 for the output itself */
    int repeat, start;
} atlas_pass;

struct halo_gl_field_atlas {
    halo_gl_frame *frame;
    int width, height; /* a tile's */
    int columns, rows, tiles;
    atlas_image images[ATLAS_MAX_IMAGES];
    int image_count, seed; /* seed: the prepass's output image */
    atlas_pass passes[ATLAS_MAX_PASSES];
    int pass_count;
    GLuint framebuffer, vertex_array, buffer;
    float *vertices; /* 12 floats a tile */
    int (*boxes)[4]; /* a draw's rectangle per tile */
};

static const char atlas_vertex_330[] =
    "#version 330 core\n"
    "layout(location = 0) in vec2 corner;\n"
    "void main() { gl_Position = vec4(corner, 0.0, 1.0); }\n";
static const char atlas_vertex_es300[] =
    "#version 300 es\n"
    "layout(location = 0) in vec2 corner;\n"
    "void main() { gl_Position = vec4(corner, 0.0, 1.0); }\n";

static int box_empty(const int b[4]) { return b[0] >= b[2] || b[1] >= b[3]; }

static void box_union(int to[4], const int b[4])
{
    if (box_empty(b))
        return;
    if (box_empty(to)) {
        memcpy(to, b, 4 * sizeof *to);
        return;
    }
    for (int k = 0; k < 2; ++k) {
        to[k] = b[k] < to[k] ? b[k] : to[k];
        to[k + 2] = b[k + 2] > to[k + 2] ? b[k + 2] : to[k + 2];
    }
}

static int atlas_find_image(halo_gl_field_atlas *a, const char *name, int add)
{
    for (int i = 0; i < a->image_count; ++i)
        if (!strcmp(a->images[i].name, name))
            return i;
    if (!add || a->image_count == ATLAS_MAX_IMAGES)
        return -1;
    a->images[a->image_count].name = name;
    return a->image_count++;
}

void halo_gl_field_atlas_destroy(const halo_glfuncs *f, halo_gl_field_atlas *a)
{
    if (!a)
        return;
    for (int i = 0; i < a->image_count; ++i) {
        f->DeleteTextures(2, a->images[i].texture);
        free(a->images[i].support[0]);
        free(a->images[i].support[1]);
    }
    for (int k = 0; k < a->pass_count; ++k)
        f->DeleteProgram(a->passes[k].program);
    f->DeleteFramebuffers(1, &a->framebuffer);
    f->DeleteVertexArrays(1, &a->vertex_array);
    f->DeleteBuffers(1, &a->buffer);
    free(a->vertices);
    free(a->boxes);
    free(a);
}

size_t halo_gl_field_atlas_bytes(const halo_gl_field_atlas *a)
{
    size_t bytes = 0;
    for (int i = 0; a && a->tiles > 0 && i < a->image_count; ++i)
        bytes += (size_t)a->images[i].count * (size_t)a->columns * (size_t)a->width * (size_t)a->rows *
                 (size_t)a->height * halo_gl_image_texel_bytes(a->images[i].internal_format);
    return bytes;
}

/* The passes of the generation that write image, or read it. */
static int atlas_users(const halo_gl_field_atlas *a, int image)
{
    int n = 0;
    for (int k = 0; k < a->pass_count; ++k) {
        int uses = a->passes[k].output == image;
        for (int i = 0; i < a->passes[k].info->input_count; ++i)
            uses |= a->passes[k].inputs[i] == image;
        n += uses;
    }
    return n;
}

/* The textures image needs (atlas_image.count). */
static int atlas_texture_count(const halo_gl_field_atlas *a, int image)
{
    int writes = 0;
    for (int k = 0; k < a->pass_count; ++k) {
        const atlas_pass *pass = &a->passes[k];
        if (pass->output != image)
            continue;
        writes += pass->repeat - pass->start + 1;
        for (int i = 0; i < pass->info->input_count; ++i)
            if (pass->inputs[i] < 0 || pass->inputs[i] == image)
                return 2;
    }
    return writes > 1 ? 2 : 1;
}

/* The passes and images of the frame's generations; 0 where they do not suit an atlas. */
static int atlas_plan(halo_gl_field_atlas *a)
{
    const halo_program *p = halo_gl_frame_program(a->frame);
    const halo_glfuncs *f = halo_gl_functions(halo_gl_frame_runtime(a->frame));
    halo_reflection r = halo_program_reflection(p);
    if (!p->prepass || halo_program_reflection(p->prepass).output_count != 1)
        return 0;
    a->seed = atlas_find_image(a, halo_program_reflection(p->prepass).outputs[0].image, 1);
    /* written[i]: image i holds this frame's content before the pass that reads it (the
     * seeds, or an earlier pass's output); an image read before it is written would be the
     * generation before's (a running image) or never written */
    int written[ATLAS_MAX_IMAGES] = {0};
    written[a->seed] = 1;
    for (size_t i = 0; i < r.pass_count; ++i) {
        const halo_pass_info *info = &r.passes[i];
        if (info->at != HALO_PASS_AT_GENERATE)
            continue;
        if (a->pass_count == ATLAS_MAX_PASSES || info->reach < 0 || info->input_count > HALO_MAX_PASS_INPUTS)
            return 0;
        atlas_pass *pass = &a->passes[a->pass_count++];
        pass->info = info;
        pass->repeat = info->repeat < 1 ? 1 : info->repeat;
        pass->start = info->start < 1 ? 1 : info->start;
        pass->output = atlas_find_image(a, info->output, 1);
        pass->first = info->first ? atlas_find_image(a, info->first, 1) : -1;
        if (pass->output < 0 || (info->first && (pass->first < 0 || !written[pass->first])))
            return 0;
        for (int k = 0; k < info->input_count; ++k) {
            int previous = !strcmp(info->inputs[k], "previous");
            pass->inputs[k] = previous ? -1 : atlas_find_image(a, info->inputs[k], 1);
            /* an image of the generation before is not per tile, but for a running pass's
             * own output (a prefix scan over the tiles: halo_gl_field_atlas_generate) */
            int running = info->running && k == 1 && pass->inputs[k] == pass->output;
            if (!previous && (pass->inputs[k] < 0 || (!written[pass->inputs[k]] && !running)))
                return 0;
            if (previous && !info->first && !written[pass->output])
                return 0;
        }
        written[pass->output] = 1;
        /* the pass's tiled variant, with a vertex shader of the tiles' corners */
        pass->program = info->fragment_source && strstr(info->fragment_source, "HALO_PASS_TILES")
                            ? halo_gl_pass_build(halo_gl_frame_runtime(a->frame), p, i,
                                                 p->target == HALO_TARGET_ES300 ? atlas_vertex_es300 : atlas_vertex_330,
                                                 "HALO_PASS_TILES", NULL)
                            : 0;
        if (!pass->program)
            return 0;
        pass->index_location = f->GetUniformLocation(pass->program, "halo_pass_index");
        pass->count_location = f->GetUniformLocation(pass->program, "halo_pass_count");
        pass->tile_location = f->GetUniformLocation(pass->program, "halo_tile_size");
        pass->columns_location = f->GetUniformLocation(pass->program, "halo_tile_columns");
        pass->back_location = f->GetUniformLocation(pass->program, "halo_tile_back");
        if (info->running && (pass->inputs[1] != pass->output || pass->back_location < 0))
            return 0;
    }
    if (a->pass_count == 0)
        return 0;
    /* every image of one size (the tile), cleared to 0 and kept at 0 outside its support by
     * the passes */
    for (int i = 0; i < a->image_count; ++i) {
        halo_gl_frame_image view;
        const halo_image_info *info = NULL;
        for (size_t k = 0; k < r.image_count && !info; ++k)
            info = !strcmp(r.images[k].name, a->images[i].name) ? &r.images[k] : NULL;
        if (!info || info->clear != 0.0 || !halo_gl_frame_image_view(a->frame, a->images[i].name, &view))
            return 0;
        /* a running pass's output: the generation before's carries over (not reset), and no
         * other pass writes or reads it (a tile a draw leaves its tiles in two textures) */
        for (int k = 0; k < a->pass_count; ++k)
            if (a->passes[k].output == i && a->passes[k].info->running &&
                (info->reset == HALO_RESET_GENERATION || atlas_users(a, i) != 1))
                return 0;
        if (i == 0) {
            a->width = view.width;
            a->height = view.height;
        } else if (view.width != a->width || view.height != a->height) {
            return 0;
        }
        a->images[i].internal_format = view.internal_format;
        a->images[i].count = atlas_texture_count(a, i);
    }
    /* the scan's first step reads input 0 as the output's own tiles */
    for (int k = 0; k < a->pass_count; ++k)
        if (a->passes[k].info->running &&
            a->images[a->passes[k].inputs[0]].internal_format != a->images[a->passes[k].output].internal_format)
            return 0;
    return a->width > 0 && a->height > 0;
}

/* Textures of `tiles` tiles (a grid as near square as the largest texture allows), cleared
 * (0 everywhere: every tile's support empty); 0 when it does not fit. */
static int atlas_allocate(halo_gl_field_atlas *a, int tiles, size_t max_bytes)
{
    const halo_glfuncs *f = halo_gl_functions(halo_gl_frame_runtime(a->frame));
    GLint largest = 2048, viewport[2] = {2048, 2048};
    f->GetIntegerv(GL_MAX_TEXTURE_SIZE, &largest);
    f->GetIntegerv(GL_MAX_VIEWPORT_DIMS, viewport); /* one draw covers the atlas */
    largest = viewport[0] < largest ? viewport[0] : largest;
    largest = viewport[1] < largest ? viewport[1] : largest;
    int columns = 1;
    while (columns * columns < tiles)
        ++columns;
    if (columns * a->width > largest)
        columns = largest / a->width;
    int rows = columns > 0 ? (tiles + columns - 1) / columns : 0;
    if (columns < 1 || rows * a->height > largest)
        return 0;
    size_t bytes = 0, pixels = (size_t)columns * (size_t)a->width * (size_t)rows * (size_t)a->height;
    for (int i = 0; i < a->image_count; ++i)
        bytes += (size_t)a->images[i].count * pixels * halo_gl_image_texel_bytes(a->images[i].internal_format);
    if (bytes > max_bytes)
        return 0;
    /* a draw's rectangles: two triangles a tile */
    float *vertices = realloc(a->vertices, (size_t)columns * (size_t)rows * 12 * sizeof *vertices);
    if (vertices)
        a->vertices = vertices;
    int(*boxes)[4] = realloc(a->boxes, (size_t)columns * (size_t)rows * sizeof *boxes);
    if (boxes)
        a->boxes = boxes;
    if (!vertices || !boxes)
        return 0;
    GLint framebuffer = 0;
    f->GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, a->framebuffer);
    GLenum buffer = GL_COLOR_ATTACHMENT0;
    f->DrawBuffers(1, &buffer);
    int allocated = 1;
    for (int i = 0; allocated && i < a->image_count; ++i) {
        atlas_image *im = &a->images[i];
        for (int k = 0; k < im->count; ++k) {
            int(*support)[4] = realloc(im->support[k], (size_t)columns * (size_t)rows * sizeof *support);
            if (!support) {
                allocated = 0;
                break;
            }
            im->support[k] = support;
            memset(support, 0, (size_t)columns * (size_t)rows * sizeof *support);
            if (!im->texture[k])
                f->GenTextures(1, &im->texture[k]);
            f->BindTexture(GL_TEXTURE_2D, im->texture[k]);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            GLenum format, type;
            halo_gl_image_upload_format(im->internal_format, &format, &type);
            f->TexImage2D(GL_TEXTURE_2D, 0, im->internal_format, columns * a->width, rows * a->height, 0, format, type,
                          NULL);
            /* (a clear obeys the scissor and colour mask: the caller's, field.c: field_save) */
            const GLfloat zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
            f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, im->texture[k], 0);
            f->ClearBufferfv(GL_COLOR, 0, zero);
        }
        im->current = 0;
        im->alternate = 0;
    }
    f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)framebuffer);
    if (!allocated || f->GetError() != GL_NO_ERROR)
        return 0;
    a->columns = columns;
    a->rows = rows;
    a->tiles = columns * rows;
    return 1;
}

halo_gl_field_atlas *halo_gl_field_atlas_reserve(halo_gl_frame *fr, halo_gl_field_atlas *atlas, int tiles,
                                                 size_t max_bytes, int *unsuited)
{
    const halo_glfuncs *f = halo_gl_functions(halo_gl_frame_runtime(fr));
    *unsuited = 0;
    if (atlas && atlas->tiles >= tiles)
        return atlas;
    if (!atlas) {
        atlas = calloc(1, sizeof *atlas);
        if (!atlas)
            return NULL;
        atlas->frame = fr;
        GLint program = 0, texture = 0;
        f->GetIntegerv(GL_CURRENT_PROGRAM, &program);
        f->GetIntegerv(GL_TEXTURE_BINDING_2D, &texture);
        int planned = atlas_plan(atlas);
        halo_gl_use_saved_program(f, program);
        if (!planned) {
            *unsuited = 1;
            halo_gl_field_atlas_destroy(f, atlas);
            return NULL;
        }
        f->GenFramebuffers(1, &atlas->framebuffer);
        f->GenVertexArrays(1, &atlas->vertex_array);
        f->GenBuffers(1, &atlas->buffer);
        f->BindTexture(GL_TEXTURE_2D, (GLuint)texture);
    }
    GLint texture = 0;
    f->GetIntegerv(GL_TEXTURE_BINDING_2D, &texture);
    int allocated = atlas_allocate(atlas, tiles + tiles / 4, max_bytes) || atlas_allocate(atlas, tiles, max_bytes);
    f->BindTexture(GL_TEXTURE_2D, (GLuint)texture);
    for (int k = 0; k < 8 && !allocated && f->GetError() != GL_NO_ERROR; ++k) {}
    if (!allocated) {
        halo_gl_field_atlas_destroy(f, atlas);
        return NULL;
    }
    return atlas;
}

void halo_gl_field_atlas_begin(halo_gl_field_atlas *a)
{
    const halo_glfuncs *f = halo_gl_functions(halo_gl_frame_runtime(a->frame));
    atlas_image *seed = &a->images[a->seed];
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, a->framebuffer);
    f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, seed->texture[seed->current], 0);
    GLenum buffer = GL_COLOR_ATTACHMENT0;
    f->DrawBuffers(1, &buffer);
    const GLfloat zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    f->ClearBufferfv(GL_COLOR, 0, zero);
    f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
    for (int t = 0; t < a->tiles; ++t)
        memset(seed->support[seed->current][t], 0, 4 * sizeof(int));
}

void halo_gl_field_atlas_seed(halo_gl_field_atlas *a, int t, unsigned seed_stack, int layer, const int footprint[4])
{
    if (box_empty(footprint) || t >= a->tiles)
        return;
    const halo_glfuncs *f = halo_gl_functions(halo_gl_frame_runtime(a->frame));
    atlas_image *seed = &a->images[a->seed];
    int x = (t % a->columns) * a->width, y = (t / a->columns) * a->height;
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, a->framebuffer);
    f->FramebufferTextureLayer(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, seed_stack, 0, layer);
    f->ReadBuffer(GL_COLOR_ATTACHMENT0);
    /* where the frame reads its images back (llvmpipe: halo_gl_desc.readback), the seeds'
     * nonzero box, as the per-segment generations take it (gl/frame.c) */
    int box[4] = {footprint[0], footprint[1], footprint[2], footprint[3]};
    GLenum format, type;
    halo_gl_image_upload_format(seed->internal_format, &format, &type);
    int channels = format == GL_RED ? 1 : format == GL_RG ? 2 : 4;
    halo_gl_frame_nonzero_box(a->frame, channels, a->width, a->height, box);
    if (box_empty(box)) {
        f->FramebufferTextureLayer(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, 0, 0, 0);
        return;
    }
    GLint texture = 0;
    f->GetIntegerv(GL_TEXTURE_BINDING_2D, &texture);
    f->BindTexture(GL_TEXTURE_2D, seed->texture[seed->current]);
    f->CopyTexSubImage2D(GL_TEXTURE_2D, 0, x + box[0], y + box[1], box[0], box[1], box[2] - box[0], box[3] - box[1]);
    f->BindTexture(GL_TEXTURE_2D, (GLuint)texture);
    f->FramebufferTextureLayer(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, 0, 0, 0);
    memcpy(seed->support[seed->current][t], box, 4 * sizeof(int));
}

/* Where repetition rep of pass can write a nonzero pixel of tile t: its inputs' support
 * grown by the pass's reach, within the tile (gl/frame.c: pass_reach_box). */
static void atlas_reach(const halo_gl_field_atlas *a, const atlas_pass *pass, int rep, int t, int box[4])
{
    int in[4] = {0, 0, 0, 0};
    for (int k = 0; k < pass->info->input_count; ++k) {
        const atlas_image *im =
            &a->images[halo_gl_pass_input(pass->inputs[k], rep, pass->start, pass->first, pass->output)];
        box_union(in, im->support[im->current][t]);
    }
    int r = halo_pass_reach(pass->info, rep);
    memset(box, 0, 4 * sizeof *box);
    if (box_empty(in))
        return;
    box[0] = in[0] - r < 0 ? 0 : in[0] - r;
    box[1] = in[1] - r < 0 ? 0 : in[1] - r;
    box[2] = in[2] + r > a->width ? a->width : in[2] + r;
    box[3] = in[3] + r > a->height ? a->height : in[3] + r;
}

/* One draw of the bound pass into out's texture `to`, over a->boxes[t] of each tile t in
 * [first, end) and where that texture held a nonzero (it becomes the pass's 0); the boxes
 * become its support. 1 when it drew. */
static int atlas_draw(halo_gl_field_atlas *a, atlas_image *out, int first, int end, int to)
{
    const halo_glfuncs *f = halo_gl_functions(halo_gl_frame_runtime(a->frame));
    float sx = 2.0f / (float)(a->columns * a->width), sy = 2.0f / (float)(a->rows * a->height);
    size_t n = 0;
    int(*target)[4] = out->support[to];
    for (int t = first; t < end; ++t) {
        int write[4];
        memcpy(write, a->boxes[t], sizeof write);
        box_union(write, target[t]);
        memcpy(target[t], a->boxes[t], sizeof write);
        if (box_empty(write))
            continue;
        float x0 = (float)((t % a->columns) * a->width + write[0]) * sx - 1.0f;
        float x1 = (float)((t % a->columns) * a->width + write[2]) * sx - 1.0f;
        float y0 = (float)((t / a->columns) * a->height + write[1]) * sy - 1.0f;
        float y1 = (float)((t / a->columns) * a->height + write[3]) * sy - 1.0f;
        const float quad[12] = {x0, y0, x1, y0, x1, y1, x0, y0, x1, y1, x0, y1};
        memcpy(a->vertices + n, quad, sizeof quad);
        n += 12;
    }
    if (n > 0) {
        f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, out->texture[to], 0);
        f->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(n * sizeof *a->vertices), a->vertices, GL_STREAM_DRAW);
        f->DrawArrays(GL_TRIANGLES, 0, (GLsizei)(n / 2));
    }
    return n > 0;
}

/* One draw of the bound pass over every tile, into out's other texture (its one texture
 * where it has one, which the pass does not read), which becomes out's current. */
static int atlas_draw_all(halo_gl_field_atlas *a, atlas_image *out, int tiles)
{
    int to = out->count == 2 ? 1 - out->current : 0, drew = atlas_draw(a, out, 0, tiles, to);
    out->current = to;
    out->alternate = 0;
    return drew;
}

/* A running pass (running=associative: O_t = O_(t-1) op I_t, op associative with identity
 * 0) over the tiles. On a GPU, an inclusive prefix scan (Hillis and Steele): step j
 * combines each tile with the tile 2^j before it, ceil(log2(tiles)) draws (at least one,
 * which gives O_0 = 0 op I_0); the first step reads input 0's tiles, the others the
 * output's. Where the frame reads back (a software renderer, whose cost is the pixels, not
 * the draws: the scan computes each tile log2(tiles) times), a tile a draw in order, each
 * from the tile before in the other texture: tile t ends in texture t % 2 (alternate). */
static long atlas_running(halo_gl_field_atlas *a, atlas_pass *pass, int tiles)
{
    const halo_glfuncs *f = halo_gl_functions(halo_gl_frame_runtime(a->frame));
    atlas_image *out = &a->images[pass->output];
    const atlas_image *in = &a->images[pass->inputs[0]];
    f->Uniform1i(pass->columns_location, a->columns);
    halo_gl_pass_repetition(f, pass->index_location, pass->count_location, 1, 1);
    long draws = 0;
    if (halo_gl_frame_reads_back(a->frame)) {
        f->Uniform1i(pass->back_location, 1);
        f->ActiveTexture(GL_TEXTURE0);
        f->BindTexture(GL_TEXTURE_2D, in->texture[in->current]);
        for (int t = 0; t < tiles; ++t) {
            int to = t % 2;
            f->ActiveTexture(GL_TEXTURE1);
            f->BindTexture(GL_TEXTURE_2D, out->texture[1 - to]); /* tile t - 1 (none for t = 0) */
            memcpy(a->boxes[t], in->support[in->current][t], sizeof a->boxes[t]);
            if (t > 0)
                box_union(a->boxes[t], out->support[1 - to][t - 1]);
            draws += atlas_draw(a, out, t, t + 1, to);
        }
        out->alternate = 1;
        return draws;
    }
    for (int back = 1;; back *= 2) {
        for (int i = 0; i < 2; ++i) {
            f->ActiveTexture(GL_TEXTURE0 + (GLenum)i);
            f->BindTexture(GL_TEXTURE_2D, in->texture[in->current]);
        }
        f->Uniform1i(pass->back_location, back);
        for (int t = 0; t < tiles; ++t) {
            memcpy(a->boxes[t], in->support[in->current][t], sizeof a->boxes[t]);
            if (t >= back)
                box_union(a->boxes[t], in->support[in->current][t - back]);
        }
        draws += atlas_draw_all(a, out, tiles);
        in = out;
        if (back >= tiles - back) /* 2 back tiles combined: every tile holds its whole prefix */
            break;
    }
    return draws;
}

void halo_gl_field_atlas_generate(halo_gl_field_atlas *a, int tiles)
{
    halo_gl *gl = halo_gl_frame_runtime(a->frame);
    const halo_glfuncs *f = halo_gl_functions(gl);
    const halo_program *p = halo_gl_frame_program(a->frame);
    tiles = tiles < a->tiles ? tiles : a->tiles; /* (the vertices and boxes of a->tiles: atlas_allocate) */
    /* the host's: the buffer binding and the 2D textures of the units the passes bind (the
     * caller keeps the rest, field.c: field_save) */
    GLint array_buffer = 0, active = GL_TEXTURE0, textures[HALO_MAX_PASS_INPUTS];
    f->GetIntegerv(GL_ARRAY_BUFFER_BINDING, &array_buffer);
    f->GetIntegerv(GL_ACTIVE_TEXTURE, &active);
    for (int i = 0; i < HALO_MAX_PASS_INPUTS; ++i) {
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)i);
        f->GetIntegerv(GL_TEXTURE_BINDING_2D, &textures[i]);
    }
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, a->framebuffer);
    GLenum buffer = GL_COLOR_ATTACHMENT0;
    f->DrawBuffers(1, &buffer);
    f->Viewport(0, 0, a->columns * a->width, a->rows * a->height);
    f->BindVertexArray(a->vertex_array);
    f->BindBuffer(GL_ARRAY_BUFFER, a->buffer);
    f->EnableVertexAttribArray(0);
    f->VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, NULL);
    halo_gl_fetch_binding counting;
    halo_gl_frame_fetches_begin(a->frame, &counting);
    long draws = 0;
    for (int k = 0; k < a->pass_count; ++k) {
        atlas_pass *pass = &a->passes[k];
        f->UseProgram(pass->program);
        halo_gl_program_upload(gl, p, pass->program);
        f->Uniform2i(pass->tile_location, a->width, a->height);
        if (pass->info->running) {
            draws += atlas_running(a, pass, tiles);
            continue;
        }
        for (int rep = pass->start; rep <= pass->repeat; ++rep) {
            for (int i = 0; i < pass->info->input_count; ++i) {
                const atlas_image *in =
                    &a->images[halo_gl_pass_input(pass->inputs[i], rep, pass->start, pass->first, pass->output)];
                f->ActiveTexture(GL_TEXTURE0 + (GLenum)i);
                f->BindTexture(GL_TEXTURE_2D, in->texture[in->current]);
            }
            halo_gl_pass_repetition(f, pass->index_location, pass->count_location, rep, pass->repeat);
            /* a rectangle a tile: where the pass can write a nonzero */
            for (int t = 0; t < tiles; ++t)
                atlas_reach(a, pass, rep, t, a->boxes[t]);
            draws += atlas_draw_all(a, &a->images[pass->output], tiles);
        }
    }
    f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
    f->DisableVertexAttribArray(0);
    f->BindBuffer(GL_ARRAY_BUFFER, (GLuint)array_buffer);
    for (int i = 0; i < HALO_MAX_PASS_INPUTS; ++i) {
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)i);
        f->BindTexture(GL_TEXTURE_2D, (GLuint)textures[i]);
    }
    f->ActiveTexture((GLenum)active);
    halo_gl_frame_fetches_end(a->frame, &counting);
    halo_gl_frame_count_pass_draws(a->frame, draws);
}

unsigned halo_gl_field_atlas_tile(const halo_gl_field_atlas *a, const char *name, int t, int origin[2], int box[4])
{
    for (int i = 0; i < a->image_count; ++i) {
        const atlas_image *im = &a->images[i];
        if (strcmp(im->name, name) || t >= a->tiles)
            continue;
        origin[0] = (t % a->columns) * a->width;
        origin[1] = (t / a->columns) * a->height;
        int k = im->alternate ? t % 2 : im->current;
        memcpy(box, im->support[k][t], 4 * sizeof *box);
        return im->texture[k];
    }
    return 0;
}
