#version 330 core
out vec4 color;
#define stringize(a) #a
void main() {
    color = vec4(stringize(1.0));
    color = vec4(later_missing);
}
