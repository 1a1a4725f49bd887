#version 330 core
// The gradient texture built on the GPU from the volume texture (host_common.c,
// halo_host_build_gradients): one layer per draw, one texel per fragment. The voxels'
// central differences per voxel step, g = (v[i+1] - v[i-1]) / 2, the neighbour
// clamped at the faces, exactly as the CPU builds them (examples/volume.c,
// halo_volume_gradients_slab); stored as g * inverse_scale (1, or one over the volume's
// largest |component| for formats that need the range).

uniform highp sampler3D volume_texture;
uniform int layer;
uniform float inverse_scale;
uniform bool to_half; // the texture is half floats: round here, to the nearest (ties to even)
uniform bool pack_value; // RGBA16_SNORM, RGBA32F (halo_host_build_packed): R the value, (value - x) * y, GBA g
uniform vec2 value_encode;

layout(location = 0) out vec4 gradient;

// x rounded to the nearest half float, ties to even: what the CPU path's conversion
// gives. Drivers convert a half render target's output in their own way (llvmpipe
// truncates); a value that is already a half float converts exactly in any of them.
float nearest_half(float x)
{
    if (abs(x) < 6.103515625e-05) // below 2^-14, half's subnormals: a fixed step of 2^-24
        return roundEven(x * 16777216.0) * 5.9604644775390625e-08;
    uint bits = floatBitsToUint(x);
    bits += 0x0FFFu + ((bits >> 13) & 1u); // 13 of float's 23 fraction bits go
    return uintBitsToFloat(bits & ~0x1FFFu);
}

float voxel(ivec3 at)
{
    return texelFetch(volume_texture, at, 0).r;
}

void main()
{
    ivec3 last = textureSize(volume_texture, 0) - 1;
    ivec3 at = ivec3(ivec2(gl_FragCoord.xy), layer);
    vec3 g;
    for (int k = 0; k < 3; ++k) {
        ivec3 step = ivec3(k == 0 ? 1 : 0, k == 1 ? 1 : 0, k == 2 ? 1 : 0);
        // (plus - minus) * 0.5 and then the scale, in the CPU's order: both products exact
        // or rounded once, the same floats
        g[k] = (voxel(min(at + step, last)) - voxel(max(at - step, ivec3(0)))) * 0.5;
    }
    g *= inverse_scale;
    if (to_half)
        g = vec3(nearest_half(g.x), nearest_half(g.y), nearest_half(g.z));
    gradient = pack_value ? vec4((voxel(at) - value_encode.x) * value_encode.y, g) : vec4(g, 0.0);
}
