#version 330 core
out vec4 color;
#line 100
void main() {
    color = vec4(first_missing);
}
