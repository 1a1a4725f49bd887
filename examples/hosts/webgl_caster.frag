#version 300 es
// Example host in the style of a WebGL2 volume renderer: one full-screen pass, a ray-box
// intersection per fragment, a jittered first sample against wood-grain artefacts, and
// early ray termination. GLSL ES 3.00 with precision qualifiers; written here for
// libhalo's host contract, version 2 (docs/host-contract.md).
//
// Compiled as it is, the pragmas are ignored and HALO_LINKED is undefined: that is the
// renderer before libhalo. The libhalo recipe changed 3 lines of it (the loop bounds)
// and added the pragmas and the HALO_LINKED blocks. The host passes position, value,
// colour and opacity only; libhalo derives the gradient from volume_texture (the pragma
// below), the view direction and the depth.

precision highp float;
precision highp int;
precision highp sampler3D;

#pragma halo declarations
#ifndef HALO_RAY_MAY_END
#define HALO_RAY_MAY_END 1 // libhalo says 0 when its stages need every sample of a ray
#endif
#pragma halo volume volume_texture

uniform highp sampler3D volume_texture; // R32F, value normalized to [0,1]
uniform highp sampler2D transfer_texture; // N x 1 RGBA: colour and opacity per unit step
uniform mat4 inverse_view_projection;   // clip space -> volume texture space [0,1]^3
uniform float step_size;                // ray step in texture units
uniform float unit_step;                // the step transfer opacities are given for
uniform vec3 background;
uniform float jitter;                   // 0: first sample on the box; 1: offset by up to one step

in vec2 ndc;
layout(location = 0) out vec4 frag_color;

const float termination_opacity = 0.98;

// Ray parameters where the ray enters and leaves the unit box (slab test).
vec2 intersect_box(vec3 origin, vec3 direction)
{
    vec3 inverse_direction = 1.0 / direction;
    vec3 t0 = -origin * inverse_direction;
    vec3 t1 = (vec3(1.0) - origin) * inverse_direction;
    vec3 near_t = min(t0, t1), far_t = max(t0, t1);
    return vec2(max(max(near_t.x, near_t.y), near_t.z), min(min(far_t.x, far_t.y), far_t.z));
}

// A small integer hash of the pixel, in [0,1).
float pixel_hash(vec2 frag_coord)
{
    uvec2 q = uvec2(frag_coord);
    uint h = q.x * 1664525u + q.y * 22695477u + 1013904223u;
    h ^= h >> 15;
    h *= 2246822519u;
    h ^= h >> 13;
    return float(h >> 8) * (1.0 / 16777216.0);
}

void main()
{
    vec4 near_h = inverse_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far_h = inverse_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 origin = near_h.xyz / near_h.w;
    vec3 direction = normalize(far_h.xyz / far_h.w - origin);

    vec2 hit = intersect_box(origin, direction);
    float t_near = max(hit.x, 0.0);
    float t_first = t_near + jitter * pixel_hash(gl_FragCoord.xy) * step_size;
    int steps = hit.y > t_first ? int(ceil((hit.y - t_first) / step_size)) : 0;
    float exponent = step_size / unit_step;

    vec4 accumulated = vec4(0.0);
    int first = 0, end = steps;
#ifdef HALO_LINKED
    halo_segment_begin(origin, direction, t_first, step_size, first, end, accumulated);
#endif
    int i = first;
    for (; i < end; ++i) {
        vec3 P = origin + (t_first + float(i) * step_size) * direction;
        float value = texture(volume_texture, P).r;
        vec4 color = texture(transfer_texture, vec2(clamp(value, 0.0, 1.0), 0.5));
#ifdef HALO_LINKED
        halo_sample s = halo_make_sample(P, value, color.rgb, color.a);
        halo_apply(s);
        color = vec4(s.color, s.opacity);
#endif
        float alpha = 1.0 - pow(1.0 - clamp(color.a, 0.0, 1.0), exponent);
        accumulated += (1.0 - accumulated.a) * vec4(color.rgb * alpha, alpha);
        if (accumulated.a >= termination_opacity && HALO_RAY_MAY_END != 0)
            break;
    }
#ifdef HALO_LINKED
    halo_segment_end(accumulated, i < end);
    halo_finish();
#endif
    frag_color = vec4(accumulated.rgb + (1.0 - accumulated.a) * background, 1.0);
}
