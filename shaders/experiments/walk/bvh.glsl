// An experiment: the BVH walk (shaders/bvh.glsl) with four other
// controls, each behind a define, for measuring them again on another
// device. Pass this folder with -I and name one:
//
//   glint render SCENE -I shaders/experiments/walk -D PAIR_VISIT -o out.pfm
//   python3 benches/choices.py --lane base= \
//       --lane pair="-I shaders/experiments/walk -D PAIR_VISIT" SCENE ...
//
// Without a define it is the shipped walk. Each renders the same bits as
// the shipped walk (tests/experiments.rs); ci/gpu-check times all four on
// a GPU. Measured on lavapipe (docs/performance.md, The walk's control; ratios of
// the trace's time to the shipped walk's, medians over the BVH scenes,
// Mesa 25.0 and 22.3):
//
//   define            what it does                     25.0              22.3              measured
//   WALK_WHILE_WHILE  Aila and Laine's while-while     1.07              not run           2026-12-02
//   SHADOW_ANY_ORDER  shadow rays' children unsorted   1.07              not run           2026-12-02
//   REGISTER_STACK    the stack's top 8 in registers   1.01 (0.94-1.09)  not run           2026-12-04
//   PAIR_VISIT        two nodes a visit, 8 boxes       1.10 (1.03-1.34)  1.35 (1.06-1.59)  2026-12-05
//
// None gained on lavapipe, whose lanes run a loop iteration cheaply and a
// box test dearly; a GPU's divergence costs are other, so they are kept
// here. It must keep the shipped file's functions (bvh_nearest,
// bvh_occluded) and their parameters: the test renders it over the BVH
// scenes.

// The BVH over the bounded kinds (src/accel/bvh.rs): 4-wide nodes stored
// once, walked nearest child first with a short stack; mirrors walk() in
// src/cpu/intersect.rs. The PackedNode struct and node_at() are in
// interface.glsl.
// Each kind in the tree is uploaded in leaf order, so a leaf names a range
// of one kind's array (leaf_nearest and leaf_occluded in scans.glsl test
// it); each primitive's meta.y is its index in the scene file, which breaks
// ties in t the way the linear scan does (the first in the file wins).
//
// A child word is an inner node (its index << 4), a leaf (first << 8 |
// kind << 4 | count, count 1 to 4) or BVH_EMPTY.

// A hook called once per node visited; empty unless a user's shader defines
// it (shaders/experiments/cost counts the visits with it).
#ifndef ON_NODE
#define ON_NODE()
#endif
// A hook called after a visit's pushes, with the stack's depth;
// shaders/experiments/stack shows the deepest stack each pixel needs.
#ifndef ON_PUSH
#define ON_PUSH(depth)
#endif

// The stack's entries: three for each node on the deepest path (the host
// defines it from the tree; Bvh::stack_size in src/accel/bvh.rs).
#ifndef BVH_STACK
#define BVH_STACK 192u
#endif

const uint BVH_EMPTY = 0xffffffffu;

#ifdef USE_TABLES
// The light buffers and the eye's tiles: a list of leaves the walks below
// take in place of the tree.
#include "tables.glsl"
#endif

// Widens a box's far distance against the rounding of the slab test (1 + 2
// gamma_3 of Ize, JCGT 2013, with room to spare); the boxes are padded too.
const real BOX_SLACK = 1.000002;

// The children waiting, with where the ray enters their boxes: private to
// the invocation, shared by the two walks (never nested).
#if defined(PAIR_VISIT) && defined(REGISTER_STACK)
#error "PAIR_VISIT reads the stack's array, which REGISTER_STACK keeps in registers"
#endif
#ifdef PAIR_VISIT
// Pairs break the bound of three entries a level (a pair's second node
// may lie above the first): room to spare, and pushes past it dropped
// (bvh_push) so that the array is never overrun.
#define BVH_CAPACITY (BVH_STACK * 4u)
#else
#define BVH_CAPACITY BVH_STACK
#endif
uint bvh_stack_word[BVH_CAPACITY];
real bvh_stack_t[BVH_CAPACITY];
uint bvh_sp;

