#version 330 core
#extension GL_GOOGLE_cpp_style_line_directive : require
out vec4 color;
#line 20 "part.glsl"
void main() {
    color = vec4(second_missing);
}
