#pragma halo module outlines
#pragma halo summary "outlines and depth enhancement: depth and normal unsharp masks per feature, occlusion styles, line colour, depth colour blending, cueing, blurring and line fading (end of frame)"
#pragma halo hook image
#pragma halo needs feature_depth feature_normal occluder_depth
#pragma halo groups
#pragma halo provides final image
#pragma halo provides importance image
#pragma halo image feature_depth clear=1
#pragma halo image feature_normal* components=4
#pragma halo image occluder_depth components=1 clear=1
#pragma halo image host_color components=4
#pragma halo image depth_blur_x
#pragma halo image depth_blur
#pragma halo image depth_min_x clear=1
#pragma halo image depth_min clear=1
#pragma halo image normal_blur_x* components=4
#pragma halo image normal_blur* components=4
#pragma halo image importance
#pragma halo image reduced components=4 clear=1 reset=frame-only
#pragma halo image final_blur_x components=4
#pragma halo image final components=4
#pragma halo param sigma float default=6 min=0 max=600 "kernel size sigma of the depth unsharp mask G_sigma (the paper's: the full width of the Gaussian, 6 standard deviations), percent of the image diagonal (paper: about 2.5)"
#pragma halo param lambda channels default=4 min=0 max=1000 "darkening strength lambda of I = lambda (dD-)^p, per feature"
#pragma halo param depth_power channels default=1 min=0.01 max=8 "p of I = lambda (dD-)^p (p < 1 brings out small depth steps; paper: 0.6)"
#pragma halo param normal_difference bool default=false "normal measure: screen-space central differences dN = (1 - n(x+1).n(x-1)) + (1 - n(y+1).n(y-1))"
#pragma halo param normal_unsharp bool default=false "normal measure: unsharp mask dN = 1 - (G_sigmaN * n).n"
#pragma halo param normal_sigma float default=12 min=0 max=600 "kernel size sigma_N of the normal unsharp mask (full width, 6 standard deviations), percent of the image diagonal"
#pragma halo param normal_min channels default=0.2 min=0 max=4 "n_min: dN below gives I_N = 0"
#pragma halo param normal_max channels default=0.8 min=0 max=4 "n_max: dN above gives I_N = 1 (n_min = n_max: a step)"
#pragma halo param normal_power channels default=1 min=0.01 max=8 "p_N: I_N = ((dN - n_min) / (n_max - n_min))^p_N between"
#pragma halo param occluded channels default=0 min=0 max=2 "outline where an occluder lies in front of the feature: 0 hidden, 1 dashed, 2 forced to the front"
#pragma halo param occlusion_bias float default=0.02 min=0 max=1 "the occluder must lie this much (normalized depth) in front of the feature"
#pragma halo param dash_length float default=6 min=1 max=256 "dashes of occluded outlines: on and off this many pixels along x + y"
#pragma halo param line_color_mode int default=0 min=0 max=2 "outline colour: 0 line_color, 1 background_fraction times the colour behind, 2 white on dark / black on light (brightness < 0.5)"
#pragma halo param line_color vec3 default=[0,0,0] min=0 max=1 "outline colour of mode 0 (linear RGB)"
#pragma halo param background_fraction float default=0.5 min=0 max=1 "phi of mode 1: C_I = phi C_back"
#pragma halo param depth_start float default=1 min=0 max=1 "d_start: gamma = 0 in front of it, (d - d_start) / (1 - d_start) behind (1: no depth effects)"
#pragma halo param depth_correction bool default=true "outline pixels over the background take gamma of d_min, the nearest depth in the kernel neighbourhood"
#pragma halo param depth_color_blend bool default=false "depth colour blending: c = lerp(c, depth_color, gamma)"
#pragma halo param depth_color vec3 default=[1,1,1] min=0 max=1 "colour at the maximum depth (often the background)"
#pragma halo param depth_cue bool default=false "depth cueing: c = lerp(c, gray, gamma)"
#pragma halo param cue_gray float default=0.5 min=0 max=1 "the grey of depth cueing"
#pragma halo param depth_blur bool default=false "depth blurring: Gaussian of kernel size lerp(1 px, blur_max, gamma)"
#pragma halo param blur_max float default=3 min=0 max=100 "kernel size K_max at gamma = 1 (full width, 6 standard deviations, as sigma), percent of the image diagonal (paper: 1-10)"
#pragma halo param line_fading bool default=false "line fading: I = lerp(I, 0, gamma)"
#pragma halo pass depth_blur_x entry=blur_x_pass inputs=feature_depth output=depth_blur_x at=post
#pragma halo pass depth_blur_y entry=blur_y_pass inputs=depth_blur_x output=depth_blur at=post
#pragma halo pass depth_min_x entry=min_x_pass inputs=feature_depth output=depth_min_x at=post
#pragma halo pass depth_min_y entry=min_y_pass inputs=depth_min_x output=depth_min at=post
#pragma halo pass normal_blur_x entry=normal_blur_x_pass inputs=feature_normal* output=normal_blur_x* each=channel when=normal_unsharp at=post
#pragma halo pass normal_blur_y entry=normal_blur_y_pass inputs=normal_blur_x* output=normal_blur* each=channel when=normal_unsharp at=post
#pragma halo pass importance entry=importance_pass inputs=feature_depth,depth_blur,depth_min,occluder_depth,feature_normal*,normal_blur* output=importance at=post
#pragma halo pass reduce entry=reduce_pass inputs=importance,feature_depth,depth_min,reduced output=reduced at=post
#pragma halo pass compose entry=compose_pass inputs=host_color,reduced output=final at=final
#pragma halo pass final_blur_x entry=final_blur_x_pass inputs=final,reduced output=final_blur_x when=depth_blur at=final
#pragma halo pass final_blur_y entry=final_blur_y_pass inputs=final_blur_x,reduced output=final when=depth_blur at=final

