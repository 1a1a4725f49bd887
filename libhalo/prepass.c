/* Host contract 3 in the linker (docs/host-contract.md, "Host contract 3"): a program
 * linked with halo_link_desc.one_draw leaves the stages whose outputs feed generation
 * passes (halo_seed's seeds) to libhalo's own march, which the linker links here from the
 * same scene (the program's prepass); the GL runtime (gl/field.c) runs that march and the
 * generation passes for every depth segment before the host draws, and the host's samples
 * read their segment's layer of the result.
 *
 * Why this is the same algorithm (docs/stages/halo_generate.md): the seed image is reset
 * at every generation and the field is rebuilt from it, so the field a segment reads
 * depends on the previous segment's seeds alone; the seeds depend on the volume, the view
 * and the seed parameters, not on the host's classification or compositing. Only the
 * occlusion image carries over (a running maximum), which the runtime keeps by running
 * the segments front to back. */
#include "internal.h"
#include "diag.h"
#include "glsl_lex.h"

#include <stdlib.h>
#include <string.h>

/* The march: for each pixel, the samples where its ray meets planes [first, end) of the
 * frame's segment planes (phi = planes.x + k planes.y, the slice host's), inside the
 * volume's box; value from the host's volume, gradient from a gradient texture (the
 * host's, or the runtime's central differences of the volume: per voxel step, as host
 * contract 2 derives it), view and depth derived. Written in the common subset of GLSL
 * 330 and ES 300.
 *
 * One segment a draw (march_range), or, compiled with HALO_MARCH_BATCH (gl/field.c, where
 * halo_prepass_batchable and the context has 8 draw buffers), eight segments a draw
 * (march_ranges): a fragment's ray is set up once for the eight, and segment b's seeds go
 * to draw buffer 0 (b = 0), b + 1 (b = 1 .. 6) or 1 (b = 7, through halo_finish and the
 * linked seed output, which the linker places at 1 after march_color), each a layer of the
 * runtime's seed stack. Either way the ray is clipped to the box first, and an empty
 * brick's planes are stepped over where the ray goes on to larger planes (the samples
 * there are skipped by the test anyway). The samples and their order are the same. */
