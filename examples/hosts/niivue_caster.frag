#version 330 core
// Example host in the style of NiiVue's 3D render (version 0.69, its default volume shader),
// written here for the web adapter's test (tests/adapters/web/browser.mjs draws NiiVue with
// libhalo's stages, tests/adapters/web/niivue_reference draws this host with NiiVue's inputs
// through libhalo's C runtime, and the two images are compared):
//
// - the volume is classified before it is interpolated: color_volume holds colour and
//   opacity per voxel (RGBA8), and a sample is that texture filtered trilinearly;
// - a ray starts where it enters the volume's box, one voxel a step (the step's length in
//   voxels is 1 along the ray);
// - an empty-space pass first, in steps of 1.9 voxels, to the first sample over 0.01
//   opacity, then one of its steps back (off for halos, which land in empty space: the
//   uniform empty_space_pass);
// - the first sample jittered by up to a step, by a sine hash of the pixel;
// - samples under 0.01 opacity are left out, early termination past 0.95 opacity, and the
//   opacity is divided by 0.95 at the end;
// - the output is premultiplied colour and that opacity, for a framebuffer that blends it
//   with (source alpha, one minus source alpha).
//
// The stages see the value (volume_texture, R32F), NiiVue's colour, and derive the gradient
// from volume_texture; view and depth come from libhalo's camera (host contract 1, short
// form). Written in the common subset of GLSL 330 core and GLSL ES 300.

#pragma halo declarations
#ifndef HALO_RAY_MAY_END
#define HALO_RAY_MAY_END 1 // libhalo says 0 when its stages need every sample of a ray
#endif
#pragma halo volume volume_texture

uniform highp sampler3D volume_texture; // R32F, the value in [0,1]: what the stages see
uniform highp sampler3D color_volume;   // RGBA8: colour and opacity per voxel
uniform mat4 inverse_view_projection;   // clip space -> volume texture space [0,1]^3
uniform float empty_space_pass;         // 1: the pass to the first opaque sample; 0: none
uniform highp sampler2D jitter_image;   // the pixel's jitter as another GPU computed it (R32F) ...
uniform float jitter_from_image;        // ... when 1; else computed here

in vec2 ndc;
layout(location = 0) out vec4 frag_color;

const float skip_opacity = 0.01;
const float termination = 0.95;
const float fast_steps = 1.9;

// The pixel's jitter in [0,1): the fractional part of a large multiple of a sine of the
// pixel's coordinates. A sine of 10^4 radians in float differs between GPUs in its last
// bits, which the multiple makes visible: jitter_image holds the values of the GPU drawn
// against.
float pixel_jitter(vec2 frag_coord)
{
    if (jitter_from_image > 0.5)
        return texelFetch(jitter_image, ivec2(frag_coord), 0).r;
    return fract(sin(frag_coord.x * 12.9898 + frag_coord.y * 78.233) * 43758.5453);
}

void main()
{
    vec4 near_point = inverse_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far_point = inverse_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 origin = near_point.xyz / near_point.w;
    vec3 direction = normalize(far_point.xyz / far_point.w - origin);
    // as NiiVue: no component under 5e-5 in size, so that 1/direction stays finite
    vec3 signs = vec3(greaterThanEqual(direction, vec3(0.0))) * 2.0 - 1.0;
    direction = signs * max(abs(direction), vec3(5e-5));
    vec3 inverse_direction = 1.0 / direction;
    vec3 t_low = -origin * inverse_direction;
    vec3 t_high = (vec3(1.0) - origin) * inverse_direction;
    vec3 t_min3 = min(t_low, t_high), t_max3 = max(t_low, t_high);
    float t_enter = max(max(max(t_min3.x, t_min3.y), t_min3.z), 0.0);
    float t_exit = min(min(t_max3.x, t_max3.y), t_max3.z);

    vec4 accumulated = vec4(0.0); // premultiplied colour, opacity
    vec3 start = origin + t_enter * direction;
    vec3 through = origin + max(t_exit, t_enter) * direction - start;
    float len = length(through);
    float len_voxels = length(vec3(textureSize(color_volume, 0)) * through);
    bool sampled = len_voxels >= 0.5 && len <= 3.0;
    float step = sampled ? len / len_voxels : 0.0;
    vec3 dir = sampled ? through / len : vec3(0.0);
    float t = 0.0;
    if (sampled && empty_space_pass > 0.5) {
        float fast = fast_steps * step;
        while (t <= len) {
            if (texture(color_volume, start + t * dir).a > skip_opacity)
                break;
            t += fast;
        }
        sampled = t < len;
        if (t > fast)
            t -= fast;
    }
    if (sampled) {
        t += step * pixel_jitter(gl_FragCoord.xy);
        float opacity_correction = step / step;
        while (t <= len) {
            vec3 P = start + t * dir;
            vec4 color = texture(color_volume, P);
#ifdef HALO_LINKED
            float value = texture(volume_texture, P).r;
            halo_sample s = halo_make_sample(P, value, color.rgb, color.a);
            halo_apply(s);
            color = vec4(s.color, s.opacity);
#endif
            t += step;
            if (color.a >= skip_opacity) {
                color.a = 1.0 - pow(1.0 - color.a, opacity_correction);
                accumulated += (1.0 - accumulated.a) * vec4(color.rgb * color.a, color.a);
                if (accumulated.a > termination && HALO_RAY_MAY_END != 0)
                    break;
            }
        }
    }
#ifdef HALO_LINKED
    halo_finish();
#endif
    frag_color = vec4(accumulated.rgb, accumulated.a / termination);
}
