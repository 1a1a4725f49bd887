#version 330 core
// A host whose output has no location, linked with stages that add outputs.
#pragma halo declarations
out vec4 fragment_color;
void main()
{
    vec4 color = vec4(0.8, 0.6, 0.4, 0.5);
#ifdef HALO_LINKED
    halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.1, 0.2, 0.3), vec3(0.0, 0.0, 1.0), 0.5,
                                     gl_FragCoord.xy, color.rgb, color.a);
    halo_apply(s);
    color = vec4(s.color, s.opacity);
    halo_finish();
#endif
    fragment_color = color;
}
