// Eye rays through the virtual screen (docs/scene-format.md, Rays); mirrors src/cpu/ray.rs.

struct Ray {
    vec3r origin;
    vec3r dir;               // unit length
};

// The eye ray through the point (px, py) of the image, in pixels (the
// centre of pixel x is at x + 0.5): adaptive sampling's rays between the
// corners. Mirrors ray_through() in src/cpu/ray.rs.
Ray ray_through(real px, real py) {
    real u = 2.0 * px / real(g.size.x) - 1.0;
    real v = 1.0 - 2.0 * py / real(g.size.y);
    vec3r to_pixel = g.to_screen.xyz + g.screen_right.xyz * u + g.screen_up.xyz * v;
    return Ray(g.eye.xyz, normalize(to_pixel));
}

Ray primary_ray(uint x, uint y, uint i, uint j) {
    real n = real(g.size.z);
    real u = 2.0 * (real(x) + (real(i) + 0.5) / n) / real(g.size.x) - 1.0;
    real v = 1.0 - 2.0 * (real(y) + (real(j) + 0.5) / n) / real(g.size.y);
    vec3r to_pixel = g.to_screen.xyz + g.screen_right.xyz * u + g.screen_up.xyz * v;
    return Ray(g.eye.xyz, normalize(to_pixel));
}
