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

// The slab test: where the ray's line enters the node's box (x) and leaves
// it (y, widened by BOX_SLACK).
vec2r slabs(Ray r, vec3r inv, Node node) {
    vec3r t0 = (vec3r(node.lo) - r.origin) * inv;
    vec3r t1 = (vec3r(node.hi) - r.origin) * inv;
    vec3r tn = min(t0, t1);
    vec3r tf = max(t0, t1);
    return vec2r(max(max(tn.x, tn.y), tn.z), min(min(tf.x, tf.y), tf.z) * BOX_SLACK);
}

// Whether the ray meets the node's box somewhere in [0, t_max].
bool enters(Ray r, vec3r inv, Node node, real t_max) {
    vec2r s = slabs(r, inv, node);
    return s.x <= s.y && s.y >= 0.0 && s.x <= t_max * BOX_SLACK;
}


#ifdef STACK_WALK
// An experiment (docs/performance.md, The lavapipe-specific choices): the
// classic walk with a stack in place of the skip links. An inner node's
// children are node i + 1 and that node's skip link; both boxes are tested,
// the nearer is visited first and the other pushed with its entry distance,
// and a popped node that starts beyond the nearest hit so far is dropped.
// The stack is a private array, as deep as the deepest tree (MAX_DEPTH in
// src/accel/bvh.rs).
#define WALK_STACK 64

// Where the ray enters the node's box within [0, t_max] (as enters()
// decides it), or INF where it does not.
real box_entry(Ray r, vec3r inv, Node node, real t_max) {
    return enters(r, inv, node, t_max) ? slabs(r, inv, node).x : INF;
}

void bvh_nearest(Ray r, uint from, inout Hit hit) {
    vec3r inv = inverse_dir(r.dir);
    uint base = layout_base(r.dir);
    uint key = NONE;
    uint stack_node[WALK_STACK];
    real stack_t[WALK_STACK];
    uint sp = 0u;
    uint i = 0u;
    bool live = box_entry(r, inv, load_node(base), hit.t) < INF;
    [[dont_unroll]] while (live) {
        ON_NODE();
        COUNT_NODE();
        Node node = load_node(base + i);
        bool pop = true;
        if (node.leaf != 0u) {
            leaf_nearest(r, from, node.leaf, hit, key);
        } else {
            uint a = i + 1u;
            Node na = load_node(base + a);
            uint b = na.skip;
            real ta = box_entry(r, inv, na, hit.t);
            real tb = box_entry(r, inv, load_node(base + b), hit.t);
            if (tb < ta) {
                uint c = a;
                a = b;
                b = c;
                real tc = ta;
                ta = tb;
                tb = tc;
            }
            if (ta < INF) {
                pop = false;
                i = a;
                if (tb < INF) {
                    stack_node[sp] = b;
                    stack_t[sp] = tb;
                    sp++;
                }
            }
        }
        if (pop) {
            live = false;
            [[dont_unroll]] while (sp > 0u && !live) {
                sp--;
                live = stack_t[sp] <= hit.t * BOX_SLACK;
                i = stack_node[sp];
            }
        }
    }
}

#if HAS_SHADOWS
bool bvh_occluded(Ray r, uint from, real dist) {
    vec3r inv = inverse_dir(r.dir);
    uint base = layout_base(r.dir);
    uint stack_node[WALK_STACK];
    uint sp = 0u;
    uint i = 0u;
    bool blocked = false;
    bool live = enters(r, inv, load_node(base), dist);
    [[dont_unroll]] while (live && !blocked) {
        ON_NODE();
        COUNT_NODE();
        Node node = load_node(base + i);
        bool pop = true;
        if (node.leaf != 0u) {
            blocked = leaf_occluded(r, from, node.leaf, dist);
        } else {
            uint a = i + 1u;
            Node na = load_node(base + a);
            uint b = na.skip;
            bool ea = enters(r, inv, na, dist);
            bool eb = enters(r, inv, load_node(base + b), dist);
            if (ea || eb) {
                pop = false;
                i = ea ? a : b;
                if (ea && eb) {
                    stack_node[sp] = b;
                    sp++;
                }
            }
        }
        if (pop) {
            live = sp > 0u;
            if (live) {
                sp--;
                i = stack_node[sp];
            }
        }
    }
    return blocked;
}
#endif
#else
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
#endif
