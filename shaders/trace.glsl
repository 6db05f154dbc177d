// The fixed-depth reflection loop (SPEC §3); mirrors src/cpu/trace.rs.

vec3 trace(Ray ray) {
    vec3 color = vec3(0.0);
    float weight = 1.0;
    uint from = NONE;
    for (uint depth = 1u; depth <= g.size.w; depth++) {
        Hit hit;
        if (!intersect_scene(ray, from, INF, hit)) {
            color += g.background.rgb * weight;
            break;
        }
        vec3 p = ray.origin + ray.dir * hit.t;
        vec3 outward = surface(hit, p);
        vec3 n = dot(outward, ray.dir) > 0.0 ? -outward : outward;
        Material m = material(hit.material);
        color += shade(p, n, -ray.dir, m, hit.prim) * weight;
        float kr = m.params.y;
        if (depth == g.size.w || kr == 0.0) {
            break;
        }
        weight *= kr;
        vec3 d = ray.dir - n * (2.0 * dot(ray.dir, n));
        ray = Ray(p, normalize(d));
        from = hit.prim;
    }
    return color;
}
