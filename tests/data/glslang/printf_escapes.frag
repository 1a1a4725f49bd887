#version 450
#extension GL_EXT_debug_printf : enable
// The escapes in a debugPrintfEXT string are the parser's to read, as written: the
// preprocessor's output rewrites them.
layout(location = 0) out vec4 color;
void main() {
    debugPrintfEXT("value\t%f\\ \"quoted\" \x41\102\?\n", 0.5);
    color = vec4(1.0);
}
