// Whitted's adaptive antialiasing, the second pass (docs/scene-format.md,
// Rays): a pixel whose corners differ by more than ADAPTIVE_THRESHOLD steps
// of 1/255 is
// split into four, each quarter in turn, at most ADAPTIVE_LEVELS times, and
// its colour is the mean of its squares' corners weighted by their areas.
// The host lists the pixels to split from the corner image, as the CPU
// chooses them; mirrors src/cpu/adaptive.rs.

// One square of the pixel waiting to be resolved: its top-left corner in
// pixels of the image, its side, its level, and its corners' colours
// (top-left, top-right, bottom-left, bottom-right).
struct Square {
    real x;
    real y;
    real size;
    uint level;
    vec3r c[4];
};

// The largest minus the smallest of the corners, in the channel where that
// is largest, in steps of 1/255 (Adaptive::STEPS; its twin is Adaptive::contrast):
// colours that differ by rounding count the same but where one sits on a
// step.
real contrast(vec3r c[4]) {
    vec3r s0 = floor(c[0] * 255.0 + 0.5);
    vec3r s1 = floor(c[1] * 255.0 + 0.5);
    vec3r s2 = floor(c[2] * 255.0 + 0.5);
    vec3r s3 = floor(c[3] * 255.0 + 0.5);
    vec3r hi = max(max(s0, s1), max(s2, s3));
    vec3r lo = min(min(s0, s1), min(s2, s3));
    vec3r d = hi - lo;
    return max(d.x, max(d.y, d.z));
}

// The colour at the point (px, py) of the image, in pixels, traced through
// the corner grid's screen (its pixel centres are the image's corners).
vec3r trace_at(real px, real py) {
    return trace(ray_through(px + 0.5, py + 0.5));
}

// Where a split square's five new points lie, in halves of its side.
const uint FIVE_X[5] = uint[5](1u, 0u, 1u, 2u, 1u);
const uint FIVE_Y[5] = uint[5](0u, 1u, 1u, 1u, 2u);

vec3r refine_pixel(Refine e) {
    // Depth first: at most three squares wait at each level, and the one
    // being split.
    Square stack[3u * ADAPTIVE_LEVELS + 1u];
    vec3r corners[4] = vec3r[4](vec3r(e.c00), vec3r(e.c10), vec3r(e.c01), vec3r(e.c11));
    stack[0] = Square(real(e.x), real(e.y), 1.0, 0u, corners);
    uint top = 1u;
    vec3r sum = vec3r(0.0);
    [[dont_unroll]] while (top > 0u) {
        top--;
        Square s = stack[top];
        // The pixel itself is split: the host chose it.
        if (s.level == 0u || s.level < ADAPTIVE_LEVELS && contrast(s.c) > real(ADAPTIVE_THRESHOLD)) {
            real h = s.size * 0.5;
            // The five new points, in this order on both renderers: top,
            // left, middle, right, bottom (h·2 is the side exactly). One
            // call site for trace(): five inlined the whole ray tree five
            // times, and lavapipe took over 300 s to compile the f64
            // generic shader.
            vec3r q[5];
            [[dont_unroll]] for (uint i = 0u; i < 5u; i++) {
                q[i] = trace_at(s.x + h * real(FIVE_X[i]), s.y + h * real(FIVE_Y[i]));
            }
            vec3r t = q[0];
            vec3r l = q[1];
            vec3r m = q[2];
            vec3r r = q[3];
            vec3r b = q[4];
            uint k = s.level + 1u;
            // Pushed last to first: the top-left quarter is resolved first.
            stack[top] = Square(s.x + h, s.y + h, h, k, vec3r[4](m, r, b, s.c[3]));
            stack[top + 1u] = Square(s.x, s.y + h, h, k, vec3r[4](l, m, s.c[2], b));
            stack[top + 2u] = Square(s.x + h, s.y, h, k, vec3r[4](t, s.c[1], m, r));
            stack[top + 3u] = Square(s.x, s.y, h, k, vec3r[4](s.c[0], t, l, m));
            top += 4u;
        } else {
            sum += (s.c[0] + s.c[1] + s.c[2] + s.c[3]) * (s.size * s.size * 0.25);
        }
    }
    return sum;
}
