#version 440
// glslang 12 crashes on an atomic function given an rvalue
void main() {
    uint counter = 3u;
    atomicMax(counter + 1u, 7u);
}
