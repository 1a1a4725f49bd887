#version 330 core
// Conformance probe for line_fragment stages (validate/conform_lines.c): every pixel
// reads its inputs from two float textures, runs the stages and writes colour, opacity
// and depth to two float targets.
#pragma halo declarations
uniform sampler2D uv_depth;         // xy: uv, z: depth
uniform sampler2D color_opacity;    // rgb: line colour, a: opacity
uniform sampler2D background_color; // rgb: background
layout(location = 0) out vec4 out_color;
layout(location = 1) out vec4 out_depth;

void main()
{
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 a = texelFetch(uv_depth, pixel, 0);
    vec4 b = texelFetch(color_opacity, pixel, 0);
    vec3 background = texelFetch(background_color, pixel, 0).rgb;
    vec3 color = b.rgb;
    float opacity = b.a;
    float depth = a.z;
#ifdef HALO_LINKED
    halo_line_fragment f = halo_make_line_fragment(a.xy, a.z, gl_FragCoord.xy, color, opacity, background);
    halo_apply(f);
    color = f.color;
    opacity = f.opacity;
    depth = f.depth;
    halo_finish();
#endif
    out_color = vec4(color, opacity);
    out_depth = vec4(depth, 0.0, 0.0, 1.0);
}
