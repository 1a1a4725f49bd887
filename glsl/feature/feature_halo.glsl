#pragma halo module feature_halo
#pragma halo summary "feature halos: samples just outside strong features get darker and more opaque (halo buffer from halo_feature.h)"
#pragma halo hook sample
#pragma halo needs gradient_magnitude
#pragma halo after opacity_power boundary silhouette orientation_fade tone_shading
#pragma halo param opacity_gain float default=2 min=0 max=1000 "c1: opacity added per unit of halo effect (dimensionless; the halo effect is in [0,1])"
#pragma halo param darkening float default=4 min=0 max=1000 "c2: fraction of the brightness removed per unit of halo effect (dimensionless)"
#pragma halo param k_hpe float default=1 min=0.01 max=64 "halo buffer: how directly a neighbour's normal must point at the sample (Fig. 6: 1)"
#pragma halo param k_hse float default=2 min=0.01 max=64 "halo buffer: how tightly halos stay in the plane facing the viewer (Fig. 6: 2)"
#pragma halo param splat_size int default=5 min=3 max=9 "halo buffer: the neighbourhood is the n x n x n cube (odd, voxels)"
#pragma halo param threshold float default=0.1 min=-1 max=1 "halo buffer: low-gradient cutoff, |grad f| in value per voxel step; negative: none"
#pragma halo param half_resolution bool default=0 "halo buffer at half resolution"
#pragma halo param gradient_weighted bool default=1 "halo buffer: weight each neighbour by |grad f|^k_hpe (IVIS Eq. 2)"
#pragma halo host_uniform feature_buffer sampler3D "the halo buffer: R32F 3D texture over the volume's texture space holding the normalized neighbour sum (halo_feature_buffer_texture); bind it and set this sampler's unit"

// Feature halos, Ebert & Rheingans 2000, Sec. 5.2; Svakhine & Ebert 2003, Eq. 1:
//   h_i = ( sum_n w_n h_n ) (1 - |grad f(P_i)|),
// with the sum (w_n = 1/|P_i - P_n|^2, normalized to sum 1 over the splat) precomputed
// for the current view in the halo buffer (docs/feature-halos.md). Applied as the
// paper does: opacity += c1 h, brightness -= c2 h (as a factor, so the hue is kept and
// the colour never turns negative), both clamped to [0, 1].

// The parameters marked "halo buffer" are not used here: the host reads them
// (halo_feature_desc_from_program) to build the buffer, so a scene describes the whole
// halo.

void apply(inout halo_sample s)
{
    // textureLod: the buffer has no mipmaps and the lookup sits in the host's loop.
    float influence = max(textureLod(halo_host_feature_buffer, s.position, 0.0).r, 0.0);
    float halo = influence * halo_saturate(1.0 - s.gradient_magnitude);
    s.opacity = halo_saturate(s.opacity + opacity_gain * halo);
    s.color = s.color * halo_saturate(1.0 - darkening * halo);
}
