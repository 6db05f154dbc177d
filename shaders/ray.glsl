// Eye rays through the virtual screen (SPEC §2); mirrors src/cpu/ray.rs.

struct Ray {
    vec3 origin;
    vec3 dir;               // unit length
};

Ray primary_ray(uint x, uint y, uint i, uint j) {
    float n = float(g.size.z);
    float u = 2.0 * (float(x) + (float(i) + 0.5) / n) / float(g.size.x) - 1.0;
    float v = 1.0 - 2.0 * (float(y) + (float(j) + 0.5) / n) / float(g.size.y);
    vec3 to_pixel = g.to_screen.xyz + g.screen_right.xyz * u + g.screen_up.xyz * v;
    return Ray(g.eye.xyz, normalize(to_pixel));
}
