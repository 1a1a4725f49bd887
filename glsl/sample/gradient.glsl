#pragma halo module gradient
#pragma halo summary "gradient magnitude and outward unit normal of the sample"
#pragma halo hook sample
#pragma halo is keeps_empty
#pragma halo provides gradient_magnitude float
#pragma halo provides normal vec3

// |grad f| and n = -grad f / |grad f|, the surface-normal analogue of Ebert & Rheingans
// 2000, Sec. 4 (their normalized gradient, negated so that it points out of dense
// material, as a surface normal does). Where |grad f| <= 1e-10 the direction is
// meaningless and the normal is the zero vector; stages that need an orientation test
// for it.

void apply(inout halo_sample s)
{
    s.gradient_magnitude = length(s.gradient);
    s.normal = -halo_normalize(s.gradient);
}
