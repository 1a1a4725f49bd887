#version 330 core
out vec4 color;
#error stop here
void main() {
    color = vec4(undeclared_value);
}
