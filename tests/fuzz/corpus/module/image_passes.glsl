#pragma halo module t_gen
#pragma halo hook image
#pragma halo needs seed
#pragma halo provides field image
#pragma halo image seed reset=generation
#pragma halo image initial
#pragma halo image field
#pragma halo param passes int default=4 min=1 max=8 "N"
#pragma halo param delta channels default=[0.8,0.9] min=0 max=1 "d"
#pragma halo pass gradient entry=gradient_pass inputs=seed output=initial
#pragma halo pass spread entry=spread_pass inputs=previous,initial output=field repeat=passes first=initial
halo_channels gradient_pass(ivec2 p) { return abs(halo_input(0, p + ivec2(1,0)) - halo_input(0, p - ivec2(1,0))); }
halo_channels spread_pass(ivec2 p) {
    int k = 1 << (halo_pass_count - halo_pass_index);
    halo_channels f = halo_input(0, p + ivec2(k, 0));
    return delta * f + (halo_channels(1.0) - delta * f) * halo_input(1, p);
}
