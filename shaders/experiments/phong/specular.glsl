// Experiment: Phong instead of Blinn-Phong. Replaces specular.glsl: the
// specular term is (R.V)^n with R the light reflected about N, as the seed
// article first writes it, instead of (N.H)^n. Highlights come out smaller
// for the same n; `glint compare` shows how far the image departs from the
// reference, which keeps Blinn-Phong.
//
//   glint render scenes/showcase.toml -I shaders/experiments/phong -o phong.png

real specular(vec3r n, vec3r l, vec3r v, real shininess) {
    vec3r r = reflect(-l, n);
    return spec_pow(max(dot(r, v), 0.0), shininess);
}
