/* libhalo/host_check.c: the host contract, each broken rule at its file:line:col, a
 * vertex host refusing sample stages, and a MIP host refusing compositing stages. No GL. */
#include "link_fixture.h"

static int check_host_error(const char *host, halo_message_id id, int line, int column)
{
    halo_scene *scene = scene_of("{\"stages\": [\"boundary\"]}");
    halo_program *p = link_with(scene, host, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    if (p) {
        halo_program_destroy(p);
        CHECK_FAIL_AT("host accepted:\n%s", host);
    }
    const halo_diagnostic *g = check_find_diag(diags, id, line);
    if (!g) {
        check_print_diags(diags);
        CHECK_FAIL_AT("no %s at line %d for host:\n%s", halo_message_name(id), line, host);
    }
    CHECK_STR_EQ(g->file, "test.frag");
    if (column)
        CHECK_INT_EQ(g->column, column);
    return 0;
}

/* (g) Hosts that break the contract, reported at the host's line. */
static int test_host_errors(void)
{
    if (check_host_error("#version 330 core\n"
                         "out vec4 c;\n"
                         "void main() { c = vec4(1.0); }\n",
                         HALO_MSG_HOST_MARKER_MISSING, 1, 0))
        return 1;
    if (check_host_error("#version 330 core\n"
                         "#pragma halo declarations\n"
                         "out vec4 c;\n"
                         "#pragma halo declarations\n"
                         "void main() { c = vec4(1.0); }\n",
                         HALO_MSG_HOST_MARKER_DUPLICATE, 4, 0))
        return 1;
    if (check_host_error("#version 330 core\n"
                         "out vec4 c;\n"
                         "void main()\n"
                         "{\n"
                         "#pragma halo declarations\n"
                         "    c = vec4(1.0);\n"
                         "}\n",
                         HALO_MSG_HOST_MARKER_SCOPE, 5, 0))
        return 1;
    if (check_host_error("#version 330 core\n"
                         "#pragma halo declarations\n"
                         "float halo_foo;\n"
                         "out vec4 c;\n"
                         "void main() { c = vec4(halo_foo); }\n",
                         HALO_MSG_HOST_RESERVED_NAME, 3, 7))
        return 1;
    if (check_host_error("#version 330 core\n"
                         "#pragma halo declarations\n"
                         "out vec4 c;\n"
                         "void main() { c = vec4(HALO_SCALE); }\n",
                         HALO_MSG_HOST_RESERVED_NAME, 4, 24))
        return 1;
    /* Each problem is reported: two reserved names and a second marker. */
    halo_program *p = link_with(NULL,
                                "#pragma halo declarations\n"
                                "float halo_a;\n"
                                "float halo_b;\n"
                                "#pragma halo declarations\n"
                                "void main() {}\n",
                                HALO_TARGET_DEFAULT, 0);
    CHECK(p == NULL);
    CHECK_DIAG_LINE(diags, HALO_MSG_HOST_RESERVED_NAME, 2);
    CHECK_DIAG_LINE(diags, HALO_MSG_HOST_RESERVED_NAME, 3);
    CHECK_DIAG_LINE(diags, HALO_MSG_HOST_MARKER_DUPLICATE, 4);
    /* The contract's own names are the host's to use. */
    p = link_with(NULL,
                  "#pragma halo declarations\n"
                  "out vec4 c;\n"
                  "void main() {\n"
                  "#if defined(HALO_LINKED) && HALO_CONTRACT_VERSION == 1\n"
                  "    halo_sample s = halo_make_sample(vec3(0.0), 0.0, vec3(0.0), vec3(0.0, 0.0, 1.0), 0.0,\n"
                  "                                     gl_FragCoord.xy, vec3(1.0), 1.0);\n"
                  "    halo_apply(s);\n"
                  "    c = vec4(s.color, s.opacity);\n"
                  "#endif\n"
                  "}\n",
                  HALO_TARGET_DEFAULT, 0);
    if (!p)
        check_print_diags(diags);
    CHECK(p != NULL);
    halo_program_destroy(p);
    /* A library and a host are required. */
    halo_diagnostics_clear(diags);
    CHECK(halo_link(&(halo_link_desc){.library = library}, diags) == NULL);
    CHECK_DIAG(diags, HALO_MSG_USAGE);
    halo_diagnostics_clear(diags);
    CHECK(halo_link(&(halo_link_desc){.host_source = host_source}, diags) == NULL);
    CHECK_DIAG(diags, HALO_MSG_USAGE);
    return 0;
}


/* Vertex hosts take no sample stages. */
static int test_hook_mismatch(void)
{
    halo_scene *scene = scene_of("{\"stages\": [\"boundary\"]}");
    halo_diagnostics_clear(diags);
    halo_program *p = halo_link(&(halo_link_desc){.library = library,
                                                  .scene = scene,
                                                  .host_source = "#pragma halo declarations\nvoid main() {}\n",
                                                  .kind = HALO_SHADER_VERTEX},
                                diags);
    halo_scene_destroy(scene);
    CHECK(p == NULL);
    CHECK_DIAG(diags, HALO_MSG_LINK_HOOK_MISMATCH);
    return 0;
}


/* Host contract 2: a host that declares `#pragma halo compositing mip` composites no
 * samples, so any stage is refused at the pragma (HOST_COMPOSITING); with none it links.
 * A host whose gradient is derived from its sampler (`#pragma halo volume`) links with
 * image passes: the pass programs do not get the derived gradient's body (they have no
 * host sampler). */
static int test_compositing_mip(void)
{
    static const char mip[] =
        "#version 330 core\n"
        "#pragma halo declarations\n"
        "#pragma halo compositing mip\n"
        "out vec4 c;\n"
        "void main() { c = vec4(1.0);\n"
        "#ifdef HALO_LINKED\n"
        "    halo_finish();\n"
        "#endif\n"
        "}\n";
    halo_scene *scene = scene_of("{\"stages\": [\"boundary\", \"silhouette\"]}");
    halo_program *p = link_with(scene, mip, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    CHECK(p == NULL);
    const halo_diagnostic *g = check_find_diag(diags, HALO_MSG_HOST_COMPOSITING, 3);
    CHECK(g != NULL);
    CHECK(strstr(g->text, "boundary") && strstr(g->text, "silhouette"));
    scene = scene_of("{\"stages\": []}");
    p = link_with(scene, mip, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    CHECK(p != NULL && halo_validate(&(halo_validate_desc){.program = p}, diags) == HALO_OK);
    halo_program_destroy(p);
    if (check_host_error("#version 330 core\n#pragma halo declarations\n#pragma halo compositing max\n"
                         "out vec4 c;\nvoid main() { c = vec4(1.0); }\n",
                         HALO_MSG_ANNOTATION_SYNTAX, 3, 0))
        return 1;
    static const char volume_host[] =
        "#version 330 core\n"
        "#pragma halo declarations\n"
        "#pragma halo volume volume_texture\n"
        "uniform sampler3D volume_texture;\n"
        "in vec3 P;\n"
        "layout(location = 0) out vec4 c;\n"
        "void main() {\n"
        "    vec4 a = vec4(0.0);\n"
        "    int first = 0, end = 8;\n"
        "    halo_segment_begin(P, vec3(0.0, 0.0, 1.0), 0.0, 0.1, first, end, a);\n"
        "    for (int i = first; i < end; ++i) {\n"
        "        halo_sample s = halo_make_sample(P, texture(volume_texture, P).r, vec3(1.0), 0.1);\n"
        "        halo_apply(s);\n"
        "        a += (1.0 - a.a) * vec4(s.color * s.opacity, s.opacity);\n"
        "    }\n"
        "    halo_segment_end(a, false);\n"
        "    halo_finish();\n"
        "    c = a;\n"
        "}\n";
    scene = scene_of("{\"stages\": [\"halo_seed\", \"halo_generate\", \"halo_map\"]}");
    p = link_with(scene, volume_host, HALO_TARGET_DEFAULT, 0);
    halo_scene_destroy(scene);
    if (!p || halo_validate(&(halo_validate_desc){.program = p}, diags) != HALO_OK) {
        check_print_diags(diags);
        halo_program_destroy(p);
        CHECK_FAIL_AT("a '#pragma halo volume' host with image passes does not link and validate");
    }
    CHECK(halo_program_reflection(p).segment_location > 0);
    halo_program_destroy(p);
    return 0;
}


int main(void)
{
    link_fixture_setup();
    RUN_TEST(test_host_errors);
    RUN_TEST(test_hook_mismatch);
    RUN_TEST(test_compositing_mip);
    return link_fixture_finish();
}