#ifdef REGISTER_STACK
// An experiment (docs/performance.md, The walk's control): the stack's top
// eight entries in registers, moved by constant-index shifts, entry 0 the
// top; older ones spill to the arrays above. No gain measured.
uint rw0, rw1, rw2, rw3, rw4, rw5, rw6, rw7;
real rt0, rt1, rt2, rt3, rt4, rt5, rt6, rt7;
uint rs_n;

void bvh_push(uint w, real t) {
    if (rs_n == 8u) {
        bvh_stack_word[bvh_sp] = rw7;
        bvh_stack_t[bvh_sp] = rt7;
        bvh_sp++;
    }
    rw7 = rw6; rt7 = rt6; rw6 = rw5; rt6 = rt5; rw5 = rw4; rt5 = rt4; rw4 = rw3; rt4 = rt3;
    rw3 = rw2; rt3 = rt2; rw2 = rw1; rt2 = rt1; rw1 = rw0; rt1 = rt0; rw0 = w; rt0 = t;
    rs_n = min(rs_n + 1u, 8u);
}
#define BVH_DEPTH (bvh_sp + rs_n)
#define BVH_CLEAR() bvh_sp = 0u; rs_n = 0u
#else
void bvh_push(uint w, real t) {
#ifdef PAIR_VISIT
    if (bvh_sp == BVH_CAPACITY) {
        return;
    }
#endif
    bvh_stack_word[bvh_sp] = w;
    bvh_stack_t[bvh_sp] = t;
    bvh_sp++;
}
#define BVH_DEPTH bvh_sp
#define BVH_CLEAR() bvh_sp = 0u
#endif

// 1/d, with +-1e30 for a zero component so that (lo - o) * inv is never 0 * inf.
vec3r inverse_dir(vec3r d) {
    vec3r big = mix(vec3r(-1e30), vec3r(1e30), greaterThanEqual(d, vec3r(0.0)));
    return mix(big, vec3r(1.0) / d, greaterThan(abs(d), vec3r(1e-30)));
}

// A node's four boxes, a row of four a coordinate, and its child words.
struct Node {
    vec4 lo_x;
    vec4 hi_x;
    vec4 lo_y;
    vec4 hi_y;
    vec4 lo_z;
    vec4 hi_z;
    uvec4 child;
};

// The four bytes of a word, child k's in bits 8k to 8k + 7.
vec4 bytes_of(uint w) {
    return vec4((uvec4(w) >> uvec4(0u, 8u, 16u, 24u)) & 0xffu);
}

// Node i's boxes from its bytes (src/accel/quantize.rs): each bound is
// origin + q * 2^e in f32, the product exact and the sum rounded once,
// as the host decoded and checked it (precise: never one fused rounding).
Node unpack(uint i) {
    PackedNode p = node_at(i);
    vec3 step = uintBitsToFloat(((uvec3(p.steps) >> uvec3(0u, 8u, 16u)) & 0xffu) << 23);
    precise vec4 lo_x = p.origin.x + bytes_of(p.xy.x) * step.x;
    precise vec4 hi_x = p.origin.x + bytes_of(p.xy.y) * step.x;
    precise vec4 lo_y = p.origin.y + bytes_of(p.xy.z) * step.y;
    precise vec4 hi_y = p.origin.y + bytes_of(p.xy.w) * step.y;
    precise vec4 lo_z = p.origin.z + bytes_of(p.z.x) * step.z;
    precise vec4 hi_z = p.origin.z + bytes_of(p.z.y) * step.z;
    return Node(lo_x, hi_x, lo_y, hi_y, lo_z, hi_z, p.child);
}

bvec4 both(bvec4 a, bvec4 b) {
    return bvec4(a.x && b.x, a.y && b.y, a.z && b.z, a.w && b.w);
}

