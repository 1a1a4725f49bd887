#version 330 core
// Conformance probe for line_vertex stages (validate/conform_lines.c): one point per
// input vertex, drawn at pixel gl_VertexID of the target, carrying the stage's output
// to a float render target (line_probe_point.frag writes it).
#pragma halo declarations
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 direction;
layout(location = 2) in vec2 uv;
layout(location = 3) in vec4 eye_width; // eye position, width unit
uniform ivec2 target_size;
flat out vec4 probe_position; // xyz: output position, w: output width
flat out vec4 probe_color;    // rgb: output colour, a: output opacity

void main()
{
    vec3 p = position;
    float width = eye_width.w;
    vec3 color = vec3(0.25, 0.5, 0.75);
    float opacity = 0.5;
#ifdef HALO_LINKED
    halo_line_vertex v = halo_make_line_vertex(position, direction, uv, eye_width.xyz, eye_width.w, color, opacity);
    halo_apply(v);
    p = v.position;
    width = v.width;
    color = v.color;
    opacity = v.opacity;
#endif
    probe_position = vec4(p, width);
    probe_color = vec4(color, opacity);
    int x = gl_VertexID % target_size.x;
    int y = gl_VertexID / target_size.x;
    gl_Position = vec4((vec2(x, y) + 0.5) / vec2(target_size) * 2.0 - 1.0, 0.0, 1.0);
}
