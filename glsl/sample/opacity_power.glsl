#pragma halo module opacity_power
#pragma halo summary "opacity as a power of the scaled scalar value"
#pragma halo hook sample
#pragma halo param k_os float default=1 min=0 max=1000 "scale applied to the value before the power (1/value units)"
#pragma halo param k_oe float default=1 min=0 max=64 "exponent of the opacity curve (dimensionless)"

// o = clamp((k_os v)^k_oe, 0, 1), replacing the classified opacity.
// Ebert & Rheingans 2000, Sec. 4.1 (o_v from a simple power transfer function).

void apply(inout halo_sample s)
{
    s.opacity = halo_saturate(halo_pow(k_os * s.value, k_oe));
}