// Outlines and depth enhancement (Svakhine, Ebert & Andrews 2009, Eqs. 1-17; Luft et al.
// 2006; docs/outlines.md, docs/blur.md). Every pass runs once at the end of the frame.
//   dD = G_sigma * D - D;  I = lambda (dD-)^p                                  (Eqs. 1, 4)
//   dN = (1 - n(x+1).n(x-1)) + (1 - n(y+1).n(y-1))  or  1 - (G_sigmaN * n).n   (Eqs. 5, 6)
//   I_N = 0 / ((dN - n_min)/(n_max - n_min))^p_N / 1;  importance max(I, I_N)  (Eq. 7)
//   gamma = 0 for d < d_start, (d - d_start)/(1 - d_start) behind              (Eq. 8)
//   colour lerp(c, c_depth, gamma), lerp(c, gray, gamma); kernel lerp(1, K_max, gamma);
//   I = lerp(I, 0, gamma)                                                      (Eqs. 10-14)
// Gaussians: separable, truncated at 3 standard deviations, weights renormalized over the
// taps inside the image (a constant image stays constant up to the border). Every kernel
// is given by its size, as in the paper ("the size of the filtering kernel sigma"): the
// full width of the truncated Gaussian, 6 standard deviations (sigma, normal_sigma and
// blur_max alike; docs/outlines.md).

const int max_radius = 1024;

float diagonal_pixels(float percent)
{
    vec2 size = vec2(halo_image_size());
    return percent * 0.01 * length(size);
}

// The standard deviation, in pixels, of a kernel of this size (percent of the diagonal).
float deviation_pixels(float kernel_size)
{
    return diagonal_pixels(kernel_size / 6.0);
}

// Radius of a Gaussian truncated at 3 sigma; no further than the image reaches.
int kernel_radius(float sigma)
{
    ivec2 size = halo_image_size();
    return int(min(ceil(3.0 * sigma), float(min(max(size.x, size.y), max_radius))));
}

float gauss(int i, float sigma)
{
    float x = float(i) / sigma;
    return exp(-0.5 * x * x);
}

bool inside(ivec2 p)
{
    ivec2 size = halo_image_size();
    return p.x >= 0 && p.y >= 0 && p.x < size.x && p.y < size.y;
}

// One separable Gaussian pass of input k along axis; the centre tap always counts.
// taper: weights exp(-x^2/2) - exp(-4.5), so that the tap at the 3 sigma cut has weight
// 0 and the blur is continuous in sigma (the per-pixel sigma of depth blurring: without
// it, a pixel whose 3 sigma crosses an integer gains two taps of weight 0.011 at once).
float tapered(int i, float sigma, bool taper)
{
    return taper ? max(gauss(i, sigma) - exp(-4.5), 0.0) : gauss(i, sigma);
}

