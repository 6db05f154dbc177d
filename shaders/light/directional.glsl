// A directional light: from infinitely far, one way, not attenuated;
// mirrors src/scene/light/directional.rs.

void directional_toward(Light light, vec3r p, vec3r n, out vec3r l, out real dist, out real att) {
    l = -light.direction.xyz;
    dist = INF;
    att = 1.0;
}
