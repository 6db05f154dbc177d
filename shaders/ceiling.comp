#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require

// The device's ceiling for the ray-sphere test (glint bench;
// docs/performance.md): each invocation runs CEILING_TESTS of the
// variant's own sphere_intersect against spheres made in registers, with no
// scene memory read, and writes their sum so that no test is left out.
// glint bench divides the tests by the dispatch time, and a scene's tests
// per second by that.

#ifndef CEILING_TESTS
#define CEILING_TESTS 8192u
#endif

#include "bindings.glsl"
#include "ray.glsl"
#include "intersect.glsl"
#include "budget.glsl"

void main() {
    uvec2 local = gl_GlobalInvocationID.xy;
    if (local.x >= tile.rect.z || local.y >= tile.rect.w) {
        return;
    }
    Ray r = primary_ray(tile.rect.x + local.x, tile.rect.y + local.y, 0u, 0u);
    real sum = 0.0;
    [[dont_unroll]] for (uint i = 0u; i < CEILING_TESTS / 8u; i++) {
        [[unroll]] for (uint j = 0u; j < 8u; j++) {
            // A sphere of its own each test, so that none can be hoisted or merged.
            Sphere s = Sphere(vec4r(real(j) * 0.25 - 1.0, real(i) * 1e-4 - 0.1, -6.0, 1.0), uvec4(0u));
            sum += max(sphere_intersect(r, s, false), 0.0);
        }
    }
    pixels[local.y * tile.rect.z + local.x] = vec4(vec3(sum), loops_completed() ? 1.0 : 0.0);
}
