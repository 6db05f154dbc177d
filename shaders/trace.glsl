// The fixed-depth reflection loop (docs/scene-format.md, Shading); mirrors src/cpu/trace.rs.

vec3r trace(Ray ray) {
    vec3r color = vec3r(0.0);
#if HAS_OBJECTS
    real weight = 1.0;
    uint from = NONE;
    // Never unrolled: with MAX_DEPTH a constant the compiler could copy the
    // whole bounce up to 64 times, for a large and slow-to-compile shader.
    [[dont_unroll]] for (uint depth = 1u; depth <= MAX_DEPTH; depth++) {
        Hit hit;
        if (!intersect_scene(ray, from, INF, hit)) {
            color += g.background.rgb * weight;
            break;
        }
        vec3r p = ray.origin + ray.dir * hit.t;
        vec3r outward = surface(hit, p);
        vec3r n = dot(outward, ray.dir) > 0.0 ? -outward : outward;
        Material m = materials[hit.material];
        color += shade(p, n, -ray.dir, m, hit.prim) * weight;
        real kr = m.params.y;
        if (depth == MAX_DEPTH || kr == 0.0) {
            break;
        }
        weight *= kr;
        if (weight == 0.0) {
            break;
        }
        vec3r d = ray.dir - n * (2.0 * dot(ray.dir, n));
        ray = Ray(p, normalize(d));
        from = hit.prim;
    }
#else
    color = g.background.rgb;
#endif
    return color;
}
