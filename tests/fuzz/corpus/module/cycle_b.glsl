#pragma halo module cycle_b
#pragma halo hook sample
#pragma halo after cycle_a

void apply(inout halo_sample s)
{
    s.opacity = s.opacity * 0.25;
}
