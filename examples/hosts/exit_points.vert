#version 330 core
// The first pass of the two-pass caster (exit_point_caster.frag): the unit cube of
// volume texture space as 12 triangles (36 vertices, no attributes), clockwise seen
// from outside: GL's default culling of back-facing (clockwise) triangles then keeps the
// box's far side, whose fragments are the rays' exit points (exit_points.frag).

uniform mat4 view_projection; // volume texture space -> clip space
out vec3 position;

const int corners[36] = int[36](4, 2, 6, 4, 0, 2, 1, 7, 3, 1, 5, 7, 1, 4, 5, 1, 0, 4,
                                2, 7, 6, 2, 3, 7, 2, 1, 3, 2, 0, 1, 4, 7, 5, 4, 6, 7);

void main()
{
    int c = corners[gl_VertexID];
    position = vec3(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1));
    gl_Position = view_projection * vec4(position, 1.0);
}