// The slab test of the node's four children at once: where the ray's line
// enters each box, for those it meets somewhere in [0, t_max] (the far
// distance widened by BOX_SLACK); INF for the others and the empty slots.
vec4r entries(Ray r, vec3r inv, Node n, real t_max) {
    vec4r x0 = (vec4r(n.lo_x) - r.origin.x) * inv.x;
    vec4r x1 = (vec4r(n.hi_x) - r.origin.x) * inv.x;
    vec4r y0 = (vec4r(n.lo_y) - r.origin.y) * inv.y;
    vec4r y1 = (vec4r(n.hi_y) - r.origin.y) * inv.y;
    vec4r z0 = (vec4r(n.lo_z) - r.origin.z) * inv.z;
    vec4r z1 = (vec4r(n.hi_z) - r.origin.z) * inv.z;
    vec4r near = max(max(min(x0, x1), min(y0, y1)), min(z0, z1));
    vec4r far = min(min(max(x0, x1), max(y0, y1)), max(z0, z1)) * BOX_SLACK;
    bvec4 met = both(both(lessThanEqual(near, far), greaterThanEqual(far, vec4r(0.0))),
                     both(lessThanEqual(near, vec4r(t_max * BOX_SLACK)),
                          notEqual(n.child, uvec4(BVH_EMPTY))));
    return mix(vec4r(INF), near, met);
}

// One compare-exchange of the sorting network: the nearer entry first, a
// tie to the earlier slot (as the CPU's sort by entry, then slot).
void order(inout real ta, inout uint wa, inout uint ka, inout real tb, inout uint wb, inout uint kb) {
    bool swap = tb < ta || (tb == ta && kb < ka);
    real t = ta;
    uint w = wa;
    uint k = ka;
    ta = swap ? tb : ta;
    wa = swap ? wb : wa;
    ka = swap ? kb : ka;
    tb = swap ? t : tb;
    wb = swap ? w : wb;
    kb = swap ? k : kb;
}

// A node's four children in the order the ray enters them, nearest first
// (INF for those it misses): their entries and their words.
struct Children {
    real t0, t1, t2, t3;
    uint w0, w1, w2, w3;
};

// The children of words `child` entered at `t`, sorted; slots numbered
// from `k` (a tie goes to the lower).
Children sorted_children(vec4r t, uvec4 child, uint k) {
    Children c = Children(t.x, t.y, t.z, t.w, child.x, child.y, child.z, child.w);
    uint k0 = k, k1 = k + 1u, k2 = k + 2u, k3 = k + 3u;
    order(c.t0, c.w0, k0, c.t1, c.w1, k1);
    order(c.t2, c.w2, k2, c.t3, c.w3, k3);
    order(c.t0, c.w0, k0, c.t2, c.w2, k2);
    order(c.t1, c.w1, k1, c.t3, c.w3, k3);
    order(c.t1, c.w1, k1, c.t2, c.w2, k2);
    return c;
}

// Pushes the entered children of `c` but the nearest, the farthest first
// (and the nearest last, where `nearest_too`).
void push_children(Children c, bool nearest_too) {
    if (c.t3 < INF) {
        bvh_push(c.w3, c.t3);
    }
    if (c.t2 < INF) {
        bvh_push(c.w2, c.t2);
    }
    if (c.t1 < INF) {
        bvh_push(c.w1, c.t1);
    }
    if (nearest_too && c.t0 < INF) {
        bvh_push(c.w0, c.t0);
    }
}

