#version 450 core
// Example host in the style of a desktop GL 4 two-pass ray caster: a first pass draws
// the back faces of the volume's box into a texture of texture-space positions
// (exit_points.vert/.frag, drawn by the C side before this pass); this pass starts each
// ray where it enters the box and reads where it leaves from that texture. Written for
// libhalo's host contract, version 2 (docs/host-contract.md): the recipe changed 3
// loop lines and added the pragmas and the HALO_LINKED blocks; libhalo derives the
// gradient (from volume_texture), the view direction and the depth. No layout(binding):
// the C side binds the samplers by name, so the text also links for 330 and ES 300.

#pragma halo declarations
#ifndef HALO_RAY_MAY_END
#define HALO_RAY_MAY_END 1 // libhalo says 0 when its stages need every sample of a ray
#endif
#pragma halo volume volume_texture

uniform highp sampler3D volume_texture;   // unit 0: R32F, value normalized to [0,1]
uniform highp sampler2D transfer_texture; // unit 1: N x 1 RGBA, colour and opacity per unit step
uniform highp sampler2D exit_points;      // unit 2, the first pass: xyz exit point, a = 1 on the box
uniform mat4 inverse_view_projection;     // clip space -> volume texture space [0,1]^3
uniform float step_size;                  // ray step in texture units
uniform float unit_step;                  // the step transfer opacities are given for
uniform vec3 background;

in vec2 ndc;
layout(location = 0) out vec4 frag_color;

void main()
{
    vec4 near_h = inverse_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far_h = inverse_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 origin = near_h.xyz / near_h.w;
    vec3 direction = normalize(far_h.xyz / far_h.w - origin);
    vec3 t0 = -origin / direction, t1 = (vec3(1.0) - origin) / direction;
    float t_enter = max(max(max(min(t0.x, t1.x), min(t0.y, t1.y)), min(t0.z, t1.z)), 0.0);
    vec4 exit_point = texelFetch(exit_points, ivec2(gl_FragCoord.xy), 0);
    float t_exit = exit_point.a > 0.0 ? dot(exit_point.xyz - origin, direction) : -1.0;
    int steps = t_exit >= t_enter ? int(floor((t_exit - t_enter) / step_size)) + 1 : 0;

    vec4 dst = vec4(0.0);
    int first = 0, end = steps;
#ifdef HALO_LINKED
    halo_segment_begin(origin, direction, t_enter, step_size, first, end, dst);
#endif
    int i = first;
    for (; i < end; i++) {
        vec3 P = origin + (t_enter + float(i) * step_size) * direction;
        float value = texture(volume_texture, P).r;
        float texels = float(textureSize(transfer_texture, 0).x);
        vec4 src = texture(transfer_texture, vec2((clamp(value, 0.0, 1.0) * (texels - 1.0) + 0.5) / texels, 0.5));
#ifdef HALO_LINKED
        halo_sample s = halo_make_sample(P, value, src.rgb, src.a);
        halo_apply(s);
        src = vec4(s.color, s.opacity);
#endif
        src.a = 1.0 - pow(1.0 - clamp(src.a, 0.0, 1.0), step_size / unit_step);
        dst.rgb += (1.0 - dst.a) * src.a * src.rgb;
        dst.a += (1.0 - dst.a) * src.a;
        if (dst.a >= 0.99 && HALO_RAY_MAY_END != 0)
            break;
    }
#ifdef HALO_LINKED
    halo_segment_end(dst, i < end);
    halo_finish();
#endif
    frag_color = vec4(dst.rgb + (1.0 - dst.a) * background, 1.0);
}
