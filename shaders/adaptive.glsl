// Whitted's adaptive antialiasing on the GPU (docs/scene-format.md, Rays):
// the host splits the squares level by level (src/sampling/adaptive.rs), as the
// CPU does, and lists each level's new points, each once though two squares
// share it; one invocation traces one point. Mirrors trace_points() in
// src/cpu/adaptive.rs.

// The colour at point p of the image, traced through the corner grid's
// screen (its pixel centres are the image's corners). Its place in pixels
// is a dyadic fraction, exact in f32 and f64.
vec3r trace_point(Refine p) {
    real scale = 1.0 / real(1u << p.point.z);
    real px = real(p.point.x) * scale;
    real py = real(p.point.y) * scale;
    return trace(ray_through(px + 0.5, py + 0.5));
}
