#version 330 core
// Example slab ray caster (beyond Bruckner & Groller 2007, measured against their
// slicing): one draw advances every ray by up to slab_samples samples. The samples
// lie on the slice host's planes (slice.frag): sample k of every ray is where its
// pixel's ray meets the plane slice_distance = first_distance + k * step_size along
// the view axis, so slab and slice renderers sample the same points and, with the
// same generation interval, see the same halo images. Per ray the accumulated
// premultiplied colour and opacity live in an RGBA32F texture that the host
// ping-pongs between slabs (ray_state in, frag_state out); the ray parameter is
// implied by the slab's first plane, the same for every ray. The extra outputs of
// halo stages accumulate over the slab's samples, as the seed image accumulates the
// slices between two generations in the slice host.

#pragma halo declarations
#pragma halo slices

uniform highp sampler3D volume_texture;
uniform highp sampler2D transfer_texture;
uniform highp sampler3D gradient_texture; // the voxels' central-difference gradients / gradient_texture_scale (slice.frag)
uniform float gradient_texture_scale;     // 1, or the texture's scale (slice.frag)
uniform highp sampler2D ray_state;        // RGBA32F: premultiplied colour, opacity so far
uniform mat4 inverse_view_projection;
uniform vec3 eye;
uniform vec3 view_axis;
uniform float first_distance;             // plane of this slab's first sample
uniform int slab_samples;                 // samples in this slab (M, fewer at the end)
uniform float step_size;
uniform float unit_step;

in vec2 ndc;
layout(location = 0) out vec4 frag_state;

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
    float cosine = dot(direction, view_axis);
    float origin_distance = dot(origin - eye, view_axis);

    const float radius = 0.8660254037844386;
    float front_distance = distance(eye, vec3(0.5)) - radius;
    float opacity_exponent = step_size / (cosine * unit_step);

    vec4 accumulated = texelFetch(ray_state, ivec2(gl_FragCoord.xy), 0);
    for (int i = 0; i < slab_samples; ++i) {
        float slice_distance = first_distance + float(i) * step_size;
        float t = (slice_distance - origin_distance) / cosine;
        vec3 P = origin + t * direction;
        bool inside = all(greaterThanEqual(P, vec3(0.0))) && all(lessThanEqual(P, vec3(1.0)));
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
        if (alpha > 0.0) {
            alpha = 1.0 - pow(1.0 - alpha, opacity_exponent);
            accumulated.rgb += (1.0 - accumulated.a) * alpha * color.rgb;
            accumulated.a += (1.0 - accumulated.a) * alpha;
        }
    }
    frag_state = accumulated;
#ifdef HALO_LINKED
    halo_finish();
#endif
}
