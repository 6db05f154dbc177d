// The binding interface between the host (src/gpu/layout.rs) and the shader.
//
// Precision: the arithmetic type `real` and its vectors are float, or double
// where the host defines GLINT_F64 (then the scene is uploaded in doubles).
#ifdef GLINT_F64
#define real double
#define vec3r dvec3
#define vec4r dvec4
#else
#define real float
#define vec3r vec3
#define vec4r vec4
#endif

// All buffers are std430 except the std140 uniform block; every struct is
// made of vec4/uvec4 so both layouts agree with the host's Pod structs.

struct Sphere {
    vec4r center_radius;     // xyz centre, w radius
    uvec4 meta;             // x material index
};

struct Plane {
    vec4r point;             // xyz
    vec4r normal;            // xyz, unit length
    uvec4 meta;             // x material index
};

struct Material {
    vec4r ambient;           // rgb Ka
    vec4r diffuse;           // rgb Kd
    vec4r specular;          // rgb Ks
    vec4r params;            // x shininess, y reflectivity
};

const uint LIGHT_POINT = 0u;
const uint LIGHT_DIRECTIONAL = 1u;
const uint LIGHT_SPOT = 2u;

struct Light {
    vec4r position;          // xyz (point, spot)
    vec4r direction;         // xyz unit (directional: travel; spot: axis)
    vec4r ambient;           // rgb Ia
    vec4r diffuse;           // rgb Id
    vec4r specular;          // rgb Is
    vec4r attenuation;       // xyz = c, l, q
    vec4r spot;              // x cos(cutoff), y exponent
    uvec4 meta;             // x LIGHT_*, y 1 if it has a diffuse or specular term
};

layout(std140, set = 0, binding = 0) uniform Globals {
    vec4r eye;               // xyz
    vec4r to_screen;         // xyz screen_center - eye, taken in f64 on the host
    vec4r screen_right;      // xyz
    vec4r screen_up;         // xyz
    vec4r background;        // rgb
    uvec4 size;             // width, height, samples, max_depth
    uvec4 counts;           // spheres, planes, lights, shadows (0 or 1)
} g;

// Features. For a scene's own variant the host defines each HAS_* to 0 or 1
// and the counts, depth and samples as constants (src/gpu/variant.rs); left
// undefined, every feature is on and the counts are read at run time: that
// is the generic shader (--generic).
#ifndef HAS_SPHERES
#define HAS_SPHERES 1
#endif
#ifndef HAS_PLANES
#define HAS_PLANES 1
#endif
#ifndef HAS_POINT
#define HAS_POINT 1
#endif
#ifndef HAS_DIRECTIONAL
#define HAS_DIRECTIONAL 1
#endif
#ifndef HAS_SPOT
#define HAS_SPOT 1
#endif
#ifndef HAS_ATTENUATION
#define HAS_ATTENUATION 1
#endif
#ifndef HAS_SHADOWS
#define HAS_SHADOWS 1
#endif
#ifndef SHADOWS_ON
#define SHADOWS_ON (g.counts.w != 0u)
#endif
#ifndef MAX_DEPTH
#define MAX_DEPTH g.size.w
#endif
#ifndef SAMPLES
#define SAMPLES g.size.z
#endif
#define HAS_LIGHTS (HAS_POINT != 0 || HAS_DIRECTIONAL != 0 || HAS_SPOT != 0)
#define HAS_POSITIONED (HAS_POINT != 0 || HAS_SPOT != 0)
#define HAS_OBJECTS (HAS_SPHERES != 0 || HAS_PLANES != 0)

// A hook called once per ray/primitive test; empty unless a user's shader
// defines it (shaders/experiments/cost counts the tests with it).
#ifndef ON_TEST
#define ON_TEST()
#endif

// The scene's arrays, each declared only where the variant reads it. Where
// they fit the device's uniform buffer range the host defines
// SCENE_IN_UNIFORMS and each array's length: llvmpipe (and many GPUs) read a
// uniform buffer at a dynamically uniform offset with one scalar load, where
// a storage buffer read under divergent control flow becomes a loop over the
// lanes. Otherwise they are storage buffers of any length.
#ifdef SCENE_IN_UNIFORMS
#define SCENE_BLOCK(n) layout(std140, set = 0, binding = n) uniform
#define SLOTS(n) n
#else
#define SCENE_BLOCK(n) layout(std430, set = 0, binding = n) readonly buffer
#define SLOTS(n)
#endif
// Binding numbers: dense for a scene's variant (the host numbers only the
// blocks it declares), fixed for the generic shader.
#ifndef SPHERES_BINDING
#define SPHERES_BINDING 1
#endif
#ifndef PLANES_BINDING
#define PLANES_BINDING 2
#endif
#ifndef MATERIALS_BINDING
#define MATERIALS_BINDING 3
#endif
#ifndef LIGHTS_BINDING
#define LIGHTS_BINDING 4
#endif
#ifndef PIXELS_BINDING
#define PIXELS_BINDING 5
#endif
#if HAS_SPHERES
SCENE_BLOCK(SPHERES_BINDING) Spheres { Sphere spheres[SLOTS(SPHERE_SLOTS)]; };
#endif
#if HAS_PLANES
SCENE_BLOCK(PLANES_BINDING) Planes { Plane planes[SLOTS(PLANE_SLOTS)]; };
#endif
#if HAS_OBJECTS
SCENE_BLOCK(MATERIALS_BINDING) Materials { Material materials[SLOTS(MATERIAL_SLOTS)]; };
#endif
#if HAS_LIGHTS
SCENE_BLOCK(LIGHTS_BINDING) Lights { Light lights[SLOTS(LIGHT_SLOTS)]; };
#endif

// Linear RGB (alpha unused) of the tile being rendered, row-major.
layout(std430, set = 0, binding = PIXELS_BINDING) writeonly buffer Pixels { vec4 pixels[]; };

// The tile: origin x, origin y, width, height, in image pixels.
layout(push_constant) uniform Tile { uvec4 rect; } tile;

// The loop bounds: constants where the host defines them (with the scene in
// uniforms), else the counts in the uniform block. UNROLL_LOOPS unrolls the
// loops over the scene, which makes every buffer offset a constant: llvmpipe
// then loads each value once for all lanes instead of lane by lane.
#ifndef SPHERE_COUNT
#define SPHERE_COUNT g.counts.x
#define PLANE_COUNT g.counts.y
#define LIGHT_COUNT g.counts.z
#endif
#ifdef UNROLL_LOOPS
#define SCENE_LOOP [[unroll]]
#else
#define SCENE_LOOP
#endif

const real INF = real(uintBitsToFloat(0x7f800000u));
const uint NONE = 0xffffffffu;
