#pragma halo module sketch
#pragma halo summary "sketch lines: only silhouettes remain, drawn in the line colour"
#pragma halo hook sample
#pragma halo needs normal
#pragma halo after opacity_power silhouette boundary orientation_fade
#pragma halo param line_color vec3 default=[1,1,1] min=0 max=1 "colour of the sketch lines (linear RGB)"
#pragma halo param k_ls float default=1 min=0 max=100 "opacity scale of the lines (dimensionless)"
#pragma halo param k_le float default=8 min=0 max=64 "line sharpness: exponent on 1 - |n.V| (dimensionless)"

// line = (1 - |n.V|)^k_le; c = line_color; o = clamp(o_v k_ls line, 0, 1).
// Ebert & Rheingans 2000, Sec. 4.2 and Fig. 5 (white sketch colour, non-silhouettes
// transparent). A sample without a gradient is no line: o = 0.

void apply(inout halo_sample s)
{
    float line = 0.0;
    if (s.normal != vec3(0.0))
        line = halo_pow(1.0 - abs(halo_dot_clamped(s.normal, s.view)), k_le);
    s.color = line_color;
    s.opacity = halo_saturate(s.opacity * k_ls * line);
}
