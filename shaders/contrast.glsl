// Contrast sampling on the GPU (docs/scene-format.md, Rays): the host picks
// each level's pixels (src/scene/contrast.rs, as the CPU does) and lists
// them; one invocation traces one entry, samples first..first+count of a
// pixel, one after another, and writes their sum, their least and greatest
// colour clamped to 0..1, and their trees' words. Mirrors src/cpu/contrast.rs.

// Point k (< 256) of the Sobol (0,2) sequence, in units of 1/256. Mirrors
// sobol() in src/scene/contrast.rs.
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

// Sample k's place in its pixel, in units of 1/512 pixel: the centre, then
// pairs mirrored through it. Mirrors sample_at() in src/scene/contrast.rs.
uvec2 sample_at(uint k) {
    if (k == 0u) {
        return uvec2(256u);
    }
    uint j = (k - 1u) / 2u;
    uint offset = j < 2u ? 64u : (j < 8u ? 16u : (j < 32u ? 4u : 1u));
    uvec2 s = sobol(j);
    uvec2 p = uvec2((2u * s.x + offset) % 512u, (2u * s.y + 3u * offset) % 512u);
    return k % 2u == 1u ? p : uvec2(512u) - p;
}

// What an entry's samples gave (src/scene/contrast.rs, Batch).
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
