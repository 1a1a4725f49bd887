#version 330 core
// A single-pass ray caster that never calls halo_segment_begin: it cannot run the
// image passes of volumetric halos (tests/libhalo/gl/link_cli.sh).
#pragma halo declarations
uniform sampler3D volume;
in vec2 ndc;
layout(location = 0) out vec4 color;
void main() {
    vec4 sum = vec4(0.0);
    for (int i = 0; i < 64; ++i) {
        vec3 P = vec3(ndc * 0.5 + 0.5, float(i) / 64.0);
        float v = texture(volume, P).r;
#ifdef HALO_LINKED
        halo_sample s = halo_make_sample(P, v, vec3(0.0), vec3(0.0, 0.0, 1.0), P.z, gl_FragCoord.xy, vec3(v), v);
        halo_apply(s);
        sum += (1.0 - sum.a) * vec4(s.color * s.opacity, s.opacity);
#else
        sum += (1.0 - sum.a) * vec4(vec3(v) * v, v);
#endif
    }
#ifdef HALO_LINKED
    halo_finish();
#endif
    color = sum;
}
