#pragma halo module halo_map
#pragma halo summary "volumetric halos, mapping: halo profile to colour and opacity, emissive or occlusive, composited with the sample"
#pragma halo hook sample
#pragma halo is keeps_empty
#pragma halo needs field occlusion
#pragma halo after halo_seed tone_shading distance_blend distance_cue
#pragma halo image field
#pragma halo image occlusion read_when=mode
#pragma halo param mode channels default=0 min=0 max=1 step=1 "0 emissive (composited behind the sample), 1 occlusive (tints the sample); >= 0.5 is occlusive"
#pragma halo param color_near vec3[4] default=[[0,0,0]] min=0 max=1 "halo colour at intensity >= full_at (linear RGB)"
#pragma halo param color_far vec3[4] default=[[0,0,0]] min=0 max=1 "halo colour as the intensity goes to 0 (linear RGB)"
#pragma halo param opacity channels default=1 min=0 max=1 "halo opacity at intensity >= full_at (fraction)"
#pragma halo param full_at channels default=1 min=0.001 max=1 "intensity at which the profile reaches full opacity and color_near"
#pragma halo param profile_exponent channels default=1 min=0 max=64 "opacity profile alpha = opacity t^exponent, t = min(1, H / full_at) (dimensionless)"
#pragma halo per_halo color_near color_far

// Volumetric halos, step 3 (Bruckner & Groller 2007, Sec. 3.3; docs/stages/halo_map.md).
// Profile of halo h at intensity H (field image: emissive; occlusion image: occlusive):
//   H <= 0: transparent; else t = clamp(H / full_at, 0, 1), alpha_h = opacity t^exponent,
//   colour_h = mix(color_far, color_near, t).
// Occlusive halos first, in channel order: c = mix(c, colour_h, alpha_h), opacity kept.
// Then emissive halos, composited behind the sample (front-to-back over, colour not
// premultiplied): a' = a + (1 - a) alpha_h, c' = (a c + (1 - a) alpha_h colour_h) / a'.

void apply(inout halo_sample s)
{
    halo_channels field = halo_read_field(s.fragcoord);
    halo_channels occluding = halo_read_occlusion(s.fragcoord);
    for (int h = 0; h < halo_channel_count; ++h) {
        float H = halo_channel(occluding, h);
        if (halo_channel(mode, h) < 0.5 || H <= 0.0)
            continue;
        float t = clamp(H / halo_channel(full_at, h), 0.0, 1.0);
        float a = halo_channel(opacity, h) * halo_pow(t, halo_channel(profile_exponent, h));
        s.color = mix(s.color, mix(color_far[h], color_near[h], t), a);
    }
    for (int h = 0; h < halo_channel_count; ++h) {
        float H = halo_channel(field, h);
        if (halo_channel(mode, h) >= 0.5 || H <= 0.0)
            continue;
        float t = clamp(H / halo_channel(full_at, h), 0.0, 1.0);
        float a = halo_channel(opacity, h) * halo_pow(t, halo_channel(profile_exponent, h));
        vec3 colour = mix(color_far[h], color_near[h], t);
        float behind = (1.0 - s.opacity) * a;
        float opacity = s.opacity + behind;
        if (opacity > 0.0)
            s.color = (s.opacity * s.color + behind * colour) / opacity;
        s.opacity = opacity;
    }
}
