#version 330 core
// Example host in the style of a MIP / isosurface shader of a web or desktop viewer:
// one full-screen pass, a ray-box intersection, and a mode chosen at compile time.
//
//  - Isosurface (the default): samples are classified by a step at iso_value (opaque
//    at and above it, transparent below) and composited front to back, so the first
//    hit ends the ray; the surface is lit by the host's own gradient. libhalo's recipe
//    goes in as in any front-to-back caster: volumetric halos, outlines and every
//    per-sample stage work on the surface and the empty space in front of it.
//  - MIP (uncomment the two lines below together): the ray keeps the largest value and
//    composites no samples, so the host never calls halo_apply; it declares that to
//    libhalo, which then refuses any scene stage (HOST_COMPOSITING) instead of linking
//    stages that would mean nothing.
//#define MIP
//#pragma halo compositing mip
//
// Written for libhalo's host contract, version 2 (docs/host-contract.md). The host
// passes its own gradient (its normal is -gradient) and takes the view direction and
// depth from libhalo (halo_view_at, halo_depth_at).

#pragma halo declarations
#ifndef HALO_RAY_MAY_END
#define HALO_RAY_MAY_END 1 // libhalo says 0 when its stages need every sample of a ray
#endif

uniform highp sampler3D volume_texture; // R32F, value normalized to [0,1]
uniform highp sampler2D transfer_texture; // N x 1 RGBA: colour by value
uniform mat4 inverse_view_projection;   // clip space -> volume texture space [0,1]^3
uniform vec3 eye;                       // eye position in volume texture space
uniform float step_size;                // ray step in texture units
uniform vec3 background;

in vec2 ndc;
layout(location = 0) out vec4 frag_color;

const float iso_value = 0.5;

vec4 colormap(float value)
{
    return texture(transfer_texture, vec2(clamp(value, 0.0, 1.0), 0.5));
}

// Unhalved central differences over one voxel: the host's gradient.
vec3 gradient_at(vec3 p)
{
    vec3 h = 1.0 / vec3(textureSize(volume_texture, 0));
    return vec3(texture(volume_texture, p + vec3(h.x, 0.0, 0.0)).r - texture(volume_texture, p - vec3(h.x, 0.0, 0.0)).r,
                texture(volume_texture, p + vec3(0.0, h.y, 0.0)).r - texture(volume_texture, p - vec3(0.0, h.y, 0.0)).r,
                texture(volume_texture, p + vec3(0.0, 0.0, h.z)).r - texture(volume_texture, p - vec3(0.0, 0.0, h.z)).r);
}

void main()
{
    vec4 near_h = inverse_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far_h = inverse_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 origin = near_h.xyz / near_h.w;
    vec3 direction = normalize(far_h.xyz / far_h.w - origin);
    vec3 inverse_direction = 1.0 / direction;
    vec3 t0 = -origin * inverse_direction, t1 = (vec3(1.0) - origin) * inverse_direction;
    vec3 near_t = min(t0, t1), far_t = max(t0, t1);
    float t_near = max(max(max(near_t.x, near_t.y), near_t.z), 0.0);
    float t_far = min(min(far_t.x, far_t.y), far_t.z);
    int steps = t_far > t_near ? int(ceil((t_far - t_near) / step_size)) : 0;

#ifdef MIP
    float max_value = 0.0;
    for (int i = 0; i < steps; ++i)
        max_value = max(max_value, texture(volume_texture, origin + (t_near + float(i) * step_size) * direction).r);
    vec4 mip = colormap(max_value);
    frag_color = vec4(mip.rgb * mip.a + (1.0 - mip.a) * background, 1.0);
#else
    vec4 accumulated = vec4(0.0);
    int first = 0, end = steps;
#ifdef HALO_LINKED
    halo_segment_begin(origin, direction, t_near, step_size, first, end, accumulated);
#endif
    int i = first;
    for (; i < end; ++i) {
        vec3 P = origin + (t_near + float(i) * step_size) * direction;
        float value = texture(volume_texture, P).r;
        vec4 color = vec4(0.0);
        vec3 gradient = vec3(0.0);
        if (value >= iso_value) {
            gradient = gradient_at(P);
            vec3 N = -gradient * inversesqrt(max(dot(gradient, gradient), 1e-20));
            float diffuse = abs(dot(N, normalize(eye - P)));
            color = vec4(colormap(value).rgb * (0.25 + 0.75 * diffuse), 1.0);
        }
#ifdef HALO_LINKED
        halo_sample s = halo_make_sample(P, value, 0.5 * gradient, halo_view_at(P), halo_depth_at(P),
                                         gl_FragCoord.xy, color.rgb, color.a);
        halo_apply(s);
        color = vec4(s.color, s.opacity);
#endif
        float alpha = clamp(color.a, 0.0, 1.0);
        accumulated += (1.0 - accumulated.a) * vec4(color.rgb * alpha, alpha);
        if (accumulated.a >= 0.99 && HALO_RAY_MAY_END != 0)
            break;
    }
#ifdef HALO_LINKED
    halo_segment_end(accumulated, i < end);
#endif
    frag_color = vec4(accumulated.rgb + (1.0 - accumulated.a) * background, 1.0);
#endif
#ifdef HALO_LINKED
    halo_finish();
#endif
}
