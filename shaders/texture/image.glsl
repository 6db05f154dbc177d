// An image's texels at the surface's uv coordinates, filtered bilinearly and
// repeated; mirrors src/scene/texture/image.rs. Left out of a variant whose
// materials have no image (HAS_IMAGES 0).

#if HAS_IMAGES
// Cell x (a whole number) of a row (or column) of n, repeated: x mod n,
// kept inside 0..n-1 where the rounding of a huge x would leave it outside.
// A quotient a whole number q (x = 16, n = 16) may come out a few ULP below
// q on a conformant driver (division is 2.5 ULP), and its floor q - 1: the
// remainder is then n, which the first correction takes back to 0
// (`--spec-worst` found it: docs/guarantees.md).
uint image_wrap(real x, uint n) {
    real nr = real(n);
    real m = x - nr * floor(x / nr);
    if (m >= nr) {
        m -= nr;
    }
    if (m < 0.0) {
        m += nr;
    }
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
// centres at half-texel offsets; times the tint.
vec3r image_filtered(Texture tx, vec2r uv) {
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

// The image at the surface's uv, turned and scaled.
vec3r image_colour(Texture tx, Hit hit, vec3r p) {
    real size = tx.origin_size.w;
    vec2r st = surface_uv(hit, p);
    real c = tx.rotation.x;
    real s = tx.rotation.y;
    return image_filtered(tx, vec2r((c * st.x + s * st.y) / size, (c * st.y - s * st.x) / size));
}
#endif
