#pragma halo module distance_cue
#pragma halo summary "distance colour cue: tints samples by a colour map of their depth"
#pragma halo hook sample
#pragma halo after tone_shading orientation_fade sketch distance_blend
#pragma halo param colors vec3[8] default=[[1,0.9,0.7],[0.55,0.65,1]] min=0 max=1 "colour map from front to back, evenly spaced over depth 0..1 (linear RGB)"
#pragma halo param k_cm float default=1 min=0 max=1 "strength of the tint (fraction)"

// c = c_v * mix(1, map(d), k_cm), map = piecewise-linear through colors[0 .. count-1]
// placed evenly over d in [0, 1]; one colour is a constant tint.
// Svakhine & Ebert 2003, Sec. 3.2 (distance colour cues: depth through an arbitrary map).

vec3 depth_map(float d)
{
    if (colors_count < 1)
        return vec3(1.0);
    if (colors_count == 1)
        return colors[0];
    float x = d * float(colors_count - 1);
    int i = int(floor(x));
    if (i > colors_count - 2)
        i = colors_count - 2;
    if (i < 0)
        i = 0;
    return mix(colors[i], colors[i + 1], x - float(i));
}

void apply(inout halo_sample s)
{
    vec3 tint = depth_map(halo_saturate(s.depth));
    s.color = s.color * mix(vec3(1.0), tint, k_cm);
}