#ifdef PAIR_VISIT
// An experiment (docs/performance.md, The walk's control): a visit takes
// the stack's top as well where it is an inner node entered within t_max,
// so that one iteration of the divergent loop tests eight boxes, as an
// 8-wide node's visit would, rather than four. The nearest of the eight
// is returned; each node's other children are pushed farthest first, the
// node with the farther nearest child first. Slower on both lavapipes: a
// box's work, not the loop's, is what a visit costs.
uint bvh_descend(Ray r, vec3r inv, uint index, real t_max) {
    uint other = BVH_EMPTY;
    if (bvh_sp > 0u && bvh_sp + 6u <= BVH_STACK) {
        uint w = bvh_stack_word[bvh_sp - 1u];
        if ((w & 15u) == 0u && bvh_stack_t[bvh_sp - 1u] <= t_max * BOX_SLACK) {
            bvh_sp--;
            other = w >> 4;
        }
    }
    ON_NODE();
    COUNT_NODE();
    if (other != BVH_EMPTY) {
        COUNT_NODE();
    }
    Node n = unpack(index);
    Node m = unpack(other != BVH_EMPTY ? other : index);
    Children a = sorted_children(entries(r, inv, n, t_max), n.child, 0u);
    Children b = sorted_children(other != BVH_EMPTY ? entries(r, inv, m, t_max) : vec4r(INF),
                                 m.child, 4u);
    bool b_nearer = b.t0 < a.t0;
    push_children(b_nearer ? a : b, true);
    Children near = b_nearer ? b : a;
    push_children(near, false);
    ON_PUSH(BVH_DEPTH);
    return near.t0 < INF ? near.w0 : BVH_EMPTY;
}
#else
// Visits inner node `index`: of the children whose boxes the ray enters
// within t_max, the nearest is returned and the others are pushed, the
// farthest first; BVH_EMPTY where it enters none.
uint bvh_descend(Ray r, vec3r inv, uint index, real t_max) {
    ON_NODE();
    COUNT_NODE();
    Node n = unpack(index);
    Children c = sorted_children(entries(r, inv, n, t_max), n.child, 0u);
    push_children(c, false);
    ON_PUSH(BVH_DEPTH);
    return c.t0 < INF ? c.w0 : BVH_EMPTY;
}
#endif

#ifdef SHADOW_ANY_ORDER
// An experiment (docs/performance.md, Reading the scene): a shadow ray
// takes the children it enters in slot order, unsorted, since any hit ends
// its walk. (It visits other nodes than the CPU's walk, so --stats differ.)
uint bvh_descend_any(Ray r, vec3r inv, uint index, real t_max) {
    ON_NODE();
    COUNT_NODE();
    Node n = unpack(index);
    vec4r t = entries(r, inv, n, t_max);
    uint first = BVH_EMPTY;
    [[unroll]] for (uint k = 0u; k < 4u; k++) {
        if (t[k] < INF) {
            if (first == BVH_EMPTY) {
                first = n.child[k];
            } else {
                bvh_push(n.child[k], t[k]);
            }
        }
    }
    return first;
}
#define bvh_descend_shadow bvh_descend_any
#else
#define bvh_descend_shadow bvh_descend
#endif

// The next child waiting that the ray enters within t_max (one entered
// beyond a hit found since it was pushed is dropped); BVH_EMPTY when none is.
uint bvh_pop(real t_max) {
    uint next = BVH_EMPTY;
#ifdef REGISTER_STACK
    [[dont_unroll]] while ((rs_n > 0u || bvh_sp > 0u) && next == BVH_EMPTY) {
        uint w;
        real t;
        if (rs_n > 0u) {
            w = rw0; t = rt0;
            rw0 = rw1; rt0 = rt1; rw1 = rw2; rt1 = rt2; rw2 = rw3; rt2 = rt3; rw3 = rw4; rt3 = rt4;
            rw4 = rw5; rt4 = rt5; rw5 = rw6; rt5 = rt6; rw6 = rw7; rt6 = rt7;
            rs_n--;
        } else {
            bvh_sp--;
            w = bvh_stack_word[bvh_sp];
            t = bvh_stack_t[bvh_sp];
        }
        next = t <= t_max * BOX_SLACK ? w : BVH_EMPTY;
    }
#else
    [[dont_unroll]] while (bvh_sp > 0u && next == BVH_EMPTY) {
        bvh_sp--;
        next = bvh_stack_t[bvh_sp] <= t_max * BOX_SLACK ? bvh_stack_word[bvh_sp] : BVH_EMPTY;
    }
#endif
    return next;
}

