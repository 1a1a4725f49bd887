#version 330 core
out vec4 color;
void helper() {
    color = vec4(1.0) + ;
}
