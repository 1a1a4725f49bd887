#version 150
// An engine's ray-casting template in the style of VTK's: tags the engine replaces with
// libhalo's pieces (tests/validate/pieces_composed.sh composes it with compose.awk).
uniform sampler3D in_volume[1];
uniform vec3 in_step;
out vec4 fragOutput0;
//ENGINE::Declarations
void main() {
    vec3 g_dataPos = vec3(0.0);
    vec3 g_dirStep = in_step;
    vec4 result = vec4(0.0);
    int first = 0, end = 64;
    vec4 state = vec4(0.0);
    halo_segment_begin(g_dataPos, normalize(g_dirStep), 0.0, length(g_dirStep), first, end, state);
    for (int i = first; i < end; ++i) {
        float scalar = texture(in_volume[0], g_dataPos).r;
        vec4 g_srcColor = vec4(scalar, scalar, scalar, 0.1);
//ENGINE::Sample
        result += (1.0 - result.a) * vec4(g_srcColor.rgb * g_srcColor.a, g_srcColor.a);
        g_dataPos += g_dirStep;
    }
    halo_segment_end(state, false);
//ENGINE::Finish
    fragOutput0 = result;
}
