#pragma halo module halo_generate
#pragma halo summary "volumetric halos, generation: spreads the gradient of the seed image into the halo field and the occlusion image"
#pragma halo hook image
#pragma halo is keeps_empty zero_generation interval=interval
#pragma halo needs seed
#pragma halo provides field image
#pragma halo provides occlusion image
#pragma halo image seed reset=generation
#pragma halo image initial
#pragma halo image field
#pragma halo image occlusion
#pragma halo param passes int default=4 min=1 max=8 "N: spreading passes; pass i reads at distance 2^(N-i) pixels (reach 2^N - 1)"
#pragma halo param delta channels default=0.8 min=0 max=1 "spreading amount (0: the seed gradient only; paper's Fig. 4: 0.70..0.95)"
#pragma halo param median bool default=false "3x3 median filter on the seed image before spreading"
#pragma halo param interval int default=4 min=1 max=64 "M: slices between two generations (read by hosts from the reflection)"
#pragma halo param wide bool default=false "approximation: each spreading pass does two of the paper's steps at once (49 taps at spacing 4^(N-i), one H_0 blend): N passes reach 4^N - 1 pixels, like 2N exact ones"
#pragma halo param fold bool default=false "at the frame's size, H_0 computed at the first spreading pass's nine taps instead of stored by a pass of its own: one draw fewer a generation; pass 1 reads 36 seed texels a pixel instead of 10, later passes 13 instead of 10 (the same floats; slower on llvmpipe at 256^2: docs/performance.md)"
#pragma halo pass median entry=median_pass inputs=seed output=seed when=median reach=1
#pragma halo pass gradient entry=gradient_pass inputs=seed output=initial when=!halo_full_size reach=1
#pragma halo pass gradient entry=gradient_pass inputs=seed output=initial when=halo_full_size,!fold reach=1
#pragma halo pass gradient entry=gradient_pass inputs=seed output=initial when=halo_full_size,fold,wide reach=1
#pragma halo pass spread entry=spread_pass inputs=previous,initial output=field repeat=passes first=initial when=!halo_full_size,!wide reach=2^(passes-i)
#pragma halo pass spread entry=spread_pass inputs=previous,initial output=field repeat=passes first=initial when=halo_full_size,!fold,!wide reach=2^(passes-i)
#pragma halo pass spread_seed entry=spread_seed_pass inputs=seed output=field when=halo_full_size,fold,!wide reach=2^(passes-i)+1
#pragma halo pass spread entry=spread_on_pass inputs=previous,seed output=field repeat=passes start=2 when=halo_full_size,fold,!wide reach=2^(passes-i)
#pragma halo pass spread_wide entry=spread_wide_pass inputs=previous,initial output=field repeat=passes first=initial when=wide reach=3*4^(passes-i)
#pragma halo pass occlude entry=occlusion_pass inputs=field,occlusion output=occlusion reach=0 running=associative

// Volumetric halos, step 2 (Bruckner & Groller 2007, Sec. 3.2; docs/stages/halo_generate.md):
//   H_0 = |grad S| (central differences, not halved, clamped to [0, 1]);
//   F_i(p) = sum over u, v in {-1, 0, 1} of w(u, v) H_{i-1}(p + k (u, v)), k = 2^(N - i)
//   (max(1, 2^(N - i) / s) on images at 1/s of the frame: docs/image-passes.md),
//   w = [1 2 1; 2 4 2; 1 2 1] / 16;  H_i = delta F_i + (1 - delta F_i) H_0;
//   O = max(O, H_N) (occlusion image, for occlusive halos).
// wide (an approximation): pass i applies the kernels at spacing 2s and s at once, s = 4^(N - i)
//   (max(1, 4^(N - i) / s_frame) on images at 1/s_frame): separable, per axis [1 2 3 4 3 2 1]/16
//   at -3s..3s (49 taps), then H_i = delta F_i + (1 - delta F_i) H_0 once (H_0 stored).
// Every channel is one halo. Pixels outside the image read as 0 (halo_input).
// fold, at the frame's size (halo_full_size): H_0 is not stored; the first spreading pass
// reads it at its nine taps from the seed image, the others at their pixel (the same sums:
// the same floats, one draw fewer per generation, 36 texel reads a pixel instead of 10 in
// pass 1 and 13 instead of 10 in the others, against the gradient pass's 4). Halo images at
// 1/s of the frame keep the gradient pass, which also max-downsamples the seed.

// Median of nine (insertion sort; no arithmetic, so the emulation matches bit for bit).
float median9(float v[9])
{
    for (int i = 1; i < 9; ++i) {
        float x = v[i];
        int j = i - 1;
        while (j >= 0 && v[j] > x) {
            v[j + 1] = v[j];
            --j;
        }
        v[j + 1] = x;
    }
    return v[4];
}

