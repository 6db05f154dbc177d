// The cylinder and the cone: open, two-sided; mirrors src/prim/cylinder.rs
// (see prim/sphere.glsl for what a kind's include gives). The radius at
// height y above the centre is center.w + slope.x * y, for |y| <= axis.w.

// The quadric A t^2 + 2 b t + c = 0 of the ray from f (its origin less the
// centre) along d: A and b, and f's height, its part across the axis and
// the radius at its height.
void cylinder_quadric(Cylinder cy, vec3r f, vec3r d, out real qa, out real b,
                      out real fy, out vec3r fx, out real r) {
    vec3r a = cy.axis.xyz;
    real k = cy.slope.x;
    fy = dot(f, a);
    real dy = dot(d, a);
    fx = f - a * fy;
    vec3r dx = d - a * dy;
    r = cy.center.w + k * fy;
    qa = dot(dx, dx) - k * k * dy * dy;
    b = dot(fx, dx) - k * dy * r;
}

#ifdef INTERSECT_NAIVE
// The textbook form: the quadric from the ray's origin, the plain c and a
// fixed epsilon.
real cylinder_intersect(Ray r, Cylinder cy, bool from_self) {
    real qa, b, fy, rad;
    vec3r fx;
    cylinder_quadric(cy, r.origin - cy.center.xyz, r.dir, qa, b, fy, fx, rad);
    real c = dot(fx, fx) - rad * rad;
    real disc = b * b - qa * c;
    if (qa == 0.0 || disc < 0.0) {
        return -1.0;
    }
    real root = sqrt(disc);
    real dy = dot(r.dir, cy.axis.xyz);
    real t0 = (-b - root) / qa;
    real t1 = (-b + root) / qa;
    real near = min(t0, t1);
    real far = max(t0, t1);
    if (near > NAIVE_EPSILON && abs(fy + near * dy) <= cy.axis.w) {
        return near;
    }
    return far > NAIVE_EPSILON && abs(fy + far * dy) <= cy.axis.w ? far : -1.0;
}
#else
// Solved from the ray's point closest to the centre, with the exact power:
// see src/prim/cylinder.rs.
real cylinder_intersect(Ray r, Cylinder cy, bool from_self) {
    real qa, b, fy, rad;
    vec3r fx;
    vec3r d = r.dir;
    real dy = dot(d, cy.axis.xyz);
    real half_length = cy.axis.w;
    if (from_self) {
        cylinder_quadric(cy, r.origin - cy.center.xyz, d, qa, b, fy, fx, rad);
        if (qa == 0.0) {
            return -1.0;
        }
        real t = -2.0 * b / qa;
        return abs(fy + t * dy) <= half_length ? t : -1.0;
    }
    real tm = dot(cy.center.xyz - r.origin, d);
    cylinder_quadric(cy, r.origin + d * tm - cy.center.xyz, d, qa, b, fy, fx, rad);
    real c = power(fx, rad);
    real t0, t1;
    if (qa == 0.0) {
        // A ray along a cone's side meets the double cone once.
        if (b == 0.0) {
            return -1.0;
        }
        t0 = -c / (2.0 * b);
        t1 = t0;
    } else {
        real disc = b * b - qa * c;
        if (disc < 0.0) {
            return -1.0;
        }
        real root = sqrt(disc);
        real q = b >= 0.0 ? -b - root : -b + root;
        if (q == 0.0) {
            return -1.0;
        }
        real u = c / q;
        real v = q / qa;
        t0 = min(u, v);
        t1 = max(u, v);
    }
    if (tm + t0 > 0.0 && abs(fy + t0 * dy) <= half_length) {
        return tm + t0;
    }
    return tm + t1 > 0.0 && abs(fy + t1 * dy) <= half_length ? tm + t1 : -1.0;
}
#endif

// What a hit keeps: nothing; the normal reads the cylinder again.
vec4r cylinder_shape(Cylinder cy) {
    return vec4r(0.0);
}

vec3r cylinder_normal(uint i, vec4r shape, vec3r p) {
    Cylinder cy = cylinder_at(i);
    vec3r a = cy.axis.xyz;
    vec3r q = p - cy.center.xyz;
    vec3r across = q - a * dot(q, a);
    real len = length(across);
    if (len == 0.0) {
        // A cone's tip: the mean of the normals around it.
        return a * -sign(cy.slope.x);
    }
    return normalize(across / len - a * cy.slope.x);
}
