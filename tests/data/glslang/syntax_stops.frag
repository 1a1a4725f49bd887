#version 330 core
out vec4 color;
float broken = ;
void main() {
    int c = 'x';
    color = vec4(1.0);
}
