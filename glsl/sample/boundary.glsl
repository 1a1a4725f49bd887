#pragma halo module boundary
#pragma halo summary "boundary enhancement: more opacity where the gradient is strong"
#pragma halo hook sample
#pragma halo is keeps_empty
#pragma halo needs gradient_magnitude
#pragma halo after opacity_power
#pragma halo param k_gc float default=0.7 min=0 max=1000 "fraction of the original opacity kept everywhere (dimensionless)"
#pragma halo param k_gs float default=10 min=0 max=1000 "scale of the gradient enhancement (dimensionless)"
#pragma halo param k_ge float default=2 min=0 max=64 "exponent on the gradient magnitude (dimensionless; |grad f| in value per voxel)"

// o_g = o_v (k_gc + k_gs |grad f|^k_ge), clamped to [0, 1].
// Ebert & Rheingans 2000, Sec. 4.1; defaults from Fig. 3. The IVIS form
// o_e = o_o |grad f|^p (Svakhine & Ebert 2003, Sec. 3.2) is k_gc = 0, k_gs = 1, k_ge = p.

void apply(inout halo_sample s)
{
    float enhancement = k_gc + k_gs * halo_pow(s.gradient_magnitude, k_ge);
    s.opacity = halo_saturate(s.opacity * enhancement);
}
