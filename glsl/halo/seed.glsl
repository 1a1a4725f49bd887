#pragma halo module halo_seed
#pragma halo summary "volumetric halos, seeding: per-halo seed intensity of contour samples, accumulated into the seed image"
#pragma halo hook sample
#pragma halo is keeps_empty
#pragma halo needs normal gradient_magnitude
#pragma halo after opacity_power boundary silhouette orientation_fade sketch
#pragma halo provides seed channels
#pragma halo output seed max
#pragma halo host_uniform screen_right vec3 "unit image-plane +x axis, in the space of view and gradient"
#pragma halo host_uniform screen_up vec3 "unit image-plane +y axis, in the space of view and gradient"
#pragma halo param alpha channels default=32 min=0 max=64 "exponent of the normalized gradient magnitude (dimensionless)"
#pragma halo param beta channels default=0.125 min=0 max=64 "exponent of the contour term 1 - |n.V| (dimensionless)"
#pragma halo param gradient_scale channels default=2 min=0 max=1000 "g = min(1, |grad f| gradient_scale): 1 / the gradient magnitude (per voxel step) of the strongest edge"
#pragma halo param value_0 vec2[8] default=[[0,1],[1,1]] min=0 max=1 "value influence h_v of halo 0: control points (value, weight), piecewise linear, clamped outside"
#pragma halo param value_1 vec2[8] default=[[0,1],[1,1]] min=0 max=1 "value influence h_v of halo 1 (as value_0)"
#pragma halo param value_2 vec2[8] default=[[0,1],[1,1]] min=0 max=1 "value influence h_v of halo 2 (as value_0)"
#pragma halo param value_3 vec2[8] default=[[0,1],[1,1]] min=0 max=1 "value influence h_v of halo 3 (as value_0)"
#pragma halo param direction_center channels default=0 min=-180 max=180 "direction influence h_d: centre direction in degrees, 0 = image +y, 90 = image +x"
#pragma halo param direction_width channels default=360 min=0 max=360 "direction influence h_d: full angular width in degrees (360 = omnidirectional)"
#pragma halo param direction_softness channels default=30 min=0 max=180 "direction influence h_d: width of the soft edge in degrees (0 = hard)"
#pragma halo param focus vec3[4] default=[[0.5,0.5,0.5]] min=-10 max=10 "position influence h_p: focus point per halo (volume texture space)"
#pragma halo param focus_radius channels default=10 min=0 max=10 "position influence h_p: radius of full influence around the focus (texture units; 10 = everywhere)"
#pragma halo param focus_transition channels default=0 min=0 max=10 "position influence h_p: width of the fall-off beyond the radius (texture units; 0 = hard)"
#pragma halo per_halo focus

// Volumetric halos, step 1 (Bruckner & Groller 2007, Sec. 3.1; docs/stages/halo_seed.md):
//   s = clamp(h_v h_d h_p g^alpha (1 - |n.V|)^beta, 0, 1) per halo, g = min(1, |grad f| gradient_scale),
// with h_v a piecewise linear function of the value, h_d of the direction of the normal
// projected on the image plane (angle from image +y), h_p of the distance to a focus point.
// s.seed is folded into the seed image (max) by the linker; the host calls halo_finish().
// Alpha = 32, beta = 0.125 as in all the paper's figures. No gradient direction: s = 0.

// 1 - smoothstep(e0, e1, x), written out so that the C emulation matches it exactly;
// a step (1 where x <= e0) when the edge has no width.
float fall_off(float e0, float e1, float x)
{
    if (e1 <= e0)
        return x <= e0 ? 1.0 : 0.0;
    float t = clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return 1.0 - t * t * (3.0 - 2.0 * t);
}

// h_v: control points (value, weight) in increasing value; clamped outside the first and last.
float value_influence(int h, float v)
{
    vec2 points[8];
    int n = 0;
    if (h == 0) {
        for (int i = 0; i < value_0_count; ++i)
            points[i] = value_0[i];
        n = value_0_count;
    } else if (h == 1) {
        for (int i = 0; i < value_1_count; ++i)
            points[i] = value_1[i];
        n = value_1_count;
    } else if (h == 2) {
        for (int i = 0; i < value_2_count; ++i)
            points[i] = value_2[i];
        n = value_2_count;
    } else {
        for (int i = 0; i < value_3_count; ++i)
            points[i] = value_3[i];
        n = value_3_count;
    }
    if (n < 1)
        return 1.0;
    if (v <= points[0].x)
        return points[0].y;
    for (int i = 1; i < n; ++i) {
        if (v < points[i].x) {
            // v >= points[i - 1].x here (else the previous point returned), so d > 0
            float d = points[i].x - points[i - 1].x;
            return d > 0.0 ? mix(points[i - 1].y, points[i].y, (v - points[i - 1].x) / d) : points[i].y;
        }
    }
    return points[n - 1].y;
}

// h_d: angle of the projected outward normal, degrees from image +y towards +x.
float direction_influence(int h, vec3 n)
{
    float width = halo_channel(direction_width, h);
    if (width >= 360.0)
        return 1.0;
    float x = dot(n, halo_host_screen_right);
    float y = dot(n, halo_host_screen_up);
    if (x * x + y * y < 1.0e-12)
        return 0.0; // seen end-on: no direction in the image
    float theta = degrees(atan(x, y));
    float distance = abs(theta - halo_channel(direction_center, h));
    distance = mod(distance, 360.0);
    if (distance > 180.0)
        distance = 360.0 - distance;
    float softness = halo_channel(direction_softness, h);
    return fall_off(0.5 * width - 0.5 * softness, 0.5 * width + 0.5 * softness, distance);
}

// h_p: distance of the sample to the halo's focus point.
float position_influence(int h, vec3 p)
{
    float r = halo_channel(focus_radius, h);
    return fall_off(r, r + halo_channel(focus_transition, h), length(p - focus[h]));
}

void apply(inout halo_sample s)
{
    vec4 seed = vec4(0.0);
    if (s.normal != vec3(0.0)) {
        float contour = 1.0 - abs(halo_dot_clamped(s.normal, s.view));
        for (int h = 0; h < halo_channel_count; ++h) {
            float g = min(1.0, s.gradient_magnitude * halo_channel(gradient_scale, h));
            float weight = value_influence(h, s.value) * direction_influence(h, s.normal) *
                           position_influence(h, s.position);
            seed[h] = clamp(weight * halo_pow(g, halo_channel(alpha, h)) * halo_pow(contour, halo_channel(beta, h)),
                            0.0, 1.0);
        }
    }
    s.seed = halo_channels_from(seed);
}
