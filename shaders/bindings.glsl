// The binding interface between the host (src/gpu/layout.rs) and the shader.
// All buffers are std430 except the std140 uniform block; every struct is
// made of vec4/uvec4 so both layouts agree with the host's Pod structs.

struct Sphere {
    vec4 center_radius;     // xyz centre, w radius
    uvec4 meta;             // x material index
};

struct Plane {
    vec4 point;             // xyz
    vec4 normal;            // xyz, unit length
    uvec4 meta;             // x material index
};

struct Material {
    vec4 ambient;           // rgb Ka
    vec4 diffuse;           // rgb Kd
    vec4 specular;          // rgb Ks
    vec4 params;            // x shininess, y reflectivity
};

const uint LIGHT_POINT = 0u;
const uint LIGHT_DIRECTIONAL = 1u;
const uint LIGHT_SPOT = 2u;

struct Light {
    vec4 position;          // xyz (point, spot)
    vec4 direction;         // xyz unit (directional: travel; spot: axis)
    vec4 ambient;           // rgb Ia
    vec4 diffuse;           // rgb Id
    vec4 specular;          // rgb Is
    vec4 attenuation;       // xyz = c, l, q
    vec4 spot;              // x cos(cutoff), y exponent
    uvec4 meta;             // x LIGHT_*
};

layout(std140, set = 0, binding = 0) uniform Globals {
    vec4 eye;               // xyz
    vec4 to_screen;         // xyz screen_center - eye, taken in f64 on the host
    vec4 screen_right;      // xyz
    vec4 screen_up;         // xyz
    vec4 background;        // rgb
    uvec4 size;             // width, height, samples, max_depth
    uvec4 counts;           // spheres, planes, lights, shadows (0 or 1)
} g;

// The scene's arrays. Where they fit the device's uniform buffer range the
// host defines SCENE_IN_UNIFORMS and each array's length: llvmpipe (and many
// GPUs) read a uniform buffer at a dynamically uniform offset with one
// scalar load, where a storage buffer read under divergent control flow
// becomes a loop over the lanes. Otherwise they are storage buffers of any
// length.
#ifdef SCENE_IN_UNIFORMS
layout(std140, set = 0, binding = 1) uniform Spheres { Sphere spheres[SPHERE_SLOTS]; };
layout(std140, set = 0, binding = 2) uniform Planes { Plane planes[PLANE_SLOTS]; };
layout(std140, set = 0, binding = 3) uniform Materials { Material materials[MATERIAL_SLOTS]; };
layout(std140, set = 0, binding = 4) uniform Lights { Light lights[LIGHT_SLOTS]; };
#else
layout(std430, set = 0, binding = 1) readonly buffer Spheres { Sphere spheres[]; };
layout(std430, set = 0, binding = 2) readonly buffer Planes { Plane planes[]; };
layout(std430, set = 0, binding = 3) readonly buffer Materials { Material materials[]; };
layout(std430, set = 0, binding = 4) readonly buffer Lights { Light lights[]; };
#endif

// Linear RGB (alpha unused) of the tile being rendered, row-major.
layout(std430, set = 0, binding = 5) writeonly buffer Pixels { vec4 pixels[]; };

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

const float INF = uintBitsToFloat(0x7f800000u);

Material material(uint i) {
    return materials[i];
}
const uint NONE = 0xffffffffu;
