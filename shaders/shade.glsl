// Local Blinn-Phong shading with hard shadows (docs/scene-format.md, Shading); mirrors
// src/cpu/shade.rs.

// x^n with the scene format's conventions: x^0 = 1 (also for x = 0), and 0 for x <= 0
// otherwise; GLSL's pow leaves both undefined. x is a cosine, taken at most
// 1: the rounding of unit vectors can put their dot product an ulp past it,
// and a large n would raise that past the shading's bound.
real spec_pow(real x, real n) {
    if (n == 0.0) {
        return 1.0;
    }
    if (x <= 0.0) {
        return 0.0;
    }
    x = min(x, 1.0);
#ifdef GLINT_F64
    // GLSL has no double pow: the specular power is taken in float.
    return real(pow(float(x), float(n)));
#else
    return pow(x, n);
#endif
}

#include "specular.glsl"
#include "record.glsl"
#include "tree.glsl"
// Each light type's include and the lists of types, generated from the
// table of light types (src/scene/light/mod.rs, src/gpu/entities.rs); the
// dispatch over them.
#include "lights.glsl"
#include "light_dispatch.glsl"

// The sum of every light's contribution at p, where n faces the viewer.
vec3r shade(vec3r p, vec3r n, vec3r v, Material m, uint from) {
    vec3r local = vec3r(0.0);
#if HAS_LIGHTS
    LIGHT_LOOP for (uint k = 0u; k < LIGHT_COUNT; k++) {
        Light light = light_at(k);
        vec3r l;
        real dist;
        real att;
        light_toward(light, p, n, l, dist, att);
        vec3r ambient = light.ambient.rgb * m.ambient.rgb;
        // A light exactly at p has no direction: it adds its ambient term only.
        if (dist == 0.0) {
            local += ambient * att;
            continue;
        }
        real cone = light_cone(light, p, n, l);
        vec3r contribution = ambient;
        real n_dot_l = dot(n, l);
        // No shadow ray where the direct term would be zero anyway: facing
        // away, outside a light's cone, or a light without diffuse and specular.
        bool direct = n_dot_l > 0.0 && cone > 0.0 && light.meta.y != 0u;
#if HAS_SHADOWS
        if (direct && SHADOWS_ON) {
            COUNT(COUNT_SHADOW);
            COUNT_AS(RAY_SHADOW);
            direct = !occluded(Ray(p, l), from, dist, light);
            RECORD_SHADOW(k, Ray(p, l), from, dist, !direct);
            TREE_NOTE(TREE_SHADOW(!direct));
        }
#endif
        if (direct) {
            // A cosine: at most 1, whatever the rounding (spec_pow).
            contribution += light.diffuse.rgb * m.diffuse.rgb * min(n_dot_l, 1.0)
                          + light.specular.rgb * m.specular.rgb * specular(n, l, v, m.params.x);
        }
        RECORD_LIGHT(k, n_dot_l, cone, direct, ambient * (att * cone),
                     light.diffuse.rgb * m.diffuse.rgb * min(n_dot_l, 1.0) * (att * cone),
                     light.specular.rgb * m.specular.rgb * specular(n, l, v, m.params.x) * (att * cone));
        local += contribution * (att * cone);
    }
#endif
    RECORD_LOCAL(local);
    return local;
}
