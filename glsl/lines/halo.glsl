#pragma halo module line_halo
#pragma halo summary "depth-dependent halo: line colour in the strip's core, background colour at its sides, depth pushed back away from the centre"
#pragma halo hook line_fragment
#pragma halo is core_fraction=core
#pragma halo param core float default=0.4 min=0 max=1 "width of the line core, as a fraction of the strip width; the rest is halo"
#pragma halo param d_max float default=0.05 min=0 max=1 "largest depth displacement, reached at the strip's edge (normalized depth: a fraction of the data's depth extent)"
#pragma halo param profile int default=0 min=0 max=2 "displacement function f: 0 linear f(x) = x, 1 smooth f(x) = 3x^2 - 2x^3, 2 step (0 in the core, 1 in the halo)"

// x = 2 |v - 0.5| (0 at the strip's centre, 1 at its edges);
// x < core: the line (host colour), else the halo (background colour);
// d_new = d_old + d_max f(x).
// Everts, Bekker, Roerdink & Isenberg 2009, "Depth manipulation (fragment shader)".
// A halo hides another line only where that line lies more than about d_max behind;
// closer lines show through it and merge into bundles. The host writes
// gl_FragDepth = f.depth, so the depth test does the rest.

float displacement(float x)
{
    if (profile == 1)
        return x * x * (3.0 - 2.0 * x);
    if (profile == 2)
        return x < core ? 0.0 : 1.0;
    return x;
}

void apply(inout halo_line_fragment f)
{
    float x = halo_saturate(2.0 * abs(f.uv.y - 0.5));
    if (!(x < core)) {
        f.color = f.background;
        f.opacity = 1.0;
    }
    f.depth = f.depth + d_max * displacement(x);
}
