/* Host contract 3's generations in a constant number of draws (field_atlas.c): the images
 * of the generation passes as atlases of one tile per depth segment, each pass one draw
 * over every tile. Internal; field.c drives it. */
#ifndef HALO_GL_FIELD_ATLAS_H
#define HALO_GL_FIELD_ATLAS_H

#include "gl/frame.h"

typedef struct halo_gl_field_atlas halo_gl_field_atlas;

/* An atlas of at least `tiles` tiles for the frame's generation passes, or NULL without a
 * diagnostic where they cannot run on one. *unsuited 1: never, for this program (a pass
 * that reads an image of the generation before, but for a running=associative pass's own
 * output, which no other pass may write or read and which is not reset each generation; a
 * pass with no declared reach; images of different sizes, or not cleared to 0; no tiled
 * variant of a pass); 0: not at this size (an atlas over the context's
 * largest texture or viewport, or over max_bytes). A given atlas that fits is kept (or
 * grown); one that cannot grow is destroyed. Its textures are cleared when made: the
 * caller has the scissor test off and every colour written (field.c: field_save). */
halo_gl_field_atlas *halo_gl_field_atlas_reserve(halo_gl_frame *fr, halo_gl_field_atlas *atlas, int tiles,
                                                 size_t max_bytes, int *unsuited);
void halo_gl_field_atlas_destroy(const halo_glfuncs *f, halo_gl_field_atlas *atlas);
/* The bytes of the atlas's textures (0 for NULL). */
size_t halo_gl_field_atlas_bytes(const halo_gl_field_atlas *atlas);
/* A new frame's seeds: every tile of the seed image 0. */
void halo_gl_field_atlas_begin(halo_gl_field_atlas *atlas);
/* Tile t's seeds: footprint (x0 y0 x1 y1, the tile's pixels) of layer `layer` of seed_stack
 * (an array texture of the seed image's format), the rest of the tile 0; where the frame
 * reads back (halo_gl_frame_nonzero_box), only the nonzero box is taken. */
void halo_gl_field_atlas_seed(halo_gl_field_atlas *atlas, int t, unsigned seed_stack, int layer,
                              const int footprint[4]);
/* Every generation pass, one draw each (a repetition each), over tiles [0, tiles); a
 * running=associative pass (the occlusion image's running maximum) as a prefix scan over
 * the tiles, ceil(log2(tiles)) draws (at least 1), or a tile a draw where the frame reads
 * back (halo_gl_frame_reads_back: a software renderer). */
void halo_gl_field_atlas_generate(halo_gl_field_atlas *atlas, int tiles);
/* Image `name` after the generations: its atlas texture (0 if the atlas has no such
 * image), the tile's origin in it, and where tile t can be nonzero (its pixels). */
unsigned halo_gl_field_atlas_tile(const halo_gl_field_atlas *atlas, const char *name, int t, int origin[2], int box[4]);

#endif