static const char march_host[] =
    "#version 330 core\n"
    "// libhalo's march for host contract 3 (libhalo/gl/field.c): the seeds of depth\n"
    "// segments, from samples on their planes.\n"
    "#pragma halo declarations\n"
    "uniform highp sampler3D march_volume;\n"
    "uniform highp sampler3D march_gradient;         // the contract's gradient (per voxel step)\n"
    "uniform highp sampler3D march_bricks;   // max |gradient| that a sample in each 4^3-voxel brick can see\n"
    "uniform float march_skip;               // a sample whose brick's max is <= this has no seed (> 0)\n"
    "uniform mat4 march_inverse_view_projection; // clip space -> volume texture space\n"
    "uniform vec2 march_viewport;                // the frame's size in pixels\n"
    "uniform float march_scale;                  // the seed image is 1/march_scale of the frame per side\n"
    "uniform vec3 march_box_min;                 // where this march samples: the volume's box or a piece's\n"
    "uniform vec3 march_box_max;\n"
    "uniform vec3 march_piece_min;               // the part of the box that the volume texture covers\n"
    "uniform vec3 march_piece_scale;             // 1 / its size (the whole volume: 0 and 1)\n"
    "uniform vec4 march_plane;                  // phi(P) = dot(xyz, P) + w: the segments' axis\n"
    "uniform vec2 march_planes;                  // phi of plane 0, the planes' spacing\n"
    "#ifdef HALO_MARCH_BATCH\n"
    "uniform ivec2 march_ranges[8];              // segment b's planes [x, y) ([0, 0): none)\n"
    "// (through a macro: the linker places the seeds after the outputs it sees, march_color's)\n"
    "#define MARCH_OUT(n) layout(location = n) out vec4\n"
    "MARCH_OUT(0) march_batch_0;\n"
    "MARCH_OUT(2) march_batch_1;\n"
    "MARCH_OUT(3) march_batch_2;\n"
    "MARCH_OUT(4) march_batch_3;\n"
    "MARCH_OUT(5) march_batch_4;\n"
    "MARCH_OUT(6) march_batch_5;\n"
    "MARCH_OUT(7) march_batch_6;\n"
    "#else\n"
    "uniform ivec2 march_range;                  // this segment's planes [x, y)\n"
    "layout(location = 0) out vec4 march_color;  // not drawn (draw buffer 0 is GL_NONE)\n"
    "#endif\n"
    "#ifdef HALO_LINKED\n"
    "// The planes where the ray origin + t direction, t in [0, 1], can be inside the box, with\n"
    "// a plane to spare at each end (march_segment's tests decide each sample): [x, y). The\n"
    "// box is widened by the rounding of a sample's position, origin + t direction, so that\n"
    "// no plane whose rounded position is inside is left out.\n"
    "ivec2 march_clip(vec3 origin, vec3 direction, float phi_origin, float phi_rate)\n"
    "{\n"
    "    float t0 = 0.0, t1 = 1.0;\n"
    "    for (int a = 0; a < 3; ++a) {\n"
    "        float widen = 1e-6 * (abs(origin[a]) + abs(direction[a]) +\n"
    "                              max(abs(march_box_min[a]), abs(march_box_max[a])));\n"
    "        float low = march_box_min[a] - widen, high = march_box_max[a] + widen;\n"
    "        if (abs(direction[a]) < 1e-20) {\n"
    "            if (origin[a] < low || origin[a] > high)\n"
    "                return ivec2(0);\n"
    "            continue;\n"
    "        }\n"
    "        float ta = (low - origin[a]) / direction[a], tb = (high - origin[a]) / direction[a];\n"
    "        t0 = max(t0, min(ta, tb));\n"
    "        t1 = min(t1, max(ta, tb));\n"
    "    }\n"
    "    float slack = 1e-4 * max(1.0, abs(t1));\n"
    "    if (!(t0 <= t1 + slack))\n"
    "        return ivec2(0);\n"
    "    float ka = (phi_origin + (t0 - slack) * phi_rate - march_planes.x) / march_planes.y;\n"
    "    float kb = (phi_origin + (t1 + slack) * phi_rate - march_planes.x) / march_planes.y;\n"
    "    vec2 k = clamp(vec2(min(ka, kb), max(ka, kb)), vec2(-1e9), vec2(1e9));\n"
    "    return ivec2(int(floor(k.x)) - 1, int(ceil(k.y)) + 2);\n"
    "}\n"
    "// The samples of planes [first, end) on the ray origin + t direction, t in [0, 1].\n"
    "void march_segment(int first, int end, vec3 origin, vec3 direction, float phi_origin, float phi_rate, vec2 pixel)\n"
    "{\n"
    "    ivec3 bricks = textureSize(march_bricks, 0);\n"
    "    vec3 voxels = vec3(textureSize(march_volume, 0));\n"
    "    vec3 dT = direction * march_piece_scale; // the ray's step in the volume texture's coordinates\n"
    "    for (int k = first; k < end;) {\n"
    "        float t = (march_planes.x + float(k) * march_planes.y - phi_origin) / phi_rate;\n"
    "        int next = k + 1;\n"
    "        vec3 P = origin + t * direction;\n"
    "        vec3 T = (P - march_piece_min) * march_piece_scale; // the volume texture's coordinates\n"
    "        ivec3 brick = clamp(ivec3(T * voxels) / 4, ivec3(0), bricks - 1);\n"
    "        if (t < 0.0 || t > 1.0) {\n"
    "            // before the near plane or past the far one: no sample of the host's\n"
    "        } else if (any(lessThan(P, march_box_min)) || any(greaterThan(P, march_box_max))) {\n"
    "        } else if (texelFetch(march_bricks, brick, 0).r <= march_skip) {\n"
    "            // empty space: no seed can be above the skip bound in this brick. Where the ray\n"
    "            // goes on to larger planes (phi_rate > 0), on to the plane before the last one\n"
    "            // that is surely still in the brick: its exit measured from this sample's own T,\n"
    "            // the brick shrunk by far more than a position's rounding (the skipped planes'\n"
    "            // samples would all be skipped; the planes from there on are tested again)\n"
    "            vec3 low = vec3(brick * 4) / voxels + 1e-5, high = vec3(brick * 4 + 4) / voxels - 1e-5;\n"
    "            float leave = 2.0;\n"
    "            for (int a = 0; a < 3; ++a)\n"
    "                if (abs(dT[a]) > 1e-20)\n"
    "                    leave = min(leave, t + max(0.0, ((dT[a] > 0.0 ? high[a] : low[a]) - T[a]) / dT[a]));\n"
    "            float plane = (phi_origin + leave * phi_rate - march_planes.x) / march_planes.y;\n"
    "            if (phi_rate > 0.0 && plane > float(k) + 2.0 && plane < 1e9)\n"
    "                next = int(floor(plane)) - 1;\n"
    "        } else {\n"
    "            halo_sample s = halo_make_sample(P, texture(march_volume, T).r, texture(march_gradient, T).rgb,\n"
    "                                             halo_view_at(P), halo_depth_at(P), pixel, vec3(0.0), 0.0);\n"
    "            halo_apply(s);\n"
    "        }\n"
    "        k = next;\n"
    "    }\n"
    "}\n"
    "#endif\n"
    "void main()\n"
    "{\n"
    "    vec2 pixel = gl_FragCoord.xy * march_scale; // the seed pixel's centre in the frame's pixels\n"
    "    vec2 ndc = pixel / march_viewport * 2.0 - 1.0;\n"
    "    vec4 near_point = march_inverse_view_projection * vec4(ndc, -1.0, 1.0);\n"
    "    vec4 far_point = march_inverse_view_projection * vec4(ndc, 1.0, 1.0);\n"
    "    vec3 origin = near_point.xyz / near_point.w;\n"
    "    vec3 direction = far_point.xyz / far_point.w - origin;\n"
    "    float phi_origin = dot(march_plane.xyz, origin) + march_plane.w;\n"
    "    float phi_rate = dot(march_plane.xyz, direction);\n"
    "    bool crosses = abs(phi_rate) > 1e-30;\n"
    "#ifdef HALO_LINKED\n"
    "    ivec2 inside = crosses ? march_clip(origin, direction, phi_origin, phi_rate) : ivec2(0);\n"
    "#endif\n"
    "#if defined(HALO_LINKED) && defined(HALO_MARCH_BATCH)\n"
    "    for (int b = 0; b < 7; ++b) {\n"
    "        if (crosses)\n"
    "            march_segment(max(march_ranges[b].x, inside.x), min(march_ranges[b].y, inside.y), origin, direction,\n"
    "                          phi_origin, phi_rate, pixel);\n"
    "        vec4 seeds = halo_march_take(); // and the accumulators reset for the next segment\n"
    "        if (b == 0) march_batch_0 = seeds;\n"
    "        else if (b == 1) march_batch_1 = seeds;\n"
    "        else if (b == 2) march_batch_2 = seeds;\n"
    "        else if (b == 3) march_batch_3 = seeds;\n"
    "        else if (b == 4) march_batch_4 = seeds;\n"
    "        else if (b == 5) march_batch_5 = seeds;\n"
    "        else march_batch_6 = seeds;\n"
    "    }\n"
    "    if (crosses)\n"
    "        march_segment(max(march_ranges[7].x, inside.x), min(march_ranges[7].y, inside.y), origin, direction,\n"
    "                      phi_origin, phi_rate, pixel);\n"
    "    halo_finish();\n"
    "#elif defined(HALO_LINKED)\n"
    "    if (crosses)\n"
    "        march_segment(max(march_range.x, inside.x), min(march_range.y, inside.y), origin, direction, phi_origin,\n"
    "                      phi_rate, pixel);\n"
    "    halo_finish();\n"
    "#endif\n"
    "#ifndef HALO_MARCH_BATCH\n"
    "    march_color = vec4(0.0);\n"
    "#endif\n"
    "}\n";

