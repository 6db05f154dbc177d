// Experiment: a normals view. Replaces trace.glsl: each pixel shows the
// normal at the first hit, facing the viewer, mapped from [-1, 1] to [0, 1]
// per axis; the background where nothing is hit.
//
//   glint render scenes/showcase.toml -I shaders/experiments/normals -o normals.png

vec3 trace(Ray ray) {
#if HAS_OBJECTS
    Hit hit;
    if (intersect_scene(ray, NONE, INF, hit)) {
        vec3 p = ray.origin + ray.dir * hit.t;
        vec3 n = surface(hit, p);
        n = dot(n, ray.dir) > 0.0 ? -n : n;
        return n * 0.5 + 0.5;
    }
#endif
    return g.background.rgb;
}
