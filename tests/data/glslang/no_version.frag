// no #version: GLSL ES 1.00 by GLSL's rule
precision mediump float;
uniform float level;
void main() {
    gl_FragColor = vec4(level);
}