const char halo_march_file[] = "(libhalo's march, host contract 3)";

/* Does a generation pass (at=generate) of a linked stage read image? */
static int generation_reads(const halo_program *p, const char *image)
{
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        for (size_t k = 0; k < m->pass_count; k++)
            for (int i = 0; i < m->passes[k].input_count && !m->passes[k].at; i++)
                if (!strcmp(m->passes[k].inputs[i], image))
                    return 1;
    }
    return 0;
}

static int provides_needed(const halo_module *t, const halo_module *m)
{
    for (size_t r = 0; r < t->provides_count; r++)
        if (halo_name_list_has(&m->needs, t->provides[r].name))
            return 1;
    return 0;
}

int halo_prepass_mark(halo_program *p)
{
    int any = 0;
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        int all = m->hook == HALO_HOOK_SAMPLE && m->output_count > 0;
        for (size_t o = 0; o < m->output_count && all; o++)
            all = generation_reads(p, m->outputs[o].name);
        p->stages[s].prepass = all ? 2 : 0;
        any |= all;
    }
    /* what the march's stages need, transitively (halo_seed: the normal, from gradient) */
    for (int changed = any; changed;) {
        changed = 0;
        for (size_t t = 0; t < p->stage_count; t++) {
            if (p->stages[t].prepass || p->stages[t].module->hook != HALO_HOOK_SAMPLE)
                continue;
            for (size_t s = 0; s < p->stage_count && !p->stages[t].prepass; s++)
                if (p->stages[s].prepass && provides_needed(p->stages[t].module, p->stages[s].module))
                    p->stages[t].prepass = changed = 1;
        }
    }
    return any;
}

