// The dispatch over the light types, written once over the variant's
// lists of them; mirrors LightKind::toward and LightKind::cone
// (src/scene/light/mod.rs). lights.glsl, generated for the variant from the
// table of light types (src/gpu/entities.rs), includes every type's file
// (shaders/light/) and defines the lists: LIGHTS_PRESENT(X) calls
// X(UPPER, name) for each type the variant's lights take, LIGHTS_CONE(X)
// for those of them with a cone. ONE_LIGHT_TYPE: one type is all there is,
// and a light's type is not tested.

// The light is of type UPPER.
#define IS_LIGHT(light, UPPER) (ONE_LIGHT_TYPE || (light).meta.x == LIGHT_##UPPER)

// How light `light` reaches p (of normal n): l the unit way to it, dist
// the distance (INF without a position), att the attenuation.
#define TOWARD(UPPER, name) \
    if (IS_LIGHT(light, UPPER)) { \
        name##_toward(light, p, n, l, dist, att); \
        return; \
    }
void light_toward(Light light, vec3r p, vec3r n, out vec3r l, out real dist, out real att) {
    LIGHTS_PRESENT(TOWARD)
    l = vec3r(0.0);
    dist = INF;
    att = 1.0;
}

// The share of the light at p (of normal n) in direction l (unit, towards
// it), 0..1: 1 but for the types with a cone.
#define CONE(UPPER, name) \
    if (IS_LIGHT(light, UPPER)) { \
        return name##_cone(light, p, n, l); \
    }
real light_cone(Light light, vec3r p, vec3r n, vec3r l) {
    LIGHTS_CONE(CONE)
    return 1.0;
}
