// What every kind of primitive shares, written once over the variant's
// lists of kinds: the scans (nearest hit, any hit), the BVH's leaves, the
// normal, the shading normal, where rays leave, a record's names, the
// textures' coordinates. Mirrors crate::prim::CpuPrims and
// src/cpu/intersect.rs.
//
// kinds.glsl, generated for the variant from the table of kinds
// (src/prim/mod.rs, src/gpu/generated.rs), includes each declared kind's
// file (shaders/prim/) and defines the lists: KINDS_DECLARED(X) calls
// X(UPPER, Struct, name) for every declared kind in the table's order
// (X(SPHERES, Sphere, sphere)), and KINDS_SCANNED, KINDS_BOUNDED,
// KINDS_SHADING, KINDS_LIFTED, KINDS_FRAMED and KINDS_UV for those of them
// that the scans test (all, or those outside the BVH), the BVH holds, have
// shading normals, lift rays off, have 2D coordinates and have uvs.
// KIND_SHIFT and PRIM_INDEX come with them.

// A primitive's id: its kind above KIND_SHIFT bits of its index in its
// array.
uint prim_id(uint kind, uint i) {
    return kind << KIND_SHIFT | i;
}

// The primitive `id` is of kind UPPER.
#define IS_KIND(id, UPPER) ((id) >> KIND_SHIFT == KIND_##UPPER)

