#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#ifdef WAVEFRONT
#extension GL_KHR_shader_subgroup_ballot : require
#endif

// One invocation per pixel of the current tile: the mean of the pixel's
// samples*samples eye rays, each traced to the fixed depth.

#include "bindings.glsl"
#include "ray.glsl"
#include "intersect.glsl"
#include "shade.glsl"
#include "trace.glsl"
#include "budget.glsl"

#ifdef WAVEFRONT
#include "wavefront.glsl"
#elif defined(ADAPTIVE_LEVELS)
// Adaptive sampling's second pass: one invocation per pixel of the list.
#include "adaptive.glsl"

void main() {
    uvec2 local = gl_GlobalInvocationID.xy;
    if (local.x >= tile.rect.z || local.y >= tile.rect.w) {
        return;
    }
    uint index = (tile.rect.y + local.y) * REFINE_WIDTH + tile.rect.x + local.x;
    begin_counts();
    vec3r colour = vec3r(0.0);
    if (index < uint(refine_list.length())) {
        colour = refine_pixel(refine_list[index]);
    }
    pixels[local.y * tile.rect.z + local.x] = vec4(vec3(colour), loops_completed() ? 1.0 : 0.0);
    end_counts();
}
#else
void main() {
    uvec2 local = gl_GlobalInvocationID.xy;
    if (local.x >= tile.rect.z || local.y >= tile.rect.w) {
        return;
    }
    uint x = tile.rect.x + local.x;
    uint y = tile.rect.y + local.y;
    begin_counts();
    uint samples = SAMPLES;
    vec3r sum = vec3r(0.0);
    [[dont_unroll]] for (uint j = 0u; j < samples; j++) {
        [[dont_unroll]] for (uint i = 0u; i < samples; i++) {
            sum += trace(primary_ray(x, y, i, j));
        }
    }
    pixels[local.y * tile.rect.z + local.x] = vec4(vec3(sum * (1.0 / real(samples * samples))), loops_completed() ? 1.0 : 0.0);
    end_counts();
}
#endif
