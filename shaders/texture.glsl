// Procedural textures (docs/scene-format.md, Textures): a material's
// diffuse colour, and its ambient colour, from a pattern at the hit point;
// mirrors src/cpu/texture.rs. Left out of a variant whose materials have
// none (HAS_TEXTURES 0).

#if HAS_TEXTURES
const uint PATTERN_CHECKER = 1u;
const uint PATTERN_SOLID_CHECKER = 2u;

// The colour of texture t at p, a point of the primitive hit: of the square
// (or cube) p is in, color0 where the cells' indices sum to an even number.
vec3r texture_colour(uint t, Hit hit, vec3r p) {
    Texture tx = textures[t];
    real size = tx.origin_size.w;
    real cells;
    if (tx.meta.x == PATTERN_CHECKER) {
        vec3r origin, u, v;
        surface_frame(hit, origin, u, v);
        vec3r q = p - origin;
        real a = dot(q, u);
        real b = dot(q, v);
        real c = tx.rotation.x;
        real s = tx.rotation.y;
        cells = floor((c * a + s * b) / size) + floor((c * b - s * a) / size);
    } else {
        vec3r q = p - tx.origin_size.xyz;
        cells = floor(q.x / size) + floor(q.y / size) + floor(q.z / size);
    }
    bool odd = cells - 2.0 * floor(cells * 0.5) != 0.0;
    return odd ? tx.color1.rgb : tx.color0.rgb;
}

// m at the hit point p: its textured colours in place of its own.
void apply_textures(inout Material m, Hit hit, vec3r p) {
    uint diffuse = m.textures.x;
    uint ambient = m.textures.y;
    if (diffuse != 0u) {
        m.diffuse.rgb = texture_colour(diffuse - 1u, hit, p);
    }
    if (ambient != 0u) {
        m.ambient.rgb = ambient == diffuse ? m.diffuse.rgb : texture_colour(ambient - 1u, hit, p);
    }
}
#endif
