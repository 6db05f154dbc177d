#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require

// Experiment: how deep each pixel's BVH walks stack their children, and how
// often they visit. Replaces main.comp: every pixel's red value is the most
// entries the walk's stack held in any ray of its tree (eye, reflection,
// refraction and shadow rays), through the ON_PUSH() hook that bvh.glsl calls
// after each visit's pushes; its green value the iterations of the walks' loops
// that visited inner nodes, through the ON_NODE() hook (with -D PAIR_VISIT a
// visit to two nodes counts once, where --stats counts two). Render it to a PFM
// to read the counts:
//
//   glint render scenes/spd/gears.nff -I shaders/experiments/stack -o stack.pfm

uint deepest = 0u;
#define ON_PUSH(depth) deepest = max(deepest, depth)
uint visits = 0u;
#define ON_NODE() visits++

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
    pixels[local.y * tile.rect.z + local.x] = vec4(float(deepest), float(visits), 0.0, loops_completed() ? 1.0 : 0.0);
}
