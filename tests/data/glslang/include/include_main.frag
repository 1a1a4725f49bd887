#version 330 core
#extension GL_GOOGLE_include_directive : require
#include "include_part.h"
out vec4 color;
void main() {
    color = vec4(shade(0.5));
}
