#pragma halo module tone_shading
#pragma halo summary "tone shading: warm towards the lights, cool away from them, plus diffuse light"
#pragma halo hook sample
#pragma halo needs normal
#pragma halo after orientation_fade sketch
#pragma halo param k_ty float default=0.3 min=0 max=1 "yellow of the warm tone c_w = (k_ty, k_ty, 0) (linear RGB)"
#pragma halo param k_tb float default=0.3 min=0 max=1 "blue of the cool tone c_c = (0, 0, k_tb) (linear RGB)"
#pragma halo param k_ta float default=1 min=0 max=10 "weight of the classified (unlit) colour (dimensionless)"
#pragma halo param k_td float default=0.6 min=0 max=10 "weight of the directed diffuse light (dimensionless)"
#pragma halo param lights vec3[4] default=[[0.577,0.577,0.577]] min=-1 max=1 "directions towards the lights, in the space of view (normalized here)"

// c = k_ta c_v + sum over lights of (I_t + k_td I_o), with
// I_t = ((1 + n.L)/2) c_w + (1 - (1 + n.L)/2) c_c, c_w = (k_ty, k_ty, 0), c_c = (0, 0, k_tb),
// I_o = c_v max(n.L, 0).
// Ebert & Rheingans 2000, Sec. 5.3; defaults from Figs. 7 and 8. The paper writes k_td
// both in the sum and in I_o; it is applied once here. Without a gradient, n.L = 0:
// half warm, half cool, no diffuse term. The result is not clamped.

void apply(inout halo_sample s)
{
    vec3 warm = vec3(k_ty, k_ty, 0.0);
    vec3 cool = vec3(0.0, 0.0, k_tb);
    vec3 color = k_ta * s.color;
    for (int i = 0; i < lights_count; ++i) {
        float n_dot_l = halo_dot_clamped(s.normal, halo_normalize(lights[i]));
        float toward = (1.0 + n_dot_l) * 0.5;
        color += toward * warm + (1.0 - toward) * cool + k_td * s.color * max(n_dot_l, 0.0);
    }
    s.color = color;
}