// The nearest hit in the tree closer than hit.t, into hit. With the tables
// (USE_TABLES), a list (first entry, count) other than the walk's
// (TABLE_WALK) is scanned in its place by the same loop: its entries are
// leaves of one primitive, taken nearest first while their keys are within
// the hit's t, so that the shader holds one copy of the loop.
#ifdef USE_TABLES
void bvh_nearest(Ray r, uint from, inout Hit hit, uvec2 list) {
#else
void bvh_nearest(Ray r, uint from, inout Hit hit) {
#endif
    vec3r inv = inverse_dir(r.dir);
    uint key = NONE;
    BVH_CLEAR();
    // The root is inner node 0.
    uint current = 0u;
#ifdef USE_TABLES
    bool listing = list.y != TABLE_WALK;
    uint at = list.x;
    uint end = listing ? list.x + list.y : 0u;
    if (listing) {
        current = list_next(at, end, hit.t * KEY_SLACK);
    }
#endif
#ifdef WALK_WHILE_WHILE
    // An experiment (docs/performance.md, Reading the scene): Aila and
    // Laine's while-while, the inner nodes until every lane holds a leaf,
    // then the leaves. (It walks the tree for a list too.)
#ifdef USE_TABLES
    current = 0u;
#endif
    [[dont_unroll]] while (current != BVH_EMPTY) {
        [[dont_unroll]] while (current != BVH_EMPTY && (current & 15u) == 0u) {
            uint next = bvh_descend(r, inv, current >> 4, hit.t);
            current = next != BVH_EMPTY ? next : bvh_pop(hit.t);
        }
        if (current != BVH_EMPTY) {
            leaf_nearest(r, from, current, hit, key);
            current = bvh_pop(hit.t);
        }
    }
#else
    [[dont_unroll]] while (current != BVH_EMPTY) {
        uint next = BVH_EMPTY;
        if ((current & 15u) != 0u) {
            leaf_nearest(r, from, current, hit, key);
        } else {
            next = bvh_descend(r, inv, current >> 4, hit.t);
        }
#ifdef USE_TABLES
        current = next != BVH_EMPTY ? next
                : listing ? list_next(at, end, hit.t * KEY_SLACK) : bvh_pop(hit.t);
#else
        current = next != BVH_EMPTY ? next : bvh_pop(hit.t);
#endif
    }
#endif
}

#if HAS_SHADOWS
// Whether a primitive in the tree lies on the ray strictly between 0 and
// dist: any hit ends the walk. With the tables, a list other than the
// walk's is scanned in its place while its keys are at most `bound`.
#ifdef USE_TABLES
bool bvh_occluded(Ray r, uint from, real dist, uvec2 list, real bound) {
#else
bool bvh_occluded(Ray r, uint from, real dist) {
#endif
    vec3r inv = inverse_dir(r.dir);
    BVH_CLEAR();
    bool blocked = false;
    uint current = 0u;
#ifdef USE_TABLES
    bool listing = list.y != TABLE_WALK;
    uint at = list.x;
    uint end = listing ? list.x + list.y : 0u;
    if (listing) {
        current = list_next(at, end, bound);
    }
#endif
#ifdef WALK_WHILE_WHILE
#ifdef USE_TABLES
    current = 0u;
#endif
    [[dont_unroll]] while (current != BVH_EMPTY) {
        [[dont_unroll]] while (current != BVH_EMPTY && (current & 15u) == 0u) {
            uint next = bvh_descend_shadow(r, inv, current >> 4, dist);
            current = next != BVH_EMPTY ? next : bvh_pop(dist);
        }
        if (current != BVH_EMPTY) {
            blocked = leaf_occluded(r, from, current, dist);
            current = blocked ? BVH_EMPTY : bvh_pop(dist);
        }
    }
#else
    [[dont_unroll]] while (current != BVH_EMPTY && !blocked) {
        uint next = BVH_EMPTY;
        if ((current & 15u) != 0u) {
            blocked = leaf_occluded(r, from, current, dist);
        } else {
            next = bvh_descend_shadow(r, inv, current >> 4, dist);
        }
#ifdef USE_TABLES
        current = next != BVH_EMPTY || blocked ? next
                : listing ? list_next(at, end, bound) : bvh_pop(dist);
#else
        current = next != BVH_EMPTY || blocked ? next : bvh_pop(dist);
#endif
    }
#endif
    return blocked;
}
#endif
