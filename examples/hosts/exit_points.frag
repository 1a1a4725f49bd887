#version 330 core
// The first pass of the two-pass caster: the texture-space position of the cube's back
// face, alpha 1 where the cube covers the pixel (the target is cleared to 0).

in vec3 position;
layout(location = 0) out vec4 exit_point;

void main()
{
    exit_point = vec4(position, 1.0);
}
