#version 330 core
// The example line host's vertex shader (examples/hosts/lines.c): every polyline vertex
// arrives twice, with uv.y = 0 and 1 (the paper's zero-width triangle strip), the
// averaged line direction and uv.x running 0..1 along the line. Unlinked, the strip
// keeps zero width; libhalo's line_strip stage opens it towards the viewer.
#pragma halo declarations
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 direction;
layout(location = 2) in vec2 uv;
uniform mat4 view_projection;
uniform vec3 eye;
uniform vec3 forward;     // unit viewing direction
uniform vec2 depth_range; // distance along forward of the data's front and back
uniform float width_unit; // length unit of strip widths (the data's bounding radius)
uniform vec3 line_color;
out vec2 line_uv;
out float line_depth;
out vec3 line_rgb;
out float line_opacity;

void main()
{
    vec3 p = position;
    vec3 color = line_color;
    float opacity = 1.0;
#ifdef HALO_LINKED
    halo_line_vertex v = halo_make_line_vertex(position, direction, uv, eye, width_unit, color, opacity);
    halo_apply(v);
    p = v.position;
    color = v.color;
    opacity = v.opacity;
#endif
    line_uv = uv;
    float extent = depth_range.y - depth_range.x;
    line_depth = extent > 0.0 ? (dot(p - eye, forward) - depth_range.x) / extent : 0.0;
    line_rgb = color;
    line_opacity = opacity;
    gl_Position = view_projection * vec4(p, 1.0);
}
