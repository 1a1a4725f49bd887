/* libhalo/prepass.c: host contract 3's march, linked from a one_draw program's scene, and
 * whether it may draw eight depth segments at once (halo_prepass_batchable: gl/field.c
 * copies a batch's seeds over the seed image where one segment a draw blended them, the
 * same only for an image that every generation starts from the blend's identity and a
 * march without discard). No GL. */
#include "link_fixture.h"

static const char one_draw_scene[] = "{\"stages\":[\"halo_seed\",\"halo_generate\",\"halo_map\"]}";

/* libhalo's march of the scene's one_draw program, linked into the fixture's host; NULL
 * (and a message) on failure. The caller destroys the program, not the march. */
static halo_program *one_draw_program(void)
{
    halo_scene *scene = scene_of(one_draw_scene);
    halo_diagnostics_clear(diags);
    halo_program *p = halo_link(
        &(halo_link_desc){
            .library = library, .scene = scene, .host_source = host_source, .host_file = "test.frag", .one_draw = 1},
        diags);
    halo_scene_destroy(scene);
    if (!p || !p->prepass) {
        check_print_diags(diags);
        halo_program_destroy(p);
        return NULL;
    }
    return p;
}

static int test_batchable(void)
{
    halo_program *p = one_draw_program();
    CHECK(p != NULL);
    CHECK(p->prepass->prepass_only);
    /* the reflection hands the march out (its emulation: validate/conform_segment.c) */
    CHECK(halo_program_reflection(p).march == p->prepass);
    CHECK(halo_program_reflection(p->prepass).march == NULL);
    halo_scene *plain_scene = scene_of(one_draw_scene);
    halo_program *plain = halo_link(
        &(halo_link_desc){
            .library = library, .scene = plain_scene, .host_source = host_source, .host_file = "test.frag"},
        diags);
    CHECK(plain != NULL && halo_program_reflection(plain).march == NULL);
    halo_program_destroy(plain);
    halo_scene_destroy(plain_scene);
    CHECK_INT_EQ((int)p->prepass->output_count, 1);
    CHECK_INT_EQ(p->prepass->outputs[0].location, 1);
    CHECK_INT_EQ(halo_prepass_batchable(p->prepass), 1);
    /* the batch's names are in the march's text, and libhalo's march may use them */
    CHECK(strstr(halo_program_source(p->prepass, HALO_PIECE_WHOLE), "vec4 halo_march_take()") != NULL);
    CHECK(strstr(halo_program_source(p->prepass, HALO_PIECE_WHOLE), "#ifdef HALO_MARCH_BATCH") != NULL);
    /* not a march, or none */
    CHECK_INT_EQ(halo_prepass_batchable(p), 0);
    CHECK_INT_EQ(halo_prepass_batchable(NULL), 0);
    halo_program_destroy(p);
    return 0;
}

/* A seeding stage that may discard: one segment a draw. */
static const char discarding_seed[] =
    "#pragma halo module halo_seed\n"
    "#pragma halo summary \"a seeding stage that discards\"\n"
    "#pragma halo hook sample\n"
    "#pragma halo provides seed channels\n"
    "#pragma halo output seed max\n"
    "void apply(inout halo_sample s)\n"
    "{\n"
    "    if (s.value < 0.0)\n"
    "        discard; // the whole fragment: every segment of a batch\n"
    "    s.seed = halo_channels(s.value);\n"
    "}\n";

static int test_discard_not_batchable(void)
{
    CHECK_INT_EQ(halo_library_add(library, "halo_seed.glsl", discarding_seed, HALO_ADD_REPLACE, diags), HALO_OK);
    check_print_diags(diags);
    halo_program *p = one_draw_program();
    CHECK(p != NULL);
    int batchable = halo_prepass_batchable(p->prepass);
    halo_program_destroy(p);
    CHECK_INT_EQ(batchable, 0);
    return 0;
}

int main(void)
{
    link_fixture_setup();
    RUN_TEST(test_batchable);
    RUN_TEST(test_discard_not_batchable);
    return link_fixture_finish();
}
