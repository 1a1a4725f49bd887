#version 330
// __FILE__ is the file's name, not a number, unless GL_GOOGLE_cpp_style_line_directive
// is on: the preprocessor refuses to add to it.
out vec4 color;
#line __FILE__ + 10
void main() {
    color = vec4(0.0);
}