vec4 blur_axis_tapered(int k, ivec2 pixel, ivec2 axis, float sigma, bool taper)
{
    if (sigma < 1.0e-3)
        return halo_input4(k, pixel);
    int r = kernel_radius(sigma);
    vec4 sum = vec4(0.0);
    float weight = 0.0;
    for (int i = -r; i <= r; ++i) {
        ivec2 p = pixel + i * axis;
        if (!inside(p))
            continue;
        float w = tapered(i, sigma, taper);
        sum += w * halo_input4(k, p);
        weight += w;
    }
    return sum / weight;
}

vec4 blur_axis(int k, ivec2 pixel, ivec2 axis, float sigma)
{
    return blur_axis_tapered(k, pixel, axis, sigma, false);
}

vec4 min_axis(int k, ivec2 pixel, ivec2 axis, float sigma)
{
    int r = sigma < 1.0e-3 ? 0 : kernel_radius(sigma);
    vec4 m = halo_input4(k, pixel);
    for (int i = -r; i <= r; ++i) {
        ivec2 p = pixel + i * axis;
        if (inside(p))
            m = min(m, halo_input4(k, p));
    }
    return m;
}

halo_channels blur_x_pass(ivec2 pixel)
{
    return halo_channels_from(blur_axis(0, pixel, ivec2(1, 0), deviation_pixels(sigma)));
}

halo_channels blur_y_pass(ivec2 pixel)
{
    return halo_channels_from(blur_axis(0, pixel, ivec2(0, 1), deviation_pixels(sigma)));
}

halo_channels min_x_pass(ivec2 pixel)
{
    return halo_channels_from(min_axis(0, pixel, ivec2(1, 0), deviation_pixels(sigma)));
}

halo_channels min_y_pass(ivec2 pixel)
{
    return halo_channels_from(min_axis(0, pixel, ivec2(0, 1), deviation_pixels(sigma)));
}

vec4 normal_blur_x_pass(ivec2 pixel)
{
    return blur_axis(0, pixel, ivec2(1, 0), deviation_pixels(normal_sigma));
}

vec4 normal_blur_y_pass(ivec2 pixel)
{
    return blur_axis(0, pixel, ivec2(0, 1), deviation_pixels(normal_sigma));
}

// gamma(d), Eq. 8; d_start = 1 gives 0 (no division by zero).
float depth_gamma(float d)
{
    if (d < depth_start || depth_start >= 1.0)
        return 0.0;
    return clamp((d - depth_start) / (1.0 - depth_start), 0.0, 1.0);
}

// 1 - a.b of two (normal, hit) texels: 0 where neither is a hit, 1 - 0 where one is.
float normal_change(vec4 a, vec4 b)
{
    if (a.w <= 0.0 && b.w <= 0.0)
        return 0.0;
    return 1.0 - dot(halo_normalize(a.xyz), halo_normalize(b.xyz));
}

float normal_importance(int k, float dn)
{
    float lo = halo_channel(normal_min, k), hi = halo_channel(normal_max, k);
    if (dn < lo)
        return 0.0;
    if (hi <= lo || dn > hi)
        return 1.0;
    return halo_pow((dn - lo) / (hi - lo), halo_channel(normal_power, k));
}

// The feature's depth at a pixel: its own, or (outline pixels over the background) d_min.
float feature_depth_at(float d, float d_min)
{
    return d >= 1.0 && depth_correction ? d_min : d;
}

