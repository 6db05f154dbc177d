// The specular term of one light: Blinn-Phong, (N.H)^n with H halfway
// between L and V (docs/scene-format.md, Shading); mirrors specular() in src/cpu/shade.rs. Its own
// file so that another model can replace it alone
// (shaders/experiments/phong).

real specular(vec3r n, vec3r l, vec3r v, real shininess) {
    vec3r h = normalize(l + v);
    return spec_pow(max(dot(n, h), 0.0), shininess);
}
