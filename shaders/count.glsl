// The counters of `glint render --stats` (src/stats.rs, docs/spd.md): where
// the host defines COUNT_RAYS, each invocation counts its rays, and the
// ray/primitive tests by kind and the BVH nodes visited by each type of
// ray (COUNT_AS sets the type of the ray being traced), and adds them to
// the Counts block when it ends; elsewhere the hooks are empty and the
// shader is as it was. The events are counted where src/cpu counts them.
// The loops over the slots are unrolled: they cost nothing of llvmpipe's
// loop budget (budget.glsl).
#ifdef COUNT_RAYS
uint counted[COUNT_SLOTS];
uint counting_as = RAY_EYE;
#define COUNT(slot) counted[slot]++
#define COUNT_AS(type) counting_as = (type)
#define COUNT_NODE() counted[COUNT_WORK + counting_as * COUNT_PER_TYPE]++
#define COUNT_CELL() counted[COUNT_WORK + counting_as * COUNT_PER_TYPE + 1u]++
#define COUNT_TEST(kind) counted[COUNT_WORK + counting_as * COUNT_PER_TYPE + 2u + (kind)]++

void begin_counts() {
    [[unroll]] for (uint i = 0u; i < COUNT_SLOTS; i++) {
        counted[i] = 0u;
    }
}

// Adds this invocation's counts to the block's 64-bit slots (a low and a
// high word each: 32-bit atomics are what every device has), carrying
// where the low word wraps.
void end_counts() {
    [[unroll]] for (uint i = 0u; i < COUNT_SLOTS; i++) {
        uint n = counted[i];
        if (n != 0u) {
            uint before = atomicAdd(count_words[2u * i], n);
            if (before + n < before) {
                atomicAdd(count_words[2u * i + 1u], 1u);
            }
        }
    }
}
#else
#define COUNT(slot)
#define COUNT_AS(type)
#define COUNT_NODE()
#define COUNT_CELL()
#define COUNT_TEST(kind)
#define begin_counts()
#define end_counts()
#endif
