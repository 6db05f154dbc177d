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
        // The geometric normal says which side the ray is on; the shading
        // normal is turned with it to face the ray.
        vec3r outward = surface(hit, p);
        vec3r shading = shading_normal(hit, p, outward);
        bool back = dot(outward, ray.dir) > 0.0;
        vec3r n = back ? -shading : shading;
        // Where the rays that leave on the ray's side start.
        p = leave(hit, p, ray.origin, back ? -outward : outward);
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
