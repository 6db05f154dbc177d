// The checkers: squares in a surface's own coordinates, and cubes in the
// scene's; mirrors src/scene/texture/checker.rs.

// color0 where the cells' indices sum to an even number, else color1.
vec3r checker_pick(Texture tx, real cells) {
    bool odd = cells - 2.0 * floor(cells * 0.5) != 0.0;
    return odd ? tx.color1.rgb : tx.color0.rgb;
}

// Squares of side size in the surface's own coordinates, turned.
vec3r checker_colour(Texture tx, Hit hit, vec3r p) {
    real size = tx.origin_size.w;
    vec3r origin, u, v;
    surface_frame(hit, origin, u, v);
    vec3r q = p - origin;
    real a = dot(q, u);
    real b = dot(q, v);
    real c = tx.rotation.x;
    real s = tx.rotation.y;
    return checker_pick(tx, floor((c * a + s * b) / size) + floor((c * b - s * a) / size));
}

// Cubes of side size in the scene's coordinates, from a corner at origin.
vec3r solid_checker_colour(Texture tx, Hit hit, vec3r p) {
    real size = tx.origin_size.w;
    vec3r q = p - tx.origin_size.xyz;
    return checker_pick(tx, floor(q.x / size) + floor(q.y / size) + floor(q.z / size));
}
