// The wavefront schedule (docs/performance.md, Schedules), after Laine,
// Karras and Aila, "Megakernels Considered Harmful" (HPG 2013): a tile's
// paths live in buffers, and each dispatch advances every live path by one
// segment (path_step, shared with the megakernel), over a compacted queue
// of the paths still alive. In the megakernel a SIMD group runs until its
// longest ray tree ends; here a group holds only paths with work to do.
//
// Three stages, chosen by the push constant tile.stage.x:
// - WAVE_START, one invocation per pixel of the tile: the first segment
//   of its first eye ray, as WAVE_BOUNCE does it; the paths that go on are
//   queue 0.
// - WAVE_BOUNCE, one invocation per entry of queue tile.stage.y (a dispatch
//   sized by the queue's own count, indirectly): one segment; a path that
//   ends starts the pixel's next sample, and a pixel whose last sample has
//   ended is written. The paths still alive join the other queue.
// - WAVE_ARGS, one invocation: the other queue's dispatch size from its
//   count, and this queue emptied, for the next bounce.
//
// A pixel's samples are traced one after the other and summed in the
// megakernel's order, so the two schedules give the same bits.

const uint WAVE_START = 0u;
const uint WAVE_BOUNCE = 1u;
const uint WAVE_ARGS = 2u;

// The path this invocation advances: its pixel's index in the tile.
uint path_index;

// A path's words: in path_reals, WAVE_REALS vec4r (the ray's origin and
// weight, its direction, the colour, the pixel's sum, then two a waiting
// refraction ray); in path_words, WAVE_WORDS uvec4 (from, depth, ray type,
// stack top; the sample and whether every loop completed; then one a
// waiting ray). The host defines both strides.
uint reals_at(uint k) {
    return path_index * WAVE_REALS + k;
}

uint words_at(uint k) {
    return path_index * WAVE_WORDS + k;
}

#if HAS_TRANSMISSION
Branch branch_at(uint k) {
    vec4r a = path_reals[reals_at(4u + 2u * k)];
    vec4r b = path_reals[reals_at(5u + 2u * k)];
    uvec4 w = path_words[words_at(2u + k)];
    return Branch(Ray(a.xyz, b.xyz), w.x, w.y, a.w);
}

void set_branch(uint k, Branch b) {
    path_reals[reals_at(4u + 2u * k)] = vec4r(b.ray.origin, b.weight);
    path_reals[reals_at(5u + 2u * k)] = vec4r(b.ray.dir, 0.0);
    path_words[words_at(2u + k)] = uvec4(b.from, b.depth, 0u, 0u);
}
#endif

void store_path(Path s, vec3r sum, uint sample_at, bool complete) {
    path_reals[reals_at(0u)] = vec4r(s.ray.origin, s.weight);
    path_reals[reals_at(1u)] = vec4r(s.ray.dir, 0.0);
    path_reals[reals_at(2u)] = vec4r(s.color, 0.0);
    path_reals[reals_at(3u)] = vec4r(sum, 0.0);
    path_words[words_at(0u)] = uvec4(s.from, s.depth, s.ray_type, s.top);
    path_words[words_at(1u)] = uvec4(sample_at, complete ? 1u : 0u, 0u, 0u);
}

Path load_path(out vec3r sum, out uint sample_at, out bool complete) {
    vec4r a = path_reals[reals_at(0u)];
    vec4r b = path_reals[reals_at(1u)];
    vec4r c = path_reals[reals_at(2u)];
    sum = path_reals[reals_at(3u)].xyz;
    uvec4 w = path_words[words_at(0u)];
    uvec4 v = path_words[words_at(1u)];
    sample_at = v.x;
    complete = v.y != 0u;
    return Path(Ray(a.xyz, b.xyz), c.xyz, a.w, w.x, w.y, w.z, w.w);
}

// Queue q's count and indirect dispatch size in wave_header: the size at
// word 4q (with 1, 1 after it), the count at 4q + 3; its entries from
// q * the tile's pixels in wave_queue.
uint queue_count(uint q) {
    return wave_header[4u * q + 3u];
}

uint queue_base(uint q) {
    return q * tile.rect.z * tile.rect.w;
}

// Traces the next segment of the path of pixel (x, y) of the tile; where
// it ends, starts the pixel's next sample, or writes the pixel after its
// last. A path that goes on is stored and joins queue `next`.
void advance(Path s, vec3r sum, uint sample_at, bool complete, uint x, uint y, uint next) {
    bool alive = path_step(s);
    uint n = SAMPLES;
    if (!alive) {
        sum += s.color;
        sample_at++;
        if (sample_at < n * n) {
            COUNT(COUNT_EYE);
            s = start_path(primary_ray(x, y, sample_at % n, sample_at / n));
            alive = true;
        }
    }
    complete = complete && loops_completed();
    // One atomic per subgroup, not per path: the paths that go on count
    // themselves with a ballot, and the first lane takes their slots.
    uvec4 going_on = subgroupBallot(alive);
    uint base = 0u;
    if (subgroupElect()) {
        base = atomicAdd(wave_header[4u * next + 3u], subgroupBallotBitCount(going_on));
    }
    base = subgroupBroadcastFirst(base);
    if (alive) {
        store_path(s, sum, sample_at, complete);
        uint slot = base + subgroupBallotExclusiveBitCount(going_on);
        wave_queue[queue_base(next) + slot] = path_index;
    } else {
        pixels[path_index] = vec4(vec3(sum * (1.0 / real(n * n))), complete ? 1.0 : 0.0);
    }
}

// The first segment of every pixel's first sample, in the pixels' order
// (the most coherent rays, laid out as the megakernel lays them): only the
// paths that go on are stored, in queue 0.
void wave_start() {
    uvec2 local = gl_GlobalInvocationID.xy;
    if (local.x >= tile.rect.z || local.y >= tile.rect.w) {
        return;
    }
    path_index = local.y * tile.rect.z + local.x;
    uint x = tile.rect.x + local.x;
    uint y = tile.rect.y + local.y;
    begin_counts();
    COUNT(COUNT_EYE);
    advance(start_path(primary_ray(x, y, 0u, 0u)), vec3r(0.0), 0u, true, x, y, 0u);
    end_counts();
}

void wave_bounce(uint q) {
    uint group = gl_WorkGroupSize.x * gl_WorkGroupSize.y;
    uint entry = gl_WorkGroupID.x * group + gl_LocalInvocationIndex;
    if (entry >= queue_count(q)) {
        return;
    }
    path_index = wave_queue[queue_base(q) + entry];
    begin_counts();
    vec3r sum;
    uint sample_at;
    bool complete;
    Path s = load_path(sum, sample_at, complete);
    uint x = tile.rect.x + path_index % tile.rect.z;
    uint y = tile.rect.y + path_index / tile.rect.z;
    advance(s, sum, sample_at, complete, x, y, 1u - q);
    end_counts();
}

// q: the queue the last bounce filled.
void wave_args(uint q) {
    if (gl_LocalInvocationIndex != 0u) {
        return;
    }
    uint group = gl_WorkGroupSize.x * gl_WorkGroupSize.y;
    wave_header[4u * q] = (queue_count(q) + group - 1u) / group;
    wave_header[4u * (1u - q)] = 0u;
    wave_header[4u * (1u - q) + 3u] = 0u;
}

void main() {
    uint stage = tile.stage.x;
    if (stage == WAVE_START) {
        wave_start();
    } else if (stage == WAVE_BOUNCE) {
        wave_bounce(tile.stage.y);
    } else {
        wave_args(tile.stage.y);
    }
}
