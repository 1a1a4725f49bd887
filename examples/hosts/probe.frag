#version 330 core
// Conformance host: one halo_sample per pixel, read from float textures instead of
// marching a ray, so every stage can be fed exactly chosen inputs (validate/conform.c).
// Follows the host contract (docs/host-contract.md, version 1); compiled without
// libhalo it passes the classified colour and opacity through unchanged.
// Common subset of GLSL 330 core and GLSL ES 300; use with raycast.vert.

#pragma halo declarations

uniform highp sampler2D position_value;   // RGBA32F: position xyz, value
uniform highp sampler2D gradient_depth;   // RGBA32F: gradient xyz, depth
uniform highp sampler2D view_texture;     // RGBA32F: view xyz (w unused)
uniform highp sampler2D color_opacity;    // RGBA32F: colour rgb, opacity

in vec2 ndc; // unused: every input is read at the fragment's own texel
layout(location = 0) out vec4 result;     // RGBA32F target: colour rgb, opacity after halo_apply

void main()
{
    ivec2 texel = ivec2(gl_FragCoord.xy);
    vec4 position = texelFetch(position_value, texel, 0);
    vec4 gradient = texelFetch(gradient_depth, texel, 0);
    vec4 view = texelFetch(view_texture, texel, 0);
    vec4 color = texelFetch(color_opacity, texel, 0);
#ifdef HALO_LINKED
    halo_sample s = halo_make_sample(position.xyz, position.w, gradient.xyz, view.xyz, gradient.w,
                                     gl_FragCoord.xy, color.rgb, color.a);
    halo_apply(s);
    color = vec4(s.color, s.opacity);
    halo_finish();
#endif
    result = color;
}
