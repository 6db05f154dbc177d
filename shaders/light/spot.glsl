// A spot light: a point light within a cone about its axis, falling off
// towards the cone's edge; mirrors src/scene/light/spot.rs.
// Its own numbers: a point light's in own0, then own1.x the cosine of its
// cutoff and own1.y its exponent.

void spot_toward(Light light, vec3r p, vec3r n, out vec3r l, out real dist, out real att) {
    point_toward(light, p, n, l, dist, att);
}

// The share of the light in direction l (unit, towards it): 0 outside the
// cone, cos^exponent inside.
real spot_cone(Light light, vec3r p, vec3r n, vec3r l) {
    real cos_theta = dot(-l, light.direction.xyz);
    return cos_theta >= light.own1.x ? spec_pow(cos_theta, light.own1.y) : 0.0;
}
