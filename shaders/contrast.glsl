// Contrast sampling on the GPU (docs/scene-format.md, Rays): the host picks
// each level's pixels (src/sampling/contrast.rs, as the CPU does) and lists
// them; one invocation traces one entry, samples first..first+count of a
// pixel, one after another, and writes their sum, their least and greatest
// colour clamped to 0..1, and their trees' words. Mirrors src/cpu/contrast.rs.

// Point k (< 256) of the Sobol (0,2) sequence, in units of 1/256. Mirrors
// sobol() in src/sampling/contrast.rs.
uvec2 sobol(uint k) {
    uint x = bitfieldReverse(k & 0xffu) >> 24u;
    uint y = 0u;
    uint v = 0x80u;
    [[dont_unroll]] for (uint bit = 0u; bit < 8u; bit++) {
        if (((k >> bit) & 1u) == 1u) {
            y ^= v;
        }
        v ^= v >> 1u;
    }
    return uvec2(x, y);
}

// The first of each mirrored pair of samples 1..64: cells of the pixel's
// 8x8 lattice, numbered x * 8 + y. Mirrors LATTICE in src/sampling/contrast.rs.
const uint LATTICE[32] = uint[](16u, 50u, 2u, 31u, 6u, 9u, 20u, 27u, 0u, 4u, 11u, 15u, 18u, 22u,
                                25u, 29u, 1u, 3u, 5u, 7u, 8u, 10u, 12u, 14u, 17u, 19u, 21u, 23u,
                                24u, 26u, 30u, 28u);

// Sample k's place in its pixel, in units of 1/512 pixel: the centre, then
// pairs mirrored through it. Mirrors sample_at() in src/sampling/contrast.rs.
uvec2 sample_at(uint k) {
    if (k == 0u) {
        return uvec2(256u);
    }
    uint j = (k - 1u) / 2u;
    uvec2 p;
    if (j < 32u) {
        uint cell = LATTICE[j];
        p = uvec2(cell / 8u, cell % 8u) * 64u + 32u;
    } else {
        uvec2 s = sobol(j);
        p = uvec2((2u * s.x + 1u) % 512u, (2u * s.y + 3u) % 512u);
    }
    return k % 2u == 1u ? p : uvec2(512u) - p;
}

// What an entry's samples gave (src/sampling/contrast.rs, Batch).
struct ContrastBatch {
    vec3r sum;
    vec3r least;
    vec3r most;
    uint word;
    bool differ;
};

ContrastBatch contrast_samples(Refine e) {
    ContrastBatch b = ContrastBatch(vec3r(0.0), vec3r(1.0), vec3r(0.0), TREE_BASIS, false);
    [[dont_unroll]] for (uint k = e.point.z; k < e.point.z + e.point.w; k++) {
        uvec2 at = sample_at(k);
        real px = real(e.point.x) + real(at.x) / 512.0;
        real py = real(e.point.y) + real(at.y) / 512.0;
#ifdef CONTRAST_TREES
        tree_hash = TREE_BASIS;
#endif
        vec3r c = trace(ray_through(px, py));
        b.sum += c;
        vec3r clamped = clamp(c, 0.0, 1.0);
        b.least = min(b.least, clamped);
        b.most = max(b.most, clamped);
#ifdef CONTRAST_TREES
        if (k == e.point.z) {
            b.word = tree_hash;
        }
        b.differ = b.differ || tree_hash != b.word;
#endif
    }
    return b;
}
