#pragma halo module cycle_a
#pragma halo hook sample
#pragma halo after cycle_b

void apply(inout halo_sample s)
{
    s.opacity = s.opacity * 0.5;
}
