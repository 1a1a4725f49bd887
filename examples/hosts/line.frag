#version 330 core
// The example line host's fragment shader: normalized linear depth (0 at the front of
// the data, 1 at its back) goes to gl_FragDepth, so a stage that moves f.depth changes
// what the depth test hides (libhalo's line_halo: depth-dependent halos).
#pragma halo declarations
in vec2 line_uv;
in float line_depth;
in vec3 line_rgb;
in float line_opacity;
uniform vec3 background;
layout(location = 0) out vec4 frag_color;

void main()
{
    vec3 color = line_rgb;
    float opacity = line_opacity;
    float depth = line_depth;
#ifdef HALO_LINKED
    halo_line_fragment f = halo_make_line_fragment(line_uv, line_depth, gl_FragCoord.xy, color, opacity, background);
    halo_apply(f);
    color = f.color;
    opacity = f.opacity;
    depth = f.depth;
    halo_finish();
#endif
    gl_FragDepth = clamp(depth, 0.0, 1.0);
    frag_color = vec4(color, opacity);
}
