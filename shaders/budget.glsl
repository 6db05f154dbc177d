// Whether this invocation's loops all ran to their end. llvmpipe (Mesa's
// lavapipe) gives each SIMD group a budget of about 65,535 loop iterations,
// shared by every loop of the shader; past it each loop exits at once,
// silently. A canary loop of two iterations, run last, sees that: once the
// budget is spent it stops after one. The trip count comes from the push
// constant so that no compiler can fold the loop away. The pixel's alpha
// carries the answer (1 complete, 0 cut short) and the host refuses an image
// with any 0 (docs/shaders.md, The loop budget).
// A driver known to run every loop to its end (llvmpipe from Mesa 25.0)
// gets NO_LOOP_CANARY: the canary costs 2–4 % there (docs/performance.md).
#ifdef NO_LOOP_CANARY
bool loops_completed() {
    return true;
}
#else
bool loops_completed() {
    uint trips = tile.rect.z != 0u ? 2u : 3u;
    uint ran = 0u;
    [[dont_unroll]] for (uint i = 0u; i < trips; i++) {
        ran++;
    }
    return ran == trips;
}
#endif
