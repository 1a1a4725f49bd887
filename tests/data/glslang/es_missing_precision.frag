#version 300 es
// no default precision for float: an error in an ES fragment shader
out vec4 color;
void main() {
    color = vec4(1.0);
}
