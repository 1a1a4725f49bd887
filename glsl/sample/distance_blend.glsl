#pragma halo module distance_blend
#pragma halo summary "distance colour blending: samples recede into the background colour with depth"
#pragma halo hook sample
#pragma halo after tone_shading orientation_fade sketch
#pragma halo param background vec3 default=[0,0,0.15] min=0 max=1 "colour distant samples blend into, c_b (linear RGB)"
#pragma halo param k_ds float default=1 min=0 max=1 "size of the blending at the back of the volume (fraction)"
#pragma halo param k_de float default=0.5 min=0 max=64 "rate of blending: exponent on the normalized depth (dimensionless)"

// c_d = (1 - k_ds d^k_de) c_v + k_ds d^k_de c_b, d = normalized depth clamped to [0, 1].
// Ebert & Rheingans 2000, Sec. 5.1; defaults from Fig. 6 (whose caption writes k_se
// for k_de). The IVIS form (Svakhine & Ebert 2003, Sec. 3.2) is k_ds = 1, k_de = 1.

void apply(inout halo_sample s)
{
    float t = k_ds * halo_pow(halo_saturate(s.depth), k_de);
    s.color = mix(s.color, background, t);
}
