#pragma halo module outline_feature
#pragma halo summary "outlines, feature buffers: per feature (channel) the front-most depth and first-hit normal of its samples, and the occluder depth"
#pragma halo hook sample
#pragma halo is labels_when=label
#pragma halo needs normal
#pragma halo groups
#pragma halo after opacity_power boundary silhouette orientation_fade sketch tone_shading distance_blend distance_cue halo_seed halo_map
#pragma halo provides feature_depth channels
#pragma halo provides feature_normal mat4
#pragma halo provides occluder_depth float
#pragma halo output feature_depth min
#pragma halo output feature_normal first
#pragma halo output occluder_depth min
#pragma halo host_uniform labels sampler3D "segmentation volume (R32F, one integer label per voxel), read nearest at s.position; only for features with label >= 0"
#pragma halo param value_min channels default=0 min=0 max=1 "feature k: smallest value of its value range (tau_k = 1 in [value_min, value_max])"
#pragma halo param value_max channels default=1 min=0 max=1 "feature k: largest value of its value range"
#pragma halo param label channels default=-1 min=-1 max=65535 "feature k: segmentation label id (tau_k = 1 where labels == id); -1: use the value range"
#pragma halo param mask_depth channels default=-1 min=-1 max=1 "feature k: -1 writes the slice depth; a value in [0, 1] writes that constant (mask outline: uniform, no inner lines)"
#pragma halo param occluder_opacity float default=0.5 min=0 max=1 "a sample at least this opaque (transfer opacity per unit step) occludes what lies behind it (occluder depth)"

// Feature buffers (Svakhine, Ebert & Andrews 2009, Sec. 3.1, Eq. 3; docs/outlines.md):
//   D_i = d_slice if tau(P) = 1 and alpha(P) > 0, else D_{i-1};  D_0 = 1.
// The linker folds feature_depth with min (front-most; image cleared to 1), each column
// k of feature_normal, vec4(n, 1) on a hit, with `first` (first hit along the ray wins)
// into image feature_normal_k, and occluder_depth with min.

bool in_feature(int k, halo_sample s)
{
    float id = halo_channel(label, k);
    if (id < 0.0)
        return s.value >= halo_channel(value_min, k) && s.value <= halo_channel(value_max, k);
    if (any(lessThan(s.position, vec3(0.0))) || any(greaterThan(s.position, vec3(1.0))))
        return false;
    ivec3 size = textureSize(halo_host_labels, 0);
    if (any(lessThanEqual(size, ivec3(0))))
        return false;
    ivec3 voxel = clamp(ivec3(floor(s.position * vec3(size))), ivec3(0), size - 1);
    return abs(texelFetch(halo_host_labels, voxel, 0).r - id) < 0.5;
}

void apply(inout halo_sample s)
{
    vec4 depth = vec4(1.0);
    mat4 normals = mat4(0.0);
    if (s.opacity > 0.0) {
        for (int k = 0; k < halo_channel_count; ++k) {
            if (!in_feature(k, s))
                continue;
            float mask = halo_channel(mask_depth, k);
            depth[k] = mask >= 0.0 ? mask : s.depth;
            normals[k] = vec4(s.normal, 1.0);
        }
    }
    s.feature_depth = halo_channels_from(depth);
    s.feature_normal = normals;
    s.occluder_depth = s.opacity >= occluder_opacity && s.opacity > 0.0 ? s.depth : 1.0;
}
