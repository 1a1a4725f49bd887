#pragma halo module t_seed
#pragma halo hook sample
#pragma halo needs gradient_magnitude
#pragma halo provides seed channels
#pragma halo output seed max
#pragma halo param alpha channels default=32 min=0 max=64 "a"
void apply(inout halo_sample s) {
    s.seed = halo_channels(s.gradient_magnitude) * alpha;
}
