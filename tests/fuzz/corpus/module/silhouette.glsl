#pragma halo module silhouette
#pragma halo summary "silhouette enhancement: more opacity where the normal is perpendicular to the view"
#pragma halo hook sample
#pragma halo needs normal
#pragma halo after opacity_power boundary
#pragma halo param k_sc float default=0.9 min=0 max=1000 "fraction of the original opacity kept in non-silhouette regions (dimensionless)"
#pragma halo param k_ss float default=50 min=0 max=1000 "amount of silhouette enhancement (dimensionless)"
#pragma halo param k_se float default=0.25 min=0 max=64 "sharpness of the silhouette curve (exponent, dimensionless)"

// o_s = o_v (k_sc + k_ss (1 - |n.V|)^k_se), clamped to [0, 1].
// Ebert & Rheingans 2000, Sec. 4.2; defaults from Fig. 4. The IVIS form
// o_e = o_o (1 - |n.V|)^p (Svakhine & Ebert 2003, Sec. 3.2) is k_sc = 0, k_ss = 1, k_se = p.
// A sample without a gradient has no orientation, hence no silhouette: o = o_v k_sc.

void apply(inout halo_sample s)
{
    float silhouette = 0.0;
    if (s.normal != vec3(0.0)) {
        float facing = abs(halo_dot_clamped(s.normal, s.view));
        silhouette = k_ss * halo_pow(1.0 - facing, k_se);
    }
    s.opacity = halo_saturate(s.opacity * (k_sc + silhouette));
}
