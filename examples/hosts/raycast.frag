#version 330 core
// Example GPU ray caster: an ordinary front-to-back emission-absorption ray caster
// that follows the libhalo host contract (docs/host-contract.md, version 2): with
// stages that run image passes between slices (volumetric halos), libhalo's runtime
// draws it once per depth segment (halo_gl_frame_draw).
//
// The same file is the renderer's original shader: compiled as it is, the pragma
// below is ignored and HALO_LINKED is undefined. Linked by libhalo, the pragma is
// replaced by the enabled stages and halo_apply runs for every sample.
//
// Written in the common subset of GLSL 330 core and GLSL ES 300; the linker replaces
// the #version line for its target. (Under ES 300 the float textures must be
// filterable: OES_texture_float_linear, or 16-bit float textures.)
//
// Output: location 0, premultiplied colour composited front to back and then over
// the opaque background, so alpha is 1 wherever the background shows.

#pragma halo declarations
#ifndef HALO_RAY_MAY_END
#define HALO_RAY_MAY_END 1 // libhalo says 0 when its stages need every sample of a ray
#endif

uniform highp sampler3D volume_texture;   // R32F, value already normalized to [0,1] by the intensity window
uniform highp sampler2D transfer_texture; // N x 1 RGBA: linear RGB and opacity per unit step, for value in [0,1]
uniform mat4 inverse_view_projection;     // clip space -> volume texture space [0,1]^3
uniform vec3 eye;                         // eye position in volume texture space
uniform float step_size;                  // ray step in texture units
uniform float unit_step;                  // the step the transfer opacities are given for, in texture units
uniform vec3 background;                  // linear RGB

in vec2 ndc;
layout(location = 0) out vec4 frag_color;

// Front-to-back compositing stops once the ray is this opaque.
const float opacity_threshold = 0.99;
// Upper bound on samples per ray: enough for a 1024^3 volume at half-voxel steps.
const int max_steps = 4096;

float sample_value(vec3 p)
{
    return texture(volume_texture, p).r;
}

// Central differences over +-1 voxel, divided by 2: the gradient of the normalized
// value per voxel step, along the texture axes (host contract).
vec3 sample_gradient(vec3 p, vec3 voxel)
{
    return vec3(sample_value(p + vec3(voxel.x, 0.0, 0.0)) - sample_value(p - vec3(voxel.x, 0.0, 0.0)),
                sample_value(p + vec3(0.0, voxel.y, 0.0)) - sample_value(p - vec3(0.0, voxel.y, 0.0)),
                sample_value(p + vec3(0.0, 0.0, voxel.z)) - sample_value(p - vec3(0.0, 0.0, voxel.z))) * 0.5;
}

vec4 classify(float value)
{
    float texels = float(textureSize(transfer_texture, 0).x);
    float u = ((value > 0.0 ? min(value, 1.0) : 0.0) * (texels - 1.0) + 0.5) / texels; // NaN -> 0
    return texture(transfer_texture, vec2(u, 0.5));
}

void main()
{
    vec4 near_point = inverse_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far_point = inverse_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 origin = near_point.xyz / near_point.w;
    vec3 direction = normalize(far_point.xyz / far_point.w - origin);

    // Entry and exit of the unit cube (slab method); a zero direction component gives
    // +-inf, which min/max handle.
    vec3 inverse_direction = 1.0 / direction;
    vec3 t_low = (vec3(0.0) - origin) * inverse_direction;
    vec3 t_high = (vec3(1.0) - origin) * inverse_direction;
    vec3 t_min3 = min(t_low, t_high);
    vec3 t_max3 = max(t_low, t_high);
    float t_enter = max(max(max(t_min3.x, t_min3.y), t_min3.z), 0.0);
    float t_exit = min(min(t_max3.x, t_max3.y), t_max3.z);

    vec3 voxel = 1.0 / vec3(textureSize(volume_texture, 0));
    // Depth is measured against the volume's bounding sphere (centre 0.5, radius
    // half the cube diagonal): 0 at its front, 1 at its back.
    const float radius = 0.8660254037844386;
    float front_distance = distance(eye, vec3(0.5)) - radius;
    // Opacity correction exponent: samples are step_size apart, opacities are per unit_step.
    float opacity_exponent = step_size / unit_step;

    vec4 accumulated = vec4(0.0); // premultiplied colour, opacity
    int first = 0, end = max_steps;
#ifdef HALO_LINKED
    // host contract 2: in a frame drawn in depth segments, march only this segment's samples
    halo_segment_begin(origin, direction, t_enter, step_size, first, end, accumulated);
#endif
    int i = first;
    for (; i < end; ++i) {
        float t = t_enter + float(i) * step_size;
        if (t > t_exit)
            break;
        vec3 P = origin + t * direction;
        float value = sample_value(P);
        vec4 color = classify(value);
#ifdef HALO_LINKED
        vec3 gradient = sample_gradient(P, voxel);
        vec3 V = normalize(eye - P);
        float depth = clamp((distance(eye, P) - front_distance) / (2.0 * radius), 0.0, 1.0);
        halo_sample s = halo_make_sample(P, value, gradient, V, depth, gl_FragCoord.xy, color.rgb, color.a);
        halo_apply(s);
        color = vec4(s.color, s.opacity);
#endif
        float alpha = clamp(color.a, 0.0, 1.0);
        if (alpha > 0.0) {
            alpha = 1.0 - pow(1.0 - alpha, opacity_exponent);
            accumulated.rgb += (1.0 - accumulated.a) * alpha * color.rgb;
            accumulated.a += (1.0 - accumulated.a) * alpha;
            if (accumulated.a >= opacity_threshold && HALO_RAY_MAY_END != 0)
                break;
        }
    }
#ifdef HALO_LINKED
    halo_segment_end(accumulated, i < end); // the loop stopped early: the ray has ended
    halo_finish();
#endif
    frag_color = vec4(accumulated.rgb + (1.0 - accumulated.a) * background, 1.0);
}
