// Textures (docs/scene-format.md, Textures): a material's diffuse colour,
// and its ambient colour, from a pattern or an image at the hit point;
// mirrors src/cpu/texture.rs. Left out of a variant whose materials have
// none (HAS_TEXTURES 0); the patterns that read uvs are left out of one
// without images (HAS_IMAGES 0).

#if HAS_TEXTURES
// Each pattern's code and include and the lists of patterns, generated
// from the table of patterns (src/scene/texture/mod.rs,
// src/gpu/entities.rs); texture_colour(t, hit, p), the colour of texture t
// at p, over them.
#include "textures.glsl"
#include "texture_dispatch.glsl"

// m at the hit point p: its textured colours in place of its own. One call
// site for texture_colour, looped over the two colours: two inlined copies
// of an image lookup made the generic f64 shader slow to compile.
void apply_textures(inout Material m, Hit hit, vec3r p) {
    uint diffuse = m.textures.x;
    uint ambient = m.textures.y;
    uint own_ambient = ambient == diffuse ? 0u : ambient;
    [[dont_unroll]] for (uint k = 0u; k < 2u; k++) {
        uint t = k == 0u ? diffuse : own_ambient;
        if (t != 0u) {
            vec3r c = texture_colour(t - 1u, hit, p);
            if (k == 0u) {
                m.diffuse.rgb = c;
            } else {
                m.ambient.rgb = c;
            }
        }
    }
    if (ambient != 0u && ambient == diffuse) {
        m.ambient.rgb = m.diffuse.rgb;
    }
}
#endif