halo_channels importance_pass(ivec2 pixel)
{
    vec4 result = vec4(0.0);
    halo_channels D = halo_input(0, pixel), B = halo_input(1, pixel), M = halo_input(2, pixel);
    float occluder = halo_input4(3, pixel).x;
    for (int k = 0; k < halo_channel_count; ++k) {
        float negative = max(0.0, halo_channel(D, k) - halo_channel(B, k)); // (G*D - D)-
        float I = clamp(halo_channel(lambda, k) * halo_pow(negative, halo_channel(depth_power, k)), 0.0, 1.0);
        float dn = 0.0;
        if (normal_difference) {
            int n = 4 + k;
            dn = max(dn, normal_change(halo_input4(n, pixel + ivec2(1, 0)), halo_input4(n, pixel - ivec2(1, 0))) +
                             normal_change(halo_input4(n, pixel + ivec2(0, 1)), halo_input4(n, pixel - ivec2(0, 1))));
        }
        if (normal_unsharp) {
            vec4 n = halo_input4(4 + k, pixel);
            if (n.w > 0.0)
                dn = max(dn, 1.0 - dot(halo_input4(4 + halo_channel_count + k, pixel).xyz, halo_normalize(n.xyz)));
        }
        if (normal_difference || normal_unsharp)
            I = max(I, normal_importance(k, dn));
        float d_min = halo_channel(M, k);
        // occlusion styles: something opaque in front of the feature's (neighbourhood) depth
        if (I > 0.0 && d_min < 1.0 && occluder < d_min - occlusion_bias) {
            float style = halo_channel(occluded, k);
            if (style < 0.5)
                I = 0.0;
            else if (style < 1.5 && ((pixel.x + pixel.y) / int(dash_length)) % 2 == 1)
                I = 0.0;
        }
        if (line_fading)
            I = mix(I, 0.0, depth_gamma(feature_depth_at(halo_channel(D, k), d_min)));
        result[k] = I;
    }
    return halo_channels_from(result);
}

// gamma at depth d (the front-most feature's), nearest depth d_min and outline I.
// Outline pixels over the background (d = 1, Sec. 4.1.1) are line in the share I and
// background in 1 - I: gamma(d_min) and gamma(1) mixed by I. A switch (I > 0, or any
// threshold) would jump where the blur's exp() tails are zero in one precision and not
// in the other; the mix is continuous in I, with slope at most 1.
float border_gamma(float d, float d_min, float I)
{
    if (d < 1.0 || !depth_correction)
        return depth_gamma(d);
    return mix(depth_gamma(d), depth_gamma(d_min), clamp(I, 0.0, 1.0));
}

// The features of a group reduced to what the end of the frame needs, folded (min) into
// the frame's accumulator over the feature groups (docs/image-passes.md): 1 - the
// largest outline I, the front-most feature depth d, the nearest depth d_min.
vec4 reduce_pass(ivec2 pixel)
{
    halo_channels I = halo_input(0, pixel), D = halo_input(1, pixel), M = halo_input(2, pixel);
    float line = 0.0, d = 1.0, d_min = 1.0;
    for (int k = 0; k < halo_channel_count; ++k) {
        line = max(line, halo_channel(I, k));
        d = min(d, halo_channel(D, k));
        d_min = min(d_min, halo_channel(M, k));
    }
    return min(halo_input4(3, pixel), vec4(1.0 - line, d, d_min, 1.0));
}

// gamma of a pixel (input 1: the reduced features): the front-most feature; outline
// pixels over the background use d_min.
float pixel_gamma(ivec2 pixel)
{
    vec4 r = halo_input4(1, pixel);
    return border_gamma(r.y, r.z, 1.0 - r.x);
}

vec4 compose_pass(ivec2 pixel)
{
    vec3 back = halo_input4(0, pixel).rgb;
    vec3 c = back;
    vec4 r = halo_input4(1, pixel);
    float I = 1.0 - r.x;
    float gamma = border_gamma(r.y, r.z, I);
    if (depth_color_blend)
        c = mix(c, depth_color, gamma);
    if (depth_cue)
        c = mix(c, vec3(cue_gray), gamma);
    vec3 line;
    if (line_color_mode == 1)
        line = background_fraction * back;
    else if (line_color_mode == 2)
        line = dot(back, vec3(0.2126, 0.7152, 0.0722)) < 0.5 ? vec3(1.0) : vec3(0.0);
    else
        line = line_color;
    return vec4(mix(c, line, I), 1.0);
}

float final_sigma(ivec2 pixel)
{
    // kernel size (pixels, 6 standard deviations) lerp(1, K_max, gamma): 1 px is no blur
    float size = mix(1.0, diagonal_pixels(blur_max), pixel_gamma(pixel));
    return size <= 1.0 ? 0.0 : size / 6.0;
}

vec4 final_blur_x_pass(ivec2 pixel)
{
    return vec4(blur_axis_tapered(0, pixel, ivec2(1, 0), final_sigma(pixel), true).rgb, 1.0);
}

vec4 final_blur_y_pass(ivec2 pixel)
{
    return vec4(blur_axis_tapered(0, pixel, ivec2(0, 1), final_sigma(pixel), true).rgb, 1.0);
}
