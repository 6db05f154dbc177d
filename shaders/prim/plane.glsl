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
