/* Host contract 2: segmented ray casting and derived inputs (docs/host-contract.md).
 *
 * A single-pass ray caster marches each ray to its end in one draw, so image passes
 * (volumetric halos) have nowhere to run. The GL runtime draws such a host once per
 * view-aligned depth segment instead (halo_gl_frame_draw); halo_segment_begin clips the
 * host's sample loop to the current segment and restores the ray's state, and
 * halo_segment_end stores it for the next segment. Segment borders are planes of
 * constant distance along the view axis, phi(P) = dot(plane.xyz, P) + plane.w, the
 * same planes the slice host draws.
 *
 * This file writes the GLSL of those functions and of the derived inputs (view
 * direction and depth from the camera, gradient from the host's volume sampler); the
 * linker places it in the declarations block. */
#include "internal.h"
#include "strbuf.h"

#include <stdio.h>
#include <string.h>

/* Does the host's code (comments excluded) use the identifier name? */
int halo_host_uses(const char *host, const char *name)
{
    halo_token_list t;
    if (!host || halo_lex(host, &t))
        return 0;
    int found = 0;
    for (size_t i = 0; i < t.count && !found; i++)
        found = t.items[i].kind == HALO_TOK_IDENT && halo_token_is(host, &t.items[i], name);
    halo_token_list_free(&t);
    return found;
}

/* The camera uniforms the runtime sets (halo_gl_frame_draw, halo_gl_set_camera) and the
 * derived view direction and depth. */
static const char camera_glsl[] =
    "uniform vec4 halo_camera_eye;         // xyz: the eye (w = 1), or towards the viewer (w = 0: orthographic)\n"
    "uniform vec4 halo_camera_plane;       // phi(P) = dot(xyz, P) + w: distance along the view axis\n"
    "uniform vec2 halo_camera_depth_range; // phi at the front and back of the volume's bounding sphere\n"
    "vec3 halo_view_at(vec3 position) {\n"
    "    vec3 v = halo_camera_eye.xyz - position * halo_camera_eye.w;\n"
    "    float length2 = dot(v, v);\n"
    "    return length2 > 1e-30 ? v * inversesqrt(length2) : vec3(0.0);\n"
    "}\n"
    "float halo_depth_at(vec3 position) {\n"
    "    float span = max(halo_camera_depth_range.y - halo_camera_depth_range.x, 1e-30);\n"
    "    float phi = dot(halo_camera_plane.xyz, position) + halo_camera_plane.w;\n"
    "    return clamp((phi - halo_camera_depth_range.x) / span, 0.0, 1.0);\n"
    "}";

/* Segments for real: the state image, the segment's bounds, the index range. */
static const char segment_glsl[] =
    "uniform highp sampler2D halo_segment_state; // the rays' state after the previous segment\n"
    "uniform vec2 halo_segment_bounds;           // samples with bounds.x <= phi < bounds.y are this segment's\n"
    "uniform int halo_segment_flags;             // 1: the first segment, 2: the last\n"
    "%sout vec4 halo_segment_state_out;\n"
    "bool halo_segment_ended = false;\n"
    "// The first sample index at or behind the plane phi = bound (the same expression in\n"
    "// both segments that share the plane, so every sample belongs to exactly one).\n"
    "int halo_segment_index(float bound, float phi0, float dphi, int first, int end) {\n"
    "    return int(clamp(ceil((bound - phi0) / dphi), float(first), float(end)));\n"
    "}\n"
    "void halo_segment_begin(vec3 origin, vec3 direction, float t_first, float t_step,\n"
    "                        inout int first, inout int end, inout vec4 state) {\n"
    "    bool head = (halo_segment_flags & 1) != 0, tail = (halo_segment_flags & 2) != 0;\n"
    "    if (!head) {\n"
    "        vec4 stored = texelFetch(halo_segment_state, ivec2(gl_FragCoord.xy), 0);\n"
    "        halo_segment_ended = stored.a >= 2.0; // an ended ray's opacity is stored + 2\n"
    "        state = vec4(stored.rgb, halo_segment_ended ? stored.a - 2.0 : stored.a);\n"
    "    }\n"
    "    float phi0 = dot(halo_camera_plane.xyz, origin + t_first * direction) + halo_camera_plane.w;\n"
    "    float dphi = dot(halo_camera_plane.xyz, direction) * t_step;\n"
    "    int low = first, high = end;\n"
    "    if (dphi > 0.0) {\n"
    "        if (!head) low = halo_segment_index(halo_segment_bounds.x, phi0, dphi, first, end);\n"
    "        if (!tail) high = halo_segment_index(halo_segment_bounds.y, phi0, dphi, first, end);\n"
    "    } else if (!head) {\n"
    "        low = end; // a ray that does not advance along the view axis is marched in the first segment\n"
    "    }\n"
    "    if (halo_segment_ended) low = end;\n"
    "    first = low;\n"
    "    end = max(low, high);\n"
    "}\n"
    "void halo_segment_end(vec4 state, bool ended) {\n"
    "    halo_segment_state_out = vec4(state.rgb, ended || halo_segment_ended ? state.a + 2.0 : state.a);\n"
    "}";

