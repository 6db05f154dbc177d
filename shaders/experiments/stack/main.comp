#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require

// Experiment: how deep each pixel's BVH walks stack their children
// (issue 58). Replaces main.comp: every pixel's value is the most entries
// the walk's stack held in any ray of its tree (eye, reflection,
// refraction and shadow rays), through the ON_PUSH() hook that bvh.glsl
// calls after each visit's pushes. Render it to a PFM to read the counts:
//
//   glint render scenes/spd/gears.nff -I shaders/experiments/stack -o stack.pfm

uint deepest = 0u;
#define ON_PUSH(depth) deepest = max(deepest, depth)

#include "bindings.glsl"
#include "ray.glsl"
#include "intersect.glsl"
#include "shade.glsl"
#include "trace.glsl"
#include "budget.glsl"

void main() {
    uvec2 local = gl_GlobalInvocationID.xy;
    if (local.x >= tile.rect.z || local.y >= tile.rect.w) {
        return;
    }
    uint x = tile.rect.x + local.x;
    uint y = tile.rect.y + local.y;
    uint samples = SAMPLES;
    for (uint j = 0u; j < samples; j++) {
        for (uint i = 0u; i < samples; i++) {
            trace(primary_ray(x, y, i, j));
        }
    }
    pixels[local.y * tile.rect.z + local.x] = vec4(vec3(float(deepest)), loops_completed() ? 1.0 : 0.0);
}
