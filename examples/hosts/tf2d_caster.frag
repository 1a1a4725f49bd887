#version 330 core
// Example host in the style of a desktop caster with a two-dimensional transfer
// function (Kniss et al.: value x gradient magnitude) and its own Phong lighting. One
// full-screen pass; written for libhalo's host contract, version 2
// (docs/host-contract.md).
//
// The 2D transfer function is procedural: colour and opacity by value come from the
// 1D table, then the gradient magnitude keeps boundaries (opacity rises with |g|,
// homogeneous interiors stay faint) and whitens the strongest edges.
//
// Where halo_apply goes: after the host's classification and Phong lighting and
// before its opacity correction, for every sample, outside the host's `if (a > 0)`
// skip of the lighting. The stages then see the lit colour the host would composite,
// with opacity per unit step, and the empty samples in front of a surface get the
// halo's colour and opacity (a skip around halo_apply would drop them). The host passes
// its own gradient, converted to the contract's (its differences are unhalved: times
// 0.5), its own view direction, and libhalo's depth (halo_depth_at).

#pragma halo declarations
#ifndef HALO_RAY_MAY_END
#define HALO_RAY_MAY_END 1 // libhalo says 0 when its stages need every sample of a ray
#endif

uniform highp sampler3D volume_texture; // R32F, value normalized to [0,1]
uniform highp sampler2D transfer_texture; // N x 1 RGBA: colour and opacity per unit step by value
uniform mat4 inverse_view_projection;   // clip space -> volume texture space [0,1]^3
uniform vec3 eye;                       // eye position (and headlight) in volume texture space
uniform float step_size;                // ray step in texture units
uniform float unit_step;                // the step transfer opacities are given for
uniform vec3 background;

in vec2 ndc;
layout(location = 0) out vec4 frag_color;

const int max_samples = 4096;
const float ambient = 0.3, diffuse = 0.6, specular = 0.25, shininess = 24.0;

// Value x gradient magnitude (the magnitude of unhalved differences over one voxel).
vec4 transfer_2d(float value, float magnitude)
{
    vec4 by_value = texture(transfer_texture, vec2(clamp(value, 0.0, 1.0), 0.5));
    float boundary = smoothstep(0.01, 0.12, magnitude);
    vec3 rgb = mix(by_value.rgb, vec3(1.0, 0.97, 0.9), 0.4 * smoothstep(0.12, 0.4, magnitude));
    return vec4(rgb, by_value.a * (0.15 + 0.85 * boundary));
}

void main()
{
    vec4 near_h = inverse_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far_h = inverse_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 origin = near_h.xyz / near_h.w;
    vec3 direction = normalize(far_h.xyz / far_h.w - origin);
    vec3 t0 = -origin / direction, t1 = (vec3(1.0) - origin) / direction;
    float t_enter = max(max(max(min(t0.x, t1.x), min(t0.y, t1.y)), min(t0.z, t1.z)), 0.0);
    float t_exit = min(min(max(t0.x, t1.x), max(t0.y, t1.y)), max(t0.z, t1.z));
    vec3 h = 1.0 / vec3(textureSize(volume_texture, 0));

    vec4 sum = vec4(0.0);
    int first = 0, end = max_samples;
#ifdef HALO_LINKED
    halo_segment_begin(origin, direction, t_enter, step_size, first, end, sum);
#endif
    int k = first;
    for (; k < end; ++k) {
        float t = t_enter + float(k) * step_size;
        if (t > t_exit)
            break;
        vec3 P = origin + t * direction;
        float value = texture(volume_texture, P).r;
        vec3 g = vec3(texture(volume_texture, P + vec3(h.x, 0, 0)).r - texture(volume_texture, P - vec3(h.x, 0, 0)).r,
                      texture(volume_texture, P + vec3(0, h.y, 0)).r - texture(volume_texture, P - vec3(0, h.y, 0)).r,
                      texture(volume_texture, P + vec3(0, 0, h.z)).r - texture(volume_texture, P - vec3(0, 0, h.z)).r);
        vec4 color = transfer_2d(value, length(g));
        vec3 V = normalize(eye - P);
        if (color.a > 0.0) {
            // Phong, headlight, two-sided; the normal points to lower values
            vec3 N = length(g) > 1e-6 ? -normalize(g) : V;
            N = dot(N, V) < 0.0 ? -N : N;
            float d = max(dot(N, V), 0.0), r = pow(max(dot(reflect(-V, N), V), 0.0), shininess);
            color.rgb = color.rgb * (ambient + diffuse * d) + vec3(specular * r);
        }
#ifdef HALO_LINKED
        halo_sample s = halo_make_sample(P, value, 0.5 * g, V, halo_depth_at(P), gl_FragCoord.xy, color.rgb, color.a);
        halo_apply(s);
        color = vec4(s.color, s.opacity);
#endif
        float alpha = 1.0 - pow(1.0 - clamp(color.a, 0.0, 1.0), step_size / unit_step);
        sum.rgb += (1.0 - sum.a) * alpha * color.rgb;
        sum.a += (1.0 - sum.a) * alpha;
        if (sum.a > 0.995 && HALO_RAY_MAY_END != 0)
            break;
    }
#ifdef HALO_LINKED
    halo_segment_end(sum, k < end);
    halo_finish();
#endif
    frag_color = vec4(sum.rgb + (1.0 - sum.a) * background, 1.0);
}