/* The uniforms of camera_glsl and segment_glsl, for the reflection: a host that draws
 * itself sets them (halo_gl_set_camera; halo_gl_frame_draw sets them all per segment). */
const halo_runtime_uniform halo_runtime_uniforms[] = {
    {"halo_camera_eye", "vec4",
     "xyz: the eye (w = 1), or the unit direction towards the viewer (w = 0: "
     "orthographic), in the space of the host's ray positions",
     "halo_gl_set_camera", 0},
    {"halo_camera_plane", "vec4", "phi(P) = dot(xyz, P) + w: distance along the view axis", "halo_gl_set_camera", 0},
    {"halo_camera_depth_range", "vec2", "phi at the front and back of the volume's bounding sphere",
     "halo_gl_set_camera", 0},
    {"halo_segment_state", "sampler2D", "the rays' state after the previous segment", "halo_gl_frame_draw", 1},
    {"halo_segment_bounds", "vec2", "samples with bounds.x <= phi < bounds.y are this segment's", "halo_gl_frame_draw",
     1},
    {"halo_segment_flags", "int", "1: the first segment, 2: the last", "halo_gl_frame_draw", 1},
    /* host contract 3 (emit.c): the stack of the segments' field layers */
    {"halo_stack_plane", "vec4", "phi(P) = dot(xyz, P) + w: the depth segments' axis", "halo_gl_frame_draw", 2},
    {"halo_stack_slabs", "vec3", "x: phi where segment 0 begins, y: 1 / a segment's length, z: segments",
     "halo_gl_frame_draw", 2},
};
const size_t halo_runtime_uniform_count = sizeof halo_runtime_uniforms / sizeof halo_runtime_uniforms[0];

int halo_program_declares_runtime_uniform(const halo_program *p, const halo_runtime_uniform *u)
{
    if (u->segmented == 2)
        return p->one_draw;
    return p->v2_host && (!u->segmented || p->segment_location > 0);
}

/* One draw: the whole ray, as a v1 host. */
static const char single_glsl[] =
    "void halo_segment_begin(vec3 origin, vec3 direction, float t_first, float t_step,\n"
    "                        inout int first, inout int end, inout vec4 state) {}\n"
    "void halo_segment_end(vec4 state, bool ended) {}";

void halo_segment_emit(halo_strbuf *b, const halo_program *p)
{
    if (!p->v2_host)
        return;
    halo_strbuf_append(b, camera_glsl);
    halo_strbuf_append(b, "\n");
    char layout[48];
    if (p->segment_location > 0)
        halo_strbuf_printf(b, segment_glsl, halo_output_layout(p, p->segment_location, layout, sizeof layout));
    else
        halo_strbuf_append(b, single_glsl);
    if (p->volume_sampler || p->gradient_sampler)
        /* the host's sampler is declared after the marker: a prototype here, the body
         * after the host's last line (halo_segment_emit_tail) */
        halo_strbuf_append(b,
                           "\nvec3 halo_gradient_at(vec3 position);\n"
                           "halo_sample halo_make_sample(vec3 position, float value, vec3 color, float opacity) {\n"
                           "    return halo_make_sample(position, value, halo_gradient_at(position), "
                           "halo_view_at(position),\n"
                           "                            halo_depth_at(position), gl_FragCoord.xy, color, opacity);\n"
                           "}");
}

void halo_segment_emit_tail(halo_strbuf *b, const halo_program *p)
{
    if (p->gradient_sampler) {
        halo_strbuf_printf(b, "vec3 halo_gradient_at(vec3 position) { return texture(%s, position).rgb; }",
                           p->gradient_sampler);
    } else if (p->volume_sampler) {
        /* the host contract's gradient: central differences of the value over +-1 voxel, halved */
        const char *v = p->volume_sampler;
        halo_strbuf_printf(b,
                           "vec3 halo_gradient_at(vec3 position) {\n"
                           "    vec3 voxel = 1.0 / vec3(textureSize(%s, 0));\n"
                           "    return 0.5 * vec3(texture(%s, position + vec3(voxel.x, 0.0, 0.0)).r - "
                           "texture(%s, position - vec3(voxel.x, 0.0, 0.0)).r,\n"
                           "                      texture(%s, position + vec3(0.0, voxel.y, 0.0)).r - "
                           "texture(%s, position - vec3(0.0, voxel.y, 0.0)).r,\n"
                           "                      texture(%s, position + vec3(0.0, 0.0, voxel.z)).r - "
                           "texture(%s, position - vec3(0.0, 0.0, voxel.z)).r);\n"
                           "}",
                           v, v, v, v, v, v, v);
    }
}

/* Passes run between slices (at=generate): a single-pass host needs segments for them. */
int halo_program_has_generation_passes(const halo_program *p)
{
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        for (size_t k = 0; k < m->pass_count; k++)
            if (!m->passes[k].at)
                return 1;
    }
    return 0;
}

/* "layout(location = N) " or "" for a program whose outputs carry none (GLSL 150). */
const char *halo_output_layout(const halo_program *p, int location, char *buf, size_t len)
{
    if (p->unlocated_outputs)
        return "";
    snprintf(buf, len, "layout(location = %d) ", location);
    return buf;
}
