// Textures (docs/scene-format.md, Textures): a material's diffuse colour,
// and its ambient colour, from a pattern or an image at the hit point;
// mirrors src/cpu/texture.rs. Left out of a variant whose materials have
// none (HAS_TEXTURES 0); images are left out of one without them
// (HAS_IMAGES 0).

#if HAS_TEXTURES
const uint PATTERN_CHECKER = 1u;
const uint PATTERN_SOLID_CHECKER = 2u;
const uint PATTERN_IMAGE = 3u;

#if HAS_IMAGES
// Cell x of a row (or column) of n, repeated: x mod n, kept inside 0..n-1
// where the rounding of a huge x would leave it outside.
uint image_wrap(real x, uint n) {
    real m = x - real(n) * floor(x / real(n));
    return uint(clamp(m, 0.0, real(n - 1u)));
}

// Texel (x, y) of the image whose top-left texel is `first`, `width` a row.
vec3r image_texel(uint first, uint width, uint x, uint y) {
    return vec3r(texel_at(first + y * width + x).rgb);
}

// a + (b - a) t, written as the CPU reference writes it.
vec3r image_lerp(vec3r a, vec3r b, real t) {
    return a * (1.0 - t) + b * t;
}

// The image's colour at uv, filtered bilinearly between the four nearest
// texel centres and repeated: v = 0 at its bottom row, 1 at its top, texel
// centres at half-texel offsets. Mirrors image_colour in src/cpu/texture.rs.
vec3r image_colour(Texture tx, vec2r uv) {
    uint w = tx.meta.z;
    uint h = tx.meta.w;
    real x = uv.x * real(w) - 0.5;
    real y = (1.0 - uv.y) * real(h) - 0.5;
    real x0 = floor(x);
    real y0 = floor(y);
    real fx = x - x0;
    real fy = y - y0;
    uint i0 = image_wrap(x0, w);
    uint i1 = image_wrap(x0 + 1.0, w);
    uint j0 = image_wrap(y0, h);
    uint j1 = image_wrap(y0 + 1.0, h);
    uint first = tx.meta.y;
    vec3r top = image_lerp(image_texel(first, w, i0, j0), image_texel(first, w, i1, j0), fx);
    vec3r bottom = image_lerp(image_texel(first, w, i0, j1), image_texel(first, w, i1, j1), fx);
    return image_lerp(top, bottom, fy) * tx.color0.rgb;
}
#endif

// The colour of texture t at p, a point of the primitive hit: an image's at
// the surface's uv, turned and scaled; a pattern's of the square (or cube)
// p is in, color0 where the cells' indices sum to an even number.
vec3r texture_colour(uint t, Hit hit, vec3r p) {
    Texture tx = texture_at(t);
    real size = tx.origin_size.w;
#if HAS_IMAGES
    if (tx.meta.x == PATTERN_IMAGE) {
        vec2r st = surface_uv(hit, p);
        real c = tx.rotation.x;
        real s = tx.rotation.y;
        return image_colour(tx, vec2r((c * st.x + s * st.y) / size, (c * st.y - s * st.x) / size));
    }
#endif
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
