// The spheres' BVH (src/accel/bvh.rs): pre-order nodes with skip links,
// walked without a stack, in one of eight layouts chosen by the ray's
// direction; mirrors the BVH walks of src/cpu/intersect.rs.
// The spheres are uploaded in leaf order, so a leaf names a range of them;
// each sphere's meta.y is its index in the scene file, which breaks ties in t
// the way the linear scan does (the first in the file wins).

struct Node {
    vec4 lo_skip;            // xyz box corner (f32, rounded outwards), w: skip link (uint bits)
    vec4 hi_leaf;            // xyz box corner, w: 0 inner, else first << 4 | count (uint bits)
};

// A uniform block where the scene is in uniforms (see bindings.glsl).
#ifdef NODE_SLOTS
SCENE_BLOCK(NODES_BINDING) Nodes { Node nodes[NODE_SLOTS]; };
#else
layout(std430, set = 0, binding = NODES_BINDING) readonly buffer Nodes { Node nodes[]; };
#endif

// A hook called once per node visited; empty unless a user's shader defines
// it (shaders/experiments/cost counts the visits with it).
#ifndef ON_NODE
#define ON_NODE()
#endif

// The layouts: 8, one per octant of ray directions, or 1 for a tree too
// large for 8 (src/accel/bvh.rs).
#ifndef LAYOUTS
#define LAYOUTS 8u
#endif

// Nodes in one layout.
#ifndef NODE_COUNT
#define NODE_COUNT (uint(nodes.length()) / LAYOUTS)
#endif

// The first node of the layout for the ray's octant (src/accel/bvh.rs): in
// it, the child a ray of that octant meets first along the split axis comes
// first. Bit k is set where component k is negative.
uint layout_base(vec3r d) {
    if (LAYOUTS == 1u) {
        return 0u;
    }
    uint octant = (d.x < 0.0 ? 1u : 0u) | (d.y < 0.0 ? 2u : 0u) | (d.z < 0.0 ? 4u : 0u);
    return octant * NODE_COUNT;
}

#ifdef PACKET_WALK
#extension GL_KHR_shader_subgroup_vote : require
#define ANY(e) subgroupAny(e)
#else
#define ANY(e) (e)
#endif

// Widens a box's far distance against the rounding of the slab test (1 + 2
// gamma_3 of Ize, JCGT 2013, with room to spare); the boxes are padded too.
const real BOX_SLACK = 1.000002;

// 1/d, with +-1e30 for a zero component so that (lo - o) * inv is never 0 * inf.
vec3r inverse_dir(vec3r d) {
    vec3r big = mix(vec3r(-1e30), vec3r(1e30), greaterThanEqual(d, vec3r(0.0)));
    return mix(big, vec3r(1.0) / d, greaterThan(abs(d), vec3r(1e-30)));
}

// Whether the ray meets the node's box somewhere in [0, t_max].
bool enters(Ray r, vec3r inv, Node node, real t_max) {
    vec3r t0 = (vec3r(node.lo_skip.xyz) - r.origin) * inv;
    vec3r t1 = (vec3r(node.hi_leaf.xyz) - r.origin) * inv;
    vec3r tn = min(t0, t1);
    vec3r tf = max(t0, t1);
    real near = max(max(tn.x, tn.y), tn.z);
    real far = min(min(tf.x, tf.y), tf.z) * BOX_SLACK;
    return near <= far && far >= 0.0 && near <= t_max * BOX_SLACK;
}

// The nearest sphere hit closer than hit.t, into hit.
void bvh_nearest(Ray r, uint from, inout Hit hit) {
    vec3r inv = inverse_dir(r.dir);
    uint base = layout_base(r.dir);
    uint key = NONE;
    uint i = 0u;
    [[dont_unroll]] while (i < NODE_COUNT) {
        ON_NODE();
        Node node = nodes[base + i];
        uint skip = floatBitsToUint(node.lo_skip.w);
        uint leaf = floatBitsToUint(node.hi_leaf.w);
        if (!ANY(enters(r, inv, node, hit.t))) {
            i = skip;
        } else if (leaf == 0u) {
            i++;
        } else {
            uint first = leaf >> 4;
            uint end = first + (leaf & 15u);
            [[dont_unroll]] for (uint k = first; k < end; k++) {
                vec4r s = spheres[k].center_radius;
                uvec4 meta = spheres[k].meta;
                real t = intersect_sphere(r, s.xyz, s.w, from == k);
                if (t > 0.0 && (t < hit.t || (t == hit.t && hit.prim != NONE && meta.y < key))) {
                    hit = Hit(t, k, meta.x, s);
                    key = meta.y;
                }
            }
            i = skip;
        }
    }
}

#if HAS_SHADOWS
// Whether a sphere lies on the ray strictly between 0 and dist: any hit ends the walk.
bool bvh_occluded(Ray r, uint from, real dist) {
    vec3r inv = inverse_dir(r.dir);
    uint base = layout_base(r.dir);
    bool blocked = false;
    uint i = 0u;
    [[dont_unroll]] while (i < NODE_COUNT && !blocked) {
        ON_NODE();
        Node node = nodes[base + i];
        uint skip = floatBitsToUint(node.lo_skip.w);
        uint leaf = floatBitsToUint(node.hi_leaf.w);
        if (!ANY(enters(r, inv, node, dist))) {
            i = skip;
        } else if (leaf == 0u) {
            i++;
        } else {
            uint first = leaf >> 4;
            uint end = first + (leaf & 15u);
            [[dont_unroll]] for (uint k = first; k < end && !blocked; k++) {
                vec4r s = spheres[k].center_radius;
                real t = intersect_sphere(r, s.xyz, s.w, from == k);
                blocked = t > 0.0 && t < dist;
            }
            i = skip;
        }
    }
    return blocked;
}
#endif
