// The light buffers and the eye's tiles (src/accel/tables.rs): a shadow
// ray reads the cell of its light's table, an eye ray its tile, and tests
// the BVH leaves listed there instead of walking the tree; mirrors
// `Tables::shadow` and `Tables::eye` there and the scans in
// src/cpu/intersect.rs.
//
// The tables are one array of 16-byte words (table_at(i).w): the grids'
// records (TableGrid, TABLE_GRID_WORDS each, read whole with TABLE_GRID_AT
// or a member with TABLE_GRID_<MEMBER>: generated from
// `tables::grid_record`), from word 0; then the
// cells, two to a word (first entry, count), from g.tables.x; then the
// entries, two to a word (primitive word, key bits), from g.tables.y. The
// eye's grid is in the uniform block (g.eye_*, where g.tables.z is 1); a
// light's meta.z is its first grid + 1 (0: none), meta.w its reach. A
// grid's form (TABLE_PARALLEL, TABLE_PERSPECTIVE: `tables::GridForm`):
// rows that take a point (one grid, a light without a position) or a
// direction (six, a cube around a light's position).

const uint TABLE_WALK = 0xffffffffu;
// The slack on a perspective key's bound (KEY_SLACK in src/accel/tables.rs).
const real KEY_SLACK = 1.0 + 1.0 / 4096.0;

// Entry i of every list: (primitive word, key bits).
uvec2 table_entry(uint i) {
    uvec4 w = table_at(g.tables.y + (i >> 1)).w;
    return (i & 1u) != 0u ? w.zw : w.xy;
}

uint table_index(real x, float x0, float s, uint n) {
    real c = floor((x - real(x0)) * real(s));
    return uint(clamp(c, real(0.0), real(n - 1u)));
}

// The list of the cell at (a, b) of the grid whose range is (a0, b0, sa, sb)
// and whose cells are (first, na, nb): (first entry, count or TABLE_WALK).
uvec2 table_cell(vec4 range, uvec4 cells, real a, real b) {
    uint c = cells.x + table_index(b, range.y, range.w, cells.z) * cells.y
           + table_index(a, range.x, range.z, cells.y);
    uvec4 w = table_at(g.tables.x + (c >> 1)).w;
    return (c & 1u) != 0u ? w.zw : w.xy;
}

#if HAS_SHADOWS
// The list a shadow ray towards light l reads in its light buffer (meta.z
// its first grid + 1), with the bound on the keys that ends its scan; the
// walk (count TABLE_WALK) where the light has none, its cell's list is too
// long or the ray starts beyond the buffer's reach.
uvec2 shadow_list(Ray r, real dist, Light l, out real bound) {
    uvec2 list = uvec2(0u, TABLE_WALK);
    bound = 0.0;
    if (l.meta.z == 0u) {
        return list;
    }
    COUNT_CELL();
    uint first = TABLE_GRID_WORDS * (l.meta.z - 1u);
    real reach = real(uintBitsToFloat(l.meta.w));
    // The light's first grid says the buffer's form; a variant compiles the
    // forms its lights' buffers take alone.
#if HAS_POSITIONED && HAS_UNPOSITIONED
    bool cube = TABLE_GRID_CELLS(first).w == TABLE_PERSPECTIVE;
#else
    bool cube = HAS_POSITIONED;
#endif
#if HAS_POSITIONED
    if (cube) {
        // A cube's face: its map takes a direction d to (+-d[axis],
        // d[axis + 1], d[axis + 2]), so its rows are not read.
        vec3r d = -r.dir;
        vec3r a = abs(d);
        uint axis = a.x >= a.y && a.x >= a.z ? 0u : (a.y >= a.z ? 1u : 2u);
        uint face = 2u * axis + (d[axis] < 0.0 ? 1u : 0u);
        real lam = abs(d[axis]);
        if (lam > 0.0) {
            uint at = first + TABLE_GRID_WORDS * face;
            list = table_cell(TABLE_GRID_RANGE(at), TABLE_GRID_CELLS(at),
                              d[(axis + 1u) % 3u] / lam, d[(axis + 2u) % 3u] / lam);
            bound = dist * KEY_SLACK;
        }
        // A ray from beyond the reach walks, though it has read a cell:
        // Mesa 22.3's llvmpipe (LLVM 15) crashes at run time (SIGSEGV in
        // the driver) where a branch on the reach skips the lookup in f64
        // (docs/guide.md, Shadow and eye rays from tables).
        if (!(dist <= reach)) {
            list = uvec2(0u, TABLE_WALK);
        }
    }
#endif
#if HAS_UNPOSITIONED
    if (!cube) {
        vec3r a = abs(r.origin);
        if (max(a.x, max(a.y, a.z)) <= reach) {
            TableGrid grid = TABLE_GRID_AT(first);
            list = table_cell(grid.range, grid.cells,
                              dot(vec3r(grid.row1.xyz), r.origin), dot(vec3r(grid.row2.xyz), r.origin));
            bound = -dot(vec3r(grid.row0.xyz), r.origin);
        }
    }
#endif
    return list;
}
#endif

// The list an eye ray of direction d reads: its tile's, where the scene has
// the eye's tiles (g.tables.z); else, or where the list is too long, the
// walk (count TABLE_WALK).
uvec2 eye_list(vec3r d) {
    if (g.tables.z == 0u) {
        return uvec2(0u, TABLE_WALK);
    }
    COUNT_CELL();
    real lam = dot(vec3r(g.eye_r0.xyz), d);
    if (!(lam > 0.0)) {
        return uvec2(0u, TABLE_WALK);
    }
    return table_cell(g.eye_range, g.eye_cells,
                      dot(vec3r(g.eye_r1.xyz), d) / lam, dot(vec3r(g.eye_r2.xyz), d) / lam);
}

// The next primitive of a list (entries at..end) whose key is at most
// bound, as a leaf word for the walk's loop (bvh.glsl); BVH_EMPTY, and the
// list ended, at the first over it: the keys rise.
uint list_next(inout uint at, uint end, real bound) {
    uint word = BVH_EMPTY;
    if (at < end) {
        uvec2 e = table_entry(at);
        at++;
        if (real(uintBitsToFloat(e.y)) <= bound) {
            word = e.x;
        } else {
            at = end;
        }
    }
    return word;
}
