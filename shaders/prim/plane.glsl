// The plane; mirrors src/prim/plane.rs (see prim/sphere.glsl for what a
// kind's include gives). A ray that leaves a plane cannot meet it again.

real plane_intersect(Ray r, Plane p, bool from_self) {
#ifdef INTERSECT_NAIVE
    real t = dot(p.point.xyz - r.origin, p.normal.xyz) / dot(r.dir, p.normal.xyz);
    return t > NAIVE_EPSILON ? t : -1.0;
#else
    if (from_self) {
        return -1.0;
    }
    real denom = dot(r.dir, p.normal.xyz);
    if (denom == 0.0) {
        return -1.0;
    }
    return dot(p.point.xyz - r.origin, p.normal.xyz) / denom;
#endif
}

vec4r plane_shape(Plane p) {
    return p.normal;
}

vec3r plane_normal(uint i, vec4r shape, vec3r p) {
    return shape.xyz;
}

// Its own coordinates (the 2D textures), as PlaneR::frame: from its origin
// (the file's point, moved with the plane, where `point` is the one nearest
// the eye),
// u = normalize(a x n) with a the coordinate axis least along n (x, then y,
// on a tie), and v = n x u.
void plane_frame(uint i, out vec3r origin, out vec3r u, out vec3r v) {
    Plane pl = plane_at(i);
    vec3r n = pl.normal.xyz;
    vec3r m = abs(n);
    vec3r a = m.x <= m.y && m.x <= m.z ? vec3r(1.0, 0.0, 0.0)
            : (m.y <= m.z ? vec3r(0.0, 1.0, 0.0) : vec3r(0.0, 0.0, 1.0));
    origin = pl.origin.xyz;
    u = normalize(cross(a, n));
    v = cross(n, u);
}

// Its own coordinates as uv, as PlaneR::uv.
vec2r plane_uv(uint i, vec4r shape, vec3r p) {
    vec3r origin, u, v;
    plane_frame(i, origin, u, v);
    vec3r q = p - origin;
    return vec2r(dot(q, u), dot(q, v));
}
