// The binding interface between the host and the shader. The structs,
// blocks, binding numbers and workgroup size are declared once on the host
// and generated into interface.glsl for each variant (src/gpu/generated.rs;
// `glint shader dump` shows it); this file sets up what they are written in.
//
// Precision: the arithmetic type `real` and its vectors are float, or double
// where the host defines GLINT_F64 (then the scene is uploaded in doubles).
#ifdef GLINT_F64
#define real double
#define vec2r dvec2
#define vec3r dvec3
#define vec4r dvec4
#else
#define real float
#define vec2r vec2
#define vec3r vec3
#define vec4r vec4
#endif

// The scene's arrays, declared by the host in interface.glsl with one
// accessor each (sphere_at(i), material_at(i), node_at(i), ...): uniform
// blocks where they fit the device's uniform range (the host then defines
// SCENE_IN_UNIFORMS and each array's length, <NAME>_SLOTS), else texel
// buffers, else storage buffers (src/gpu/access.rs).

#include "interface.glsl"

// Features. For a scene's own variant the host defines each HAS_* to 0 or 1
// and the counts, depth and samples as constants (src/gpu/variant.rs); left
// undefined, every feature is on and the counts are read at run time: that
// is the generic shader (--generic). interface.glsl does the same for each
// kind of primitive (HAS_SPHERES, SPHERES_COUNT, ...) and each light type
// (HAS_POINT, ...; HAS_LIGHTS, HAS_POSITIONED).
#ifndef HAS_ATTENUATION
#define HAS_ATTENUATION 1
#endif
#ifndef HAS_SHADOWS
#define HAS_SHADOWS 1
#endif
#ifndef HAS_TRANSMISSION
#define HAS_TRANSMISSION 1
#endif
#ifndef SHADOWS_ON
#define SHADOWS_ON (g.lights.y != 0u)
#endif
#ifndef HAS_TEXTURES
#define HAS_TEXTURES 1
#endif
#ifndef HAS_IMAGES
#define HAS_IMAGES 1
#endif
#ifndef HAS_UVS
#define HAS_UVS 1
#endif
#ifndef SPD_RAYS
#define SPD_RAYS (g.lights.z != 0u)
#endif
#ifndef MAX_DEPTH
#define MAX_DEPTH g.size.w
// The refraction stack's size: the deepest any scene may be (MAX_DEPTH in
// src/scene/mod.rs); a variant sizes it to its own depth.
#define STACK_SIZE 64u
#else
#define STACK_SIZE MAX_DEPTH
#endif
#ifndef SAMPLES
#define SAMPLES g.size.z
#endif
#ifndef LIGHT_COUNT
#define LIGHT_COUNT g.lights.x
#endif

// A hook called once per ray/primitive test; empty unless a user's shader
// defines it (shaders/experiments/cost counts the tests with it).
#ifndef ON_TEST
#define ON_TEST()
#endif

#include "count.glsl"

// UNROLL_LOOPS unrolls the loops over the scene, which makes every buffer
// offset a constant: llvmpipe then loads each value once for all lanes
// instead of lane by lane.
#ifdef UNROLL_LOOPS
#define SCENE_LOOP [[unroll]]
#else
#define SCENE_LOOP
#endif

// The lights' loop is unrolled with the others, or alone where the lights
// are few and in a uniform block while the primitives are not (the host
// defines UNROLL_LIGHTS).
#if defined(UNROLL_LOOPS) || defined(UNROLL_LIGHTS)
#define LIGHT_LOOP [[unroll]]
#else
#define LIGHT_LOOP
#endif

const real INF = real(uintBitsToFloat(0x7f800000u));
const uint NONE = 0xffffffffu;
