// A point light: from a position, in every direction, attenuated with
// distance; mirrors src/scene/light/point.rs.
// Its own numbers: own0.xyz its attenuation's c, l and q.

// How light `light` reaches p: l the unit way to it, dist the distance, att
// the attenuation (1 in a variant whose lights have none, HAS_ATTENUATION 0).
void point_toward(Light light, vec3r p, vec3r n, out vec3r l, out real dist, out real att) {
    vec3r to_light = light.position.xyz - p;
    dist = length(to_light);
    att = 1.0;
#if HAS_ATTENUATION
    vec3r a = light.own0.xyz;
    att = 1.0 / (a.x + a.y * dist + a.z * dist * dist);
#endif
    l = to_light / dist;
}