halo_channels median_pass(ivec2 pixel)
{
    vec4 result = vec4(0.0);
    for (int c = 0; c < halo_channel_count; ++c) {
        float v[9];
        for (int i = 0; i < 9; ++i)
            v[i] = halo_channel(halo_input(0, pixel + ivec2(i % 3 - 1, i / 3 - 1)), c);
        result[c] = median9(v);
    }
    return halo_channels_from(result);
}

// H_0 at pixel from the seed image, input k; 0 outside the image, as a stored H_0 reads there.
halo_channels seed_gradient(int k, ivec2 pixel)
{
    if (any(greaterThanEqual(uvec2(pixel), uvec2(halo_image_size())))) // also pixel < 0
        return halo_channels(0.0);
    halo_channels gx = halo_input(k, pixel + ivec2(1, 0)) - halo_input(k, pixel - ivec2(1, 0));
    halo_channels gy = halo_input(k, pixel + ivec2(0, 1)) - halo_input(k, pixel - ivec2(0, 1));
    return clamp(sqrt(gx * gx + gy * gy), 0.0, 1.0);
}

halo_channels gradient_pass(ivec2 pixel)
{
    return seed_gradient(0, pixel);
}

// Pass i of N: 2^(N - i) frame pixels; on a 1/s image (halo_link_desc.image_scale)
// 2^(N - i) / s of its pixels, and at least 1: the reach stays about 2^N frame pixels
int spread_distance(int i)
{
    return max(1, (1 << (passes - i)) / halo_pass_scale);
}

// H_i from F_i (the nine taps' weighted sum) and H_0.
halo_channels spread_step(halo_channels corners, halo_channels edges, halo_channels centre, halo_channels initial)
{
    halo_channels f = (corners + 2.0 * edges + 4.0 * centre) * (1.0 / 16.0);
    halo_channels spread = delta * f;
    return spread + (halo_channels(1.0) - spread) * initial;
}

// H_{i-1} (input 0) at the eight outer taps, k pixels away.
void previous_taps(ivec2 pixel, int k, out halo_channels corners, out halo_channels edges)
{
    corners = halo_input(0, pixel + ivec2(-k, -k)) + halo_input(0, pixel + ivec2(k, -k)) +
              halo_input(0, pixel + ivec2(-k, k)) + halo_input(0, pixel + ivec2(k, k));
    edges = halo_input(0, pixel + ivec2(0, -k)) + halo_input(0, pixel + ivec2(-k, 0)) +
            halo_input(0, pixel + ivec2(k, 0)) + halo_input(0, pixel + ivec2(0, k));
}

halo_channels spread_pass(ivec2 pixel)
{
    halo_channels corners, edges;
    previous_taps(pixel, spread_distance(halo_pass_index), corners, edges);
    return spread_step(corners, edges, halo_input(0, pixel), halo_input(1, pixel));
}

// Pass 1 at the frame's size: H_0 at the nine taps from the seed image (input 0).
halo_channels spread_seed_pass(ivec2 pixel)
{
    int k = spread_distance(1);
    halo_channels corners = seed_gradient(0, pixel + ivec2(-k, -k)) + seed_gradient(0, pixel + ivec2(k, -k)) +
                            seed_gradient(0, pixel + ivec2(-k, k)) + seed_gradient(0, pixel + ivec2(k, k));
    halo_channels edges = seed_gradient(0, pixel + ivec2(0, -k)) + seed_gradient(0, pixel + ivec2(-k, 0)) +
                          seed_gradient(0, pixel + ivec2(k, 0)) + seed_gradient(0, pixel + ivec2(0, k));
    halo_channels centre = seed_gradient(0, pixel);
    return spread_step(corners, edges, centre, centre);
}

// Passes 2..N at the frame's size: H_0 at the pixel from the seed image (input 1).
halo_channels spread_on_pass(ivec2 pixel)
{
    halo_channels corners, edges;
    previous_taps(pixel, spread_distance(halo_pass_index), corners, edges);
    return spread_step(corners, edges, halo_input(0, pixel), seed_gradient(1, pixel));
}

// wide: pass i of N, the two kernels at spacing 2s and s convolved (49 taps of H_{i-1}, input 0),
// s = 4^(N - i) frame pixels; H_0 from input 1.
halo_channels spread_wide_pass(ivec2 pixel)
{
    int s = max(1, (1 << (2 * (passes - halo_pass_index))) / halo_pass_scale);
    const float weights[7] = float[7](1.0, 2.0, 3.0, 4.0, 3.0, 2.0, 1.0);
    halo_channels sum = halo_channels(0.0);
    for (int v = 0; v < 7; ++v) {
        halo_channels row = halo_channels(0.0);
        for (int u = 0; u < 7; ++u)
            row += weights[u] * halo_input(0, pixel + s * ivec2(u - 3, v - 3));
        sum += weights[v] * row;
    }
    halo_channels spread = delta * (sum * (1.0 / 256.0));
    return spread + (halo_channels(1.0) - spread) * halo_input(1, pixel);
}

halo_channels occlusion_pass(ivec2 pixel)
{
    return max(halo_input(0, pixel), halo_input(1, pixel));
}
