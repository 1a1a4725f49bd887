#version 330 core
// Example slice renderer: view-aligned slices drawn front to back, as in Bruckner &
// Groller 2007 (Sec. 4), following the libhalo host contract (docs/host-contract.md).
//
// One draw per slice: a full-screen triangle whose fragments intersect their pixel's
// ray with the slice's plane (perpendicular to the view axis, slice_distance from the
// eye), sample the volume there, run halo_apply once and write the sample's opacity-
// corrected, premultiplied colour. The host composites it front to back by blending
// into colour buffer 0 (glBlendFunci(0, GL_ONE_MINUS_DST_ALPHA, GL_ONE)); the extra
// outputs of halo stages (the seed image) are blended by halo_gl_frame_attach.
// Outside the unit cube the sample is empty (value 0, transparent), but halo_apply
// still runs, so that emissive halos composite over the background.
//
// Same conventions as raycast.frag: positions in volume texture space, gradient per
// voxel step, depth against the bounding sphere, opacities per voxel step.

#pragma halo declarations
#pragma halo slices

uniform highp sampler3D volume_texture;   // R32F, value normalized to [0,1]
uniform highp sampler2D transfer_texture; // N x 1 RGBA: linear RGB and opacity per unit step
uniform highp sampler3D gradient_texture; // central-difference gradient per voxel step at the voxels, / gradient_texture_scale
uniform float gradient_texture_scale;     // RGB8_SNORM (RGB16F beyond [0,1] values): the largest |component|; else 1
uniform mat4 inverse_view_projection;     // clip space -> volume texture space
uniform vec3 eye;                         // eye position in volume texture space
uniform vec3 view_axis;                   // unit view direction (from the eye into the scene)
uniform float slice_distance;             // this slice's plane: dot(P - eye, view_axis) = slice_distance
uniform float step_size;                  // distance between slices along the view axis, texture units
uniform float unit_step;                  // the step the transfer opacities are given for (one voxel)

in vec2 ndc;
layout(location = 0) out vec4 frag_color;

#ifdef SLICE_PACKED_VOLUME
// The slice host's packed gradient formats (packed16: RGBA16_SNORM, packed32: RGBA32F):
// one texture on volume_texture's unit, R the value as (value - packed_value.x) /
// packed_value.y, GBA the gradient / gradient_texture_scale (snorm: a zero gradient is
// code 0, read as exactly 0, so a homogeneous region has no normal in any format). The
// two reads are the same texture read: the compiler keeps one fetch.
uniform vec2 packed_value;

float sample_value(vec3 p)
{
    return packed_value.x + texture(volume_texture, p).r * packed_value.y;
}

vec3 sample_gradient(vec3 p)
{
    return texture(volume_texture, p).gba * gradient_texture_scale;
}
#else
float sample_value(vec3 p)
{
    return texture(volume_texture, p).r;
}

// The gradient per voxel step: the trilinear interpolation of the voxels' central
// differences (the host precomputes them, examples/volume.h halo_volume_gradients),
// which is the central difference of the trilinear field at +-1 voxel, in one RGB fetch
// instead of six scalar ones.
vec3 sample_gradient(vec3 p)
{
    return texture(gradient_texture, p).rgb * gradient_texture_scale;
}
#endif

vec4 classify(float value)
{
    float texels = float(textureSize(transfer_texture, 0).x);
    float u = ((value > 0.0 ? min(value, 1.0) : 0.0) * (texels - 1.0) + 0.5) / texels; // NaN -> 0
    return texture(transfer_texture, vec2(u, 0.5));
}

void main()
{
    vec4 near_point = inverse_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far_point = inverse_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 origin = near_point.xyz / near_point.w;
    vec3 direction = normalize(far_point.xyz / far_point.w - origin);
    // The pixel's ray meets the plane at t; consecutive slices are step_size / cosine
    // apart along the ray, which is the distance the opacity is corrected for.
    float cosine = dot(direction, view_axis);
    float t = (slice_distance - dot(origin - eye, view_axis)) / cosine;
    vec3 P = origin + t * direction;
#ifdef SLICE_OUTSIDE
    // The host's variant for pixels whose ray meets this slice's plane outside the volume
    // (it draws them only where a halo image read can be nonzero): the sample is empty,
    // as the test below gives there, and the compiler drops the volume's fetches.
    const bool inside = false;
#else
    bool inside = all(greaterThanEqual(P, vec3(0.0))) && all(lessThanEqual(P, vec3(1.0)));
#endif

    const float radius = 0.8660254037844386;
    float front_distance = distance(eye, vec3(0.5)) - radius;
    float opacity_exponent = step_size / (cosine * unit_step);

    float value = inside ? sample_value(P) : 0.0;
    vec4 color = inside ? classify(value) : vec4(0.0);
#ifdef HALO_LINKED
    vec3 gradient = inside ? sample_gradient(P) : vec3(0.0);
    vec3 V = normalize(eye - P);
    float depth = clamp((distance(eye, P) - front_distance) / (2.0 * radius), 0.0, 1.0);
    halo_sample s = halo_make_sample(P, value, gradient, V, depth, gl_FragCoord.xy, color.rgb, color.a);
    halo_apply(s);
    color = vec4(s.color, s.opacity);
#endif
    float alpha = clamp(color.a, 0.0, 1.0);
    if (alpha > 0.0)
        alpha = 1.0 - pow(1.0 - alpha, opacity_exponent);
    frag_color = vec4(alpha * color.rgb, alpha);
#ifdef HALO_LINKED
    halo_finish();
#endif
}