#if defined(RECORD_TREE) || defined(AOVS)
// For `glint explain`'s record (shaders/record.glsl): a bounded kind's
// array is in the BVH's leaf order, and a tree names a primitive by its
// place in the scene file, as the CPU's does.
#define IN_FILE(UPPER, Struct, name) \
    if (IS_KIND(prim, UPPER)) { \
        return prim_id(KIND_##UPPER, name##_test_at(prim & PRIM_INDEX).meta.y); \
    }
// The primitive `prim` (an id; NONE: none) as a record names it: its kind
// above its index in the scene file.
uint prim_in_file(uint prim) {
    if (prim == NONE) {
        return NONE;
    }
    KINDS_DECLARED(IN_FILE)
    return prim;
}
#endif

// The nearest hit closer than hit.t among the scanned kinds, in the
// table's order: a strict < leaves a tie to the earlier.
#define SCAN_NEAREST(UPPER, Struct, name) \
    SCENE_LOOP for (uint i = 0u; i < UPPER##_COUNT; i++) { \
        ON_TEST(); \
        COUNT_TEST(KIND_##UPPER); \
        Struct p = name##_test_at(i); \
        uint id = prim_id(KIND_##UPPER, i); \
        real t = name##_intersect(r, p, from == id); \
        if (t > 0.0 && t < hit.t) { \
            hit = Hit(t, id, p.meta.x, name##_shape(p)); \
        } \
    }
void scan_nearest(Ray r, uint from, inout Hit hit) {
    KINDS_SCANNED(SCAN_NEAREST)
}

#if HAS_SHADOWS
// Whether a scanned primitive lies on the ray strictly between 0 and dist.
#define SCAN_OCCLUDED(UPPER, Struct, name) \
    SCENE_LOOP for (uint i = 0u; i < UPPER##_COUNT; i++) { \
        ON_TEST(); \
        COUNT_TEST(KIND_##UPPER); \
        real t = name##_intersect(r, name##_test_at(i), from == prim_id(KIND_##UPPER, i)); \
        if (t > 0.0 && t < dist) { \
            return true; \
        } \
    }
bool scan_occluded(Ray r, uint from, real dist) {
    KINDS_SCANNED(SCAN_OCCLUDED)
    return false;
}
#endif

#ifdef USE_BVH
// The BVH's leaf tests (shaders/bvh.glsl calls them): the leaf word is
// first << 8 | kind << 4 | count (src/accel/bvh.rs). Where the BVH holds
// one kind, every leaf is of it, and the kind is not tested.
#define IS_LEAF_OF(UPPER) (ONE_BOUNDED_KIND || ((leaf >> 4) & 15u) == KIND_##UPPER)

// The leaf's nearest hit closer than hit.t; a tie in t goes to the lower
// key (the kind, then the index in the scene file).
#define LEAF_NEAREST(UPPER, Struct, name) \
    if (IS_LEAF_OF(UPPER)) { \
        [[dont_unroll]] for (uint i = first; i < end; i++) { \
            ON_TEST(); \
            COUNT_TEST(KIND_##UPPER); \
            Struct p = name##_test_at(i); \
            uint id = prim_id(KIND_##UPPER, i); \
            real t = name##_intersect(r, p, from == id); \
            uint order = prim_id(KIND_##UPPER, p.meta.y); \
            if (t > 0.0 && (t < hit.t || (t == hit.t && hit.prim != NONE && order < key))) { \
                hit = Hit(t, id, p.meta.x, name##_shape(p)); \
                key = order; \
            } \
        } \
    }
void leaf_nearest(Ray r, uint from, uint leaf, inout Hit hit, inout uint key) {
    uint first = leaf >> 8;
    uint end = first + (leaf & 15u);
    KINDS_BOUNDED(LEAF_NEAREST)
}

#if HAS_SHADOWS
// Whether a primitive of the leaf lies on the ray strictly between 0 and
// dist. A flag rather than a return from inside the loop: 5 % faster on
// flake-4 with llvmpipe.
#define LEAF_OCCLUDED(UPPER, Struct, name) \
    if (IS_LEAF_OF(UPPER)) { \
        [[dont_unroll]] for (uint i = first; i < end && !blocked; i++) { \
            ON_TEST(); \
            COUNT_TEST(KIND_##UPPER); \
            real t = name##_intersect(r, name##_test_at(i), from == prim_id(KIND_##UPPER, i)); \
            blocked = t > 0.0 && t < dist; \
        } \
    }
bool leaf_occluded(Ray r, uint from, uint leaf, real dist) {
    bool blocked = false;
    uint first = leaf >> 8;
    uint end = first + (leaf & 15u);
    KINDS_BOUNDED(LEAF_OCCLUDED)
    return blocked;
}
#endif
#endif

// The outward unit normal at p of the primitive hit.
#define SURFACE(UPPER, Struct, name) \
    if (IS_KIND(hit.prim, UPPER)) { \
        return name##_normal(hit.prim & PRIM_INDEX, hit.shape, p); \
    }
vec3r surface(Hit hit, vec3r p) {
    KINDS_DECLARED(SURFACE)
    return vec3r(0.0);
}

// The unit normal that shading uses at p, on the side of the outward
// normal: the kinds with shading normals give theirs.
#define SHADING(UPPER, Struct, name) \
    if (IS_KIND(hit.prim, UPPER)) { \
        return name##_shading(hit.prim & PRIM_INDEX, p, geometric); \
    }
vec3r shading_normal(Hit hit, vec3r p, vec3r geometric) {
    KINDS_SHADING(SHADING)
    return geometric;
}

// Where rays leaving the primitive hit at p start, on `side`: lifted off
// the kinds that ask for it (intersect.glsl's lift()), else p.
#define LIFTED(UPPER, Struct, name) \
    if (IS_KIND(hit.prim, UPPER)) { \
        return lift(p, o, side); \
    }
vec3r leave(Hit hit, vec3r p, vec3r o, vec3r side) {
    KINDS_LIFTED(LIFTED)
    return p;
}

#if HAS_TEXTURES
// The hit primitive's own coordinates, for the 2D textures: false for a
// kind without them (the scene's checks give those none).
#define FRAMED(UPPER, Struct, name) \
    if (IS_KIND(hit.prim, UPPER)) { \
        name##_frame(hit.prim & PRIM_INDEX, origin, u, v); \
        return true; \
    }
bool surface_frame(Hit hit, out vec3r origin, out vec3r u, out vec3r v) {
    origin = vec3r(0.0);
    u = vec3r(0.0);
    v = vec3r(0.0);
    KINDS_FRAMED(FRAMED)
    return false;
}
#endif

#if HAS_IMAGES
// The uv coordinates at p of the primitive hit, for the image textures
// (the scene's checks give those only to primitives with them).
#define MAPPED(UPPER, Struct, name) \
    if (IS_KIND(hit.prim, UPPER)) { \
        return name##_uv(hit.prim & PRIM_INDEX, hit.shape, p); \
    }
vec2r surface_uv(Hit hit, vec3r p) {
    KINDS_UV(MAPPED)
    return vec2r(0.0);
}
#endif
