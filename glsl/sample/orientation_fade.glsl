#pragma halo module orientation_fade
#pragma halo summary "orientation fading: samples facing the viewer fade and desaturate, those turned away darken"
#pragma halo hook sample
#pragma halo needs normal
#pragma halo after opacity_power
#pragma halo param k_fo float default=0.5 min=0 max=1 "opacity removed from samples facing the viewer (fraction)"
#pragma halo param k_fs float default=0.5 min=0 max=1 "saturation removed from samples facing the viewer (fraction)"
#pragma halo param k_fv float default=0.3 min=0 max=1 "HSV value removed from samples turned away from the viewer (fraction)"
#pragma halo param k_fe float default=1 min=0 max=64 "exponent on |n.V|: higher keeps the fading to samples facing the viewer squarely (dimensionless)"

// facing = |n.V|^k_fe; o *= 1 - k_fo facing; in HSV: S *= 1 - k_fs facing,
// V *= 1 - k_fv (1 - facing).
// Ebert & Rheingans 2000, Sec. 4.2 (oriented fading; Figs. 9 and 10): structures
// facing the viewer are desaturated, structures turned away are darkened.
// A sample without a gradient has no orientation and is left unchanged.

void apply(inout halo_sample s)
{
    if (s.normal == vec3(0.0))
        return;
    float facing = halo_pow(abs(halo_dot_clamped(s.normal, s.view)), k_fe);
    s.opacity = s.opacity * (1.0 - k_fo * facing);
    vec3 hsv = halo_rgb_to_hsv(s.color);
    hsv.y = hsv.y * (1.0 - k_fs * facing);
    hsv.z = hsv.z * (1.0 - k_fv * (1.0 - facing));
    s.color = halo_hsv_to_rgb(hsv);
}