int halo_prepass_image(const halo_program *p, const char *image)
{
    if (!p->one_draw || halo_program_image_unread(p, image))
        return 0; /* an unread image (read as zero) needs no stack */
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        for (size_t k = 0; k < m->pass_count; k++)
            if (!m->passes[k].at && m->passes[k].output && !strcmp(m->passes[k].output, image))
                return 1;
    }
    return 0;
}

void halo_prepass_drop_outputs(halo_program *p, int seeds)
{
    size_t kept = 0;
    for (size_t o = 0; o < p->output_count; o++)
        if (generation_reads(p, p->outputs[o].image) != seeds)
            p->outputs[kept++] = p->outputs[o];
    p->output_count = kept;
}

halo_link_desc halo_prepass_desc(const halo_program *p, const halo_link_desc *desc)
{
    return (halo_link_desc){
        .library = desc->library,
        .scene = desc->scene,
        .host_source = march_host,
        .host_file = halo_march_file,
        .target = p->target == HALO_TARGET_ES300 ? HALO_TARGET_ES300 : HALO_TARGET_GLSL330,
        .all_live = desc->all_live,
        .image_precision = desc->image_precision,
        .image_scale = desc->image_scale,
        .one_draw = 1, /* a march: no segments, no HOST_SINGLE_PASS */
    };
}

int halo_prepass_host_uniforms_known(const halo_program *march, halo_diagnostics *diag)
{
    /* gl/field.c derives these from the camera; nothing else can reach the march. Only the
     * stages the march runs count (the others are linked but not called there). */
    for (size_t s = 0; s < march->stage_count; s++) {
        const halo_module *m = march->stages[s].module;
        for (size_t i = 0; i < m->host_uniform_count && march->stages[s].prepass; i++) {
            const char *name = m->host_uniforms[i].name;
            if (strcmp(name, "screen_right") && strcmp(name, "screen_up")) {
                halo_diag_error(diag, USAGE, "", 0, 0,
                                "halo_link: one_draw (host contract 3): the seeding stage %s reads the host uniform "
                                "'halo_host_%s', which libhalo's march cannot get from the host",
                                m->name, name);
                return 0;
            }
        }
    }
    return 1;
}

int halo_prepass_batchable(const halo_program *march)
{
    /* one output, at location 1 (prepass.c's batch writes the others around it) */
    if (!march || !march->prepass_only || march->output_count != 1 || march->outputs[0].location != 1)
        return 0;
    /* the batch copies a segment's seeds over the seed image where one segment a draw
     * blended them onto it: the same only when the image starts every generation from the
     * blend's identity */
    const halo_output_info *out = &march->outputs[0];
    const halo_image_info *im = halo_program_image_named((halo_program *)march, out->image);
    double identity = out->blend == HALO_BLEND_MIN ? 1.0 : 0.0;
    if (!im || im->reset != HALO_RESET_GENERATION || im->clear != identity || out->blend == HALO_BLEND_FIRST)
        return 0;
    /* a discard would drop the pixel's seeds of all eight segments, not one */
    for (size_t s = 0; s < march->stage_count; s++) {
        const halo_module *m = march->stages[s].module;
        for (int i = 0; march->stages[s].prepass && i < m->line_count; i++) {
            halo_token_list toks = {0};
            if (halo_lex(m->lines[i], &toks))
                return 0;
            int found = 0;
            for (size_t t = 0; t < toks.count && !found; t++)
                found = halo_token_is(m->lines[i], &toks.items[t], "discard");
            halo_token_list_free(&toks);
            if (found)
                return 0;
        }
    }
    return 1;
}
