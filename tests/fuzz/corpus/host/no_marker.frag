#version 330 core
// A host that forgot '#pragma halo declarations'.
out vec4 fragment_color;
void main()
{
    fragment_color = vec4(1.0);
}
