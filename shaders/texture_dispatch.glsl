// The dispatch over the patterns, written once over the lists of them;
// mirrors Pattern::colour (src/scene/texture/mod.rs). textures.glsl,
// generated from the table of patterns (src/gpu/entities.rs), gives each
// pattern's code and include and defines the lists: PATTERNS_UV(X) calls
// X(UPPER, name) for each pattern that reads uvs, PATTERNS_OTHER(X) for the
// others.

// The colour of texture t at p, a point of the primitive hit. The patterns
// that read uvs are compiled where the variant has images.
#define PATTERN(UPPER, name) \
    if (pattern == PATTERN_##UPPER) { \
        return name##_colour(tx, hit, p); \
    }
vec3r texture_colour(uint t, Hit hit, vec3r p) {
    Texture tx = texture_at(t);
    uint pattern = tx.meta.x;
#if HAS_IMAGES
    PATTERNS_UV(PATTERN)
#endif
    PATTERNS_OTHER(PATTERN)
    return vec3r(0.0);
}
