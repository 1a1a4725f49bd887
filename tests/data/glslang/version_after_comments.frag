// the preprocessor takes #version from the first token: these are comments
// #version 330 core
/* written for
#version 450 core */
#version 100
precision mediump float;
void main() {
    gl_FragColor = vec4(1.0);
}
