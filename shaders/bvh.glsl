// The BVH over the bounded kinds (src/accel/bvh.rs): pre-order nodes with
// skip links, walked without a stack, in one of eight layouts chosen by the
// ray's direction; mirrors the BVH walks of src/cpu/intersect.rs. The Node
// struct and block are in interface.glsl.
// Each kind in the tree is uploaded in leaf order, so a leaf names a range
// of one kind's array (leaf_nearest and leaf_occluded in kinds.glsl test
// it); each primitive's meta.y is its index in the scene file, which breaks
// ties in t the way the linear scan does (the first in the file wins).

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
#define NODE_COUNT (uint(node_words.length()) / (2u * LAYOUTS))
#endif

// Node i from its two vec4s (interface.glsl): xyz the box corner, w the
// skip link and the leaf word as uint bits.
Node load_node(uint i) {
    vec4 lo = node_words[2u * i];
    vec4 hi = node_words[2u * i + 1u];
    return Node(lo.xyz, floatBitsToUint(lo.w), hi.xyz, floatBitsToUint(hi.w));
}

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
    vec3r t0 = (vec3r(node.lo) - r.origin) * inv;
    vec3r t1 = (vec3r(node.hi) - r.origin) * inv;
    vec3r tn = min(t0, t1);
    vec3r tf = max(t0, t1);
    real near = max(max(tn.x, tn.y), tn.z);
    real far = min(min(tf.x, tf.y), tf.z) * BOX_SLACK;
    return near <= far && far >= 0.0 && near <= t_max * BOX_SLACK;
}


// The nearest hit in the tree closer than hit.t, into hit.
void bvh_nearest(Ray r, uint from, inout Hit hit) {
    vec3r inv = inverse_dir(r.dir);
    uint base = layout_base(r.dir);
    uint key = NONE;
    uint i = 0u;
    [[dont_unroll]] while (i < NODE_COUNT) {
        ON_NODE();
        COUNT_NODE();
        Node node = load_node(base + i);
        if (!ANY(enters(r, inv, node, hit.t))) {
            i = node.skip;
        } else if (node.leaf == 0u) {
            i++;
        } else {
            leaf_nearest(r, from, node.leaf, hit, key);
            i = node.skip;
        }
    }
}

#if HAS_SHADOWS
// Whether a primitive in the tree lies on the ray strictly between 0 and
// dist: any hit ends the walk.
bool bvh_occluded(Ray r, uint from, real dist) {
    vec3r inv = inverse_dir(r.dir);
    uint base = layout_base(r.dir);
    bool blocked = false;
    uint i = 0u;
    [[dont_unroll]] while (i < NODE_COUNT && !blocked) {
        ON_NODE();
        COUNT_NODE();
        Node node = load_node(base + i);
        if (!ANY(enters(r, inv, node, dist))) {
            i = node.skip;
        } else if (node.leaf == 0u) {
            i++;
        } else {
            blocked = leaf_occluded(r, from, node.leaf, dist);
            i = node.skip;
        }
    }
    return blocked;
}
#endif
