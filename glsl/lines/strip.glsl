#pragma halo module line_strip
#pragma halo summary "view-aligned line strip: moves each duplicated polyline vertex sideways, perpendicular to the line and the view, with depth-attenuated, tapered width"
#pragma halo hook line_vertex
#pragma halo host_uniform depth_range vec2 "distance from the eye to the front and to the back of the line data's bounding sphere (world units); (0, 0) = unset: no depth attenuation"
#pragma halo is strip_width=strip_width
#pragma halo param strip_width float default=0.03 min=0 max=10 "strip width w_strip (line core and halo together), as a multiple of the host's length unit v.width"
#pragma halo param depth_attenuation float default=0.5 min=0 max=1 "fraction of the width lost at the back of the data (normalized depth 1); 0 = constant width"
#pragma halo param taper float default=0.1 min=0 max=0.5 "length of the taper at each line end, in the line's parameter u (0 = no taper)"
#pragma halo param taper_end float default=0.25 min=0 max=1 "fraction of the width left at the very ends of a line (u = 0 and 1)"

// p_out = p_in + S (v - 0.5) w,  S = (V x D) / |V x D|,
// w = w_strip * v.width * (1 - depth_attenuation * depth) * taper(u),
// taper(u) = mix(taper_end, 1, saturate(min(u, 1 - u) / taper)).
// Everts, Bekker, Roerdink & Isenberg 2009, "Depth-dependent halos" (strip construction:
// p_out = p_in + ||V x D|| (v - 0.5) w_strip). A point plus a scalar is undefined, so the
// slide's ||V x D|| is read as the normalized cross product: the strip has its full width
// whatever the angle between the line and the view. Depth attenuation and tapering are
// the paper's "depth-attenuated line width" and "tapering"; their linear forms are ours.
// Where V x D vanishes (a line pointing at the eye, a zero-length segment: D = 0) there
// is no side direction; any direction perpendicular to V is as good as another, so the
// strip opens towards the coordinate axis least aligned with V (stable, never NaN).

vec3 side_direction(vec3 view, vec3 direction)
{
    vec3 side = cross(view, direction);
    float side_squared = dot(side, side);
    // |V x D| <= 1e-6: below that, float rounding alone decides the direction.
    if (side_squared > 1.0e-12)
        return side * inversesqrt(side_squared);
    vec3 magnitude = abs(view);
    vec3 axis = vec3(0.0, 0.0, 1.0);
    if (magnitude.x <= magnitude.y && magnitude.x <= magnitude.z)
        axis = vec3(1.0, 0.0, 0.0);
    else if (magnitude.y <= magnitude.z)
        axis = vec3(0.0, 1.0, 0.0);
    return halo_normalize(cross(view, axis));
}

// Normalized depth of a point: 0 at the front of the data, 1 at its back (distance from
// the eye); 0 when the host set no range.
float vertex_depth(vec3 position, vec3 eye)
{
    float extent = halo_host_depth_range.y - halo_host_depth_range.x;
    if (!(extent > 0.0))
        return 0.0;
    return halo_saturate((length(position - eye) - halo_host_depth_range.x) / extent);
}

// taper_end at a line end, rising linearly to 1 at distance `taper` (in u) from it.
float taper_factor(float u)
{
    if (!(taper > 0.0))
        return 1.0;
    return mix(taper_end, 1.0, halo_saturate(min(u, 1.0 - u) / taper));
}

// D scaled by its largest component first, so that neither a huge nor a tiny D
// overflows or underflows in dot(D, D).
vec3 unit_direction(vec3 direction)
{
    vec3 magnitude = abs(direction);
    float largest = max(magnitude.x, max(magnitude.y, magnitude.z));
    if (!(largest > 0.0))
        return vec3(0.0);
    return halo_normalize(direction / largest);
}

void apply(inout halo_line_vertex v)
{
    vec3 view = halo_normalize(v.eye - v.position);
    vec3 side = side_direction(view, unit_direction(v.direction));
    float attenuation = 1.0 - depth_attenuation * vertex_depth(v.position, v.eye);
    float strip = strip_width * v.width * attenuation * taper_factor(v.uv.x);
    v.position = v.position + side * ((v.uv.y - 0.5) * strip);
    v.width = strip;
}
