// The triangle; mirrors src/prim/triangle.rs (see prim/sphere.glsl for what
// a kind's include gives; a kind with shading normals gives
// <name>_shading besides). Two-sided; a ray that leaves a triangle cannot
// meet it again.

#ifdef INTERSECT_NAIVE
// Moller-Trumbore with a fixed epsilon: the textbook form, not watertight.
real triangle_intersect(Ray r, Triangle tri, bool from_self) {
    vec3r e1 = tri.v1.xyz - tri.v0.xyz;
    vec3r e2 = tri.v2.xyz - tri.v0.xyz;
    vec3r pv = cross(r.dir, e2);
    real det = dot(e1, pv);
    if (det == 0.0) {
        return -1.0;
    }
    real inv = 1.0 / det;
    vec3r tv = r.origin - tri.v0.xyz;
    real u = dot(tv, pv) * inv;
    vec3r qv = cross(tv, e1);
    real v = dot(r.dir, qv) * inv;
    if (u < 0.0 || v < 0.0 || u + v > 1.0) {
        return -1.0;
    }
    real t = dot(e2, qv) * inv;
    return t > NAIVE_EPSILON ? t : -1.0;
}
#else
// v with its axes turned so that kz (the ray's dominant axis) comes last,
// x and y swapped where the ray runs down that axis.
vec3r triangle_permute(vec3r v, uint kz, bool swap) {
    vec3r p = kz == 0u ? v.yzx : (kz == 1u ? v.zxy : v);
    return swap ? p.yxz : p;
}

// Watertight (Woop, Benthin and Wald, JCGT 2013): see src/prim/triangle.rs.
// `precise` keeps each edge function a rounded product minus a rounded
// product: an fma would break the exact sign symmetry between two
// triangles that share the edge.
real triangle_intersect(Ray r, Triangle tri, bool from_self) {
    if (from_self) {
        return -1.0;
    }
    vec3r ad = abs(r.dir);
    uint kz = ad.x > ad.y ? (ad.x > ad.z ? 0u : 2u) : (ad.y > ad.z ? 1u : 2u);
    bool swap = triangle_permute(r.dir, kz, false).z < 0.0;
    vec3r d = triangle_permute(r.dir, kz, swap);
    real sx = d.x / d.z;
    real sy = d.y / d.z;
    real sz = 1.0 / d.z;
    vec3r a = triangle_permute(tri.v0.xyz - r.origin, kz, swap);
    vec3r b = triangle_permute(tri.v1.xyz - r.origin, kz, swap);
    vec3r c = triangle_permute(tri.v2.xyz - r.origin, kz, swap);
    precise real ax = a.x - sx * a.z;
    precise real ay = a.y - sy * a.z;
    precise real bx = b.x - sx * b.z;
    precise real by = b.y - sy * b.z;
    precise real cx = c.x - sx * c.z;
    precise real cy = c.y - sy * c.z;
    precise real u = cx * by - cy * bx;
    precise real v = ax * cy - ay * cx;
    precise real w = bx * ay - by * ax;
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) {
        return -1.0;
    }
    precise real det = u + v + w;
    if (det == 0.0) {
        return -1.0;
    }
    precise real t = (u * (sz * a.z) + v * (sz * b.z) + w * (sz * c.z)) / det;
    return t;
}
#endif

// What a hit keeps: the geometric normal (kept in the vertices' w).
vec4r triangle_shape(Triangle tri) {
    return vec4r(tri.v0.w, tri.v1.w, tri.v2.w, 0.0);
}

vec3r triangle_normal(uint i, vec4r shape, vec3r p) {
    return shape.xyz;
}

// The barycentric coordinates of p, a point in its plane, as
// TriangleR::barycentric.
vec3r triangle_barycentric(Triangle tri, vec3r p) {
    vec3r v0 = tri.v0.xyz;
    vec3r e1 = tri.v1.xyz - v0;
    vec3r e2 = tri.v2.xyz - v0;
    vec3r q = p - v0;
    vec3r c = cross(e1, e2);
    real inv = 1.0 / dot(c, c);
    real b1 = dot(cross(q, e2), c) * inv;
    real b2 = dot(cross(e1, q), c) * inv;
    return vec3r(1.0 - b1 - b2, b1, b2);
}

// The vertex normals interpolated at p by its barycentric coordinates; the
// geometric normal where the triangle is flat. Reads the triangle again,
// once per shaded hit, rather than carry its normals through every test.
vec3r triangle_shading(uint i, vec3r p, vec3r geometric) {
    Triangle tri = triangle_at(i);
    if (tri.meta.z == 0u) {
        return geometric;
    }
    vec3r b = triangle_barycentric(tri, p);
    return normalize(tri.n0.xyz * b.x + tri.n1.xyz * b.y + tri.n2.xyz * b.z);
}

// The vertices' uvs interpolated at p, as TriangleR::uv; kept by the
// triangle's index in the file. The scene's checks give an image texture
// only to triangles with uvs.
vec2r triangle_uv(uint i, vec4r shape, vec3r p) {
#if HAS_UVS
    Triangle tri = triangle_at(i);
    vec3r b = triangle_barycentric(tri, p);
    TriangleUv t = triangle_uv_at(tri.meta.y);
    return t.uv01.xy * b.x + t.uv01.zw * b.y + t.uv2.xy * b.z;
#else
    return vec2r(0.0);
#endif
}

// Its own coordinates (the 2D textures), as TriangleR::frame: from its
// first vertex, u along the edge to the second, v = n x u.
void triangle_frame(uint i, out vec3r origin, out vec3r u, out vec3r v) {
    Triangle tri = triangle_at(i);
    origin = tri.v0.xyz;
    u = normalize(tri.v1.xyz - tri.v0.xyz);
    v = cross(vec3r(tri.v0.w, tri.v1.w, tri.v2.w), u);
}
