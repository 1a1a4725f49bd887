#version 100
// GLSL ES 1.00: gl_FragColor, a default precision
precision mediump float;
void main() {
    gl_FragColor = vec4(0.25, 0.5, 0.75, 1.0);
}
