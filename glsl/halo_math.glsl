#pragma halo library
// Shared helpers for libhalo stage modules. Each function is emitted into a linked
// shader only when a stage calls it. They exist because GLSL leaves pow, normalize and
// division undefined at the edges, and drivers differ there (llvmpipe: pow(0.0, 0.0) = 0,
// pow(-1.0, 2.0) = NaN, denormals flushed to zero). libhalo/emu/math.c mirrors every
// helper in double precision with the same thresholds.

// clamp(x, 0, 1).
float halo_saturate(float x)
{
    return clamp(x, 0.0, 1.0);
}

// x^e with C's pow(0, 0) = 1; a base at or below zero gives 0 (e != 0) instead of NaN.
// A whole exponent 1..64 (alpha = 32, profile exponents) multiplies by repeated squaring,
// and e = 1/2, 1/4, 1/8 (beta = 0.125) takes square roots: with a compile-time exponent
// the branches and the loop fold into a few multiplications (g^32: 5) or roots, where pow
// is exp2(e log2 x) with its approximations (on llvmpipe the 1/8 power costs about 6 ms of
// an 86 ms march, docs/performance.md). All are within a few float ulps of x^e; the
// emulation keeps the exact pow (docs/accuracy.md).
float halo_pow(float x, float e)
{
    if (x <= 0.0)
        return e == 0.0 ? 1.0 : 0.0;
    if (e == 0.5)
        return sqrt(x);
    if (e == 0.25)
        return sqrt(sqrt(x));
    if (e == 0.125)
        return sqrt(sqrt(sqrt(x)));
    if (e >= 1.0 && e <= 64.0 && e == floor(e)) {
        int n = int(e);
        float result = 1.0, power = x;
        for (int bit = 0; bit < 7; ++bit) {
            if ((n & (1 << bit)) != 0)
                result *= power;
            power *= power;
        }
        return result;
    }
    return pow(x, e);
}

// v / |v|, or the zero vector where |v| <= 1e-10 (no direction to speak of).
vec3 halo_normalize(vec3 v)
{
    float length_squared = dot(v, v);
    if (length_squared <= 1.0e-20)
        return vec3(0.0);
    return v * inversesqrt(length_squared);
}

// dot(a, b) clamped to [-1, 1]: for unit vectors, rounding can step past +-1, which
// would make 1 - |a.b| negative and its power undefined.
float halo_dot_clamped(vec3 a, vec3 b)
{
    return clamp(dot(a, b), -1.0, 1.0);
}

// Linear RGB to HSV, every component in [0, 1] (hue in turns). A grey has hue 0 and
// saturation 0; black has saturation 0 (no division by a zero chroma or maximum).
vec3 halo_rgb_to_hsv(vec3 rgb)
{
    float maximum = max(rgb.r, max(rgb.g, rgb.b));
    float minimum = min(rgb.r, min(rgb.g, rgb.b));
    float chroma = maximum - minimum;
    float hue = 0.0;
    if (chroma > 0.0) {
        if (maximum == rgb.r)
            hue = (rgb.g - rgb.b) / chroma;
        else if (maximum == rgb.g)
            hue = 2.0 + (rgb.b - rgb.r) / chroma;
        else
            hue = 4.0 + (rgb.r - rgb.g) / chroma;
        hue = hue / 6.0;
        if (hue < 0.0)
            hue = hue + 1.0;
    }
    float saturation = maximum > 0.0 ? chroma / maximum : 0.0;
    return vec3(hue, saturation, maximum);
}

// HSV (hue in turns, wrapped) to linear RGB. The sector index is kept in 0..5 even
// where rounding makes hue * 6 reach 6 (or the hue is not finite).
vec3 halo_hsv_to_rgb(vec3 hsv)
{
    float hue = (hsv.x - floor(hsv.x)) * 6.0;
    if (!(hue >= 0.0 && hue < 6.0))
        hue = 0.0;
    float saturation = halo_saturate(hsv.y);
    float value = hsv.z;
    float sector = floor(hue);
    float fraction = hue - sector;
    float p = value * (1.0 - saturation);
    float q = value * (1.0 - saturation * fraction);
    float t = value * (1.0 - saturation * (1.0 - fraction));
    int index = int(sector);
    if (index == 0)
        return vec3(value, t, p);
    if (index == 1)
        return vec3(q, value, p);
    if (index == 2)
        return vec3(p, value, t);
    if (index == 3)
        return vec3(p, q, value);
    if (index == 4)
        return vec3(t, p, value);
    return vec3(value, p, q);
}
