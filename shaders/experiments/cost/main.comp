#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require

// Experiment: a cost heat-map. Replaces main.comp: counts the ray/primitive
// tests each pixel makes (eye rays, reflections and shadow rays) through the
// ON_TEST() hook that intersect.glsl calls, and shows the count per eye ray
// on a log scale: dark blue for 1 test, red around 100, white for 10000 and more.
//
//   glint render scenes/seed-fig5.toml -I shaders/experiments/cost -o cost.png

uint cost = 0u;
#define ON_TEST() cost++

#include "bindings.glsl"
#include "ray.glsl"
#include "intersect.glsl"
#include "shade.glsl"
#include "trace.glsl"
#include "budget.glsl"

vec3 ramp(float t) {
    vec3 a = mix(vec3(0.05, 0.05, 0.3), vec3(0.9, 0.1, 0.1), clamp(t * 2.0, 0.0, 1.0));
    return mix(a, vec3(1.0), clamp(t * 2.0 - 1.0, 0.0, 1.0));
}

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
    float per_ray = float(cost) / float(samples * samples);
    pixels[local.y * tile.rect.z + local.x] = vec4(ramp(log2(1.0 + per_ray) / log2(10001.0)), loops_completed() ? 1.0 : 0.0);
}
