#version 330 core
// Full-screen triangle for the slice host and the slab ray caster (slice.frag, slab.frag):
// one per slice or slab.
// No vertex attributes: draw 3 vertices with any vertex array bound. The triangle
// (-1,-1) (3,-1) (-1,3) covers the viewport; ndc is the fragment's position in
// normalized device coordinates, from which the fragment shader builds its ray.
// Common subset of GLSL 330 core and GLSL ES 300.

out vec2 ndc;

void main()
{
    vec2 corner = vec2(float((gl_VertexID & 1) << 2), float((gl_VertexID & 2) << 1)) - 1.0;
    ndc = corner;
    gl_Position = vec4(corner, 0.0, 1.0);
}
