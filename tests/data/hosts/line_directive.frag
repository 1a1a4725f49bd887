#version 330 core
// A host assembled from parts: #line says where its main comes from.
#pragma halo declarations
out vec4 fragment_color;
#line 200
void main()
{
    vec4 color = vec3(0.8, 0.6, 0.4);
#ifdef HALO_LINKED
    halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.1, 0.2, 0.3), vec3(0.0, 0.0, 1.0), 0.5,
                                     gl_FragCoord.xy, color.rgb, color.a);
    halo_apply(s);
    color = vec4(s.color, s.opacity);
#endif
    fragment_color = color;
}
