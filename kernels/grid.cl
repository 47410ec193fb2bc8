/*
 * Neighbour grid: cell keys, a counting sort of (cell, index) keys on the
 * device, cell ranges, and the gather that reorders particle fields.
 *
 * Keys are (cell << 32) | original slot, so the sorted order is a total
 * order and the result is deterministic (the sort's atomic increments only
 * place keys within a bucket, which it then orders: grid_bucket_order).
 */

/* The cell of a position, clamped to the grid (the sort's keys and the
 * total Lagrangian contact search's). */
static inline uint cell_of_position(vec p, real4 origin, real inv_cell_size, int4 grid_dims)
{
    int cx = (int)floor((p.x - origin.x) * inv_cell_size);
    int cy = (int)floor((p.y - origin.y) * inv_cell_size);
#if SPH_DIM == 3
    int cz = (int)floor((p.z - origin.z) * inv_cell_size);
#else
    int cz = 0;
#endif
    /* the host sizes the grid to contain every particle; clamping only guards
     * against rounding at the upper faces (and, for the total Lagrangian
     * form's contact search on current positions, holds particles that have
     * left the reference box in its border cells: clamping never moves two
     * cells further apart, so no pair within the reach is lost) */
    cx = clamp(cx, 0, grid_dims.x - 1);
    cy = clamp(cy, 0, grid_dims.y - 1);
    cz = clamp(cz, 0, grid_dims.z - 1);
    return (uint)((cz * grid_dims.y + cy) * grid_dims.x + cx);
}

/* ... as the cell's coordinates */
static inline int4 cell_coords_of_position(vec p, real4 origin, real inv_cell_size, int4 grid_dims)
{
    return grid_cell_coords((int)cell_of_position(p, origin, inv_cell_size, grid_dims), grid_dims);
}

/* reads pos; writes sort_keys. */
__kernel void grid_cell_keys(__global const vec *restrict pos, __global ulong *restrict sort_keys,
                             const int n, const real4 grid_origin, const real grid_inv_cell_size,
                             const int4 grid_dims)
{
    const int i = get_global_id(0);
    if (i >= n)
        return;
    const uint cell = cell_of_position(pos[i], grid_origin, grid_inv_cell_size, grid_dims);
    sort_keys[i] = ((ulong)cell << 32) | (ulong)(uint)i;
}

/* Bounding box of the particles: each work-group writes (min x, min y,
 * min z, max x, max y, max z) for the host to combine. reads pos. */
__kernel __attribute__((reqd_work_group_size(REDUCE_WG, 1, 1))) void
grid_bounds(__global const vec *restrict pos, __global real *restrict partials, const int n)
{
    __local real acc[REDUCE_WG][6];
    real box[6] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
    const uchar op[6] = {REDUCE_MIN, REDUCE_MIN, REDUCE_MIN, REDUCE_MAX, REDUCE_MAX, REDUCE_MAX};
    FOR_GROUP_BLOCK (i, n)
        for (int a = 0; a < SPH_DIM; ++a) {
            const real x = vec_get(pos[i], a);
            box[a] = fmin(box[a], x);
            box[3 + a] = fmax(box[3 + a], x);
        }
    work_group_reduce(&acc[0][0], box, op, 6, partials);
}

/* A counting sort of 64-bit keys by their high half (a cell, or an id at
 * the ghosts' compaction), every high half below `buckets`; host/launch.c
 * solver_sort_keys runs the passes. The keys of one sort are nearly in
 * order already (particles keep their cell between sorts), but a counting
 * sort does not care: it takes O(n + buckets) work where a comparison
 * network took O(n log^2 n) (a bitonic sort of 1.18M keys: 231 stages,
 * 320-350 ms on two cores; docs/performance.md). The scatter takes its
 * slots with atomic increments, so within a bucket the keys land in an
 * order the device's scheduling picks; grid_bucket_order then sorts each
 * bucket by the whole key (the low half is the slot, unique), so the
 * result is the one total order of the keys: deterministic, as the
 * comparison sort was. */

/* counts the keys per bucket (bucket zeroed before). reads keys; updates
 * bucket. */
__kernel void grid_bucket_count(__global const ulong *restrict keys, __global int *restrict bucket,
                                const int n)
{
    const int i = get_global_id(0);
    if (i < n)
        atomic_inc(&bucket[(int)(keys[i] >> 32)]);
}

/* Counts to the first slot of each bucket (an exclusive prefix sum) in
 * three passes over blocks of SPH_SCAN_BLOCK buckets (include/sph_shared.h),
 * so that no work-item walks all of them (millions of cells): each block's
 * total, the blocks' offsets (one work-item, a few thousand blocks), each
 * block's prefix. */
/* reads bucket; writes block_total[block] */
__kernel void grid_bucket_block_total(__global const int *restrict bucket,
                                      __global int *restrict block_total, const int buckets)
{
    const int block = get_global_id(0), first = block * SPH_SCAN_BLOCK;
    if (first >= buckets)
        return;
    int sum = 0;
    for (int b = first; b < min(first + SPH_SCAN_BLOCK, buckets); ++b)
        sum += bucket[b];
    block_total[block] = sum;
}

/* updates block_total to each block's first slot */
__kernel void grid_bucket_block_offsets(__global int *restrict block_total, const int blocks)
{
    if (get_global_id(0) != 0)
        return;
    int sum = 0;
    for (int k = 0; k < blocks; ++k) {
        const int total = block_total[k];
        block_total[k] = sum;
        sum += total;
    }
}

/* reads block_total; updates bucket (count -> first slot) */
__kernel void grid_bucket_block_scan(__global int *restrict bucket,
                                     __global const int *restrict block_total, const int buckets)
{
    const int block = get_global_id(0), first = block * SPH_SCAN_BLOCK;
    if (first >= buckets)
        return;
    int sum = block_total[block];
    for (int b = first; b < min(first + SPH_SCAN_BLOCK, buckets); ++b) {
        const int count = bucket[b];
        bucket[b] = sum;
        sum += count;
    }
}

/* each key to a free slot of its bucket; after it bucket[b] is the end of
 * bucket b (the start of b + 1). reads keys; updates bucket; writes
 * scattered. */
__kernel void grid_bucket_scatter(__global const ulong *restrict keys,
                                  __global int *restrict bucket, __global ulong *restrict scattered,
                                  const int n)
{
    const int i = get_global_id(0);
    if (i < n) {
        const ulong key = keys[i];
        scattered[atomic_inc(&bucket[(int)(key >> 32)])] = key;
    }
}

/* each bucket's keys back into `keys`, in order (an insertion sort: a
 * bucket holds a cell's few tens of particles). reads scattered, bucket;
 * writes keys. */
__kernel void grid_bucket_order(__global const ulong *restrict scattered,
                                __global const int *restrict bucket, __global ulong *restrict keys,
                                const int buckets)
{
    const int b = get_global_id(0);
    if (b >= buckets)
        return;
    const int first = b > 0 ? bucket[b - 1] : 0, last = bucket[b];
    for (int i = first; i < last; ++i) {
        const ulong key = scattered[i];
        int k = i;
        for (; k > first && keys[k - 1] > key; --k)
            keys[k] = keys[k - 1];
        keys[k] = key;
    }
}

__kernel void grid_fill_int(__global int *restrict a, const int value, const int n)
{
    const int i = get_global_id(0);
    if (i < n)
        a[i] = value;
}

/* Marks where key i's cell starts and ends in the sorted keys. */
static inline void mark_cell_range(__global const ulong *restrict keys,
                                   __global int *restrict start, __global int *restrict end,
                                   const int i, const int n)
{
    const int cell = (int)(keys[i] >> 32);
    if (i == 0 || (int)(keys[i - 1] >> 32) != cell)
        start[cell] = i;
    if (i == n - 1 || (int)(keys[i + 1] >> 32) != cell)
        end[cell] = i + 1;
}

/* reads sort_keys (sorted); writes cell_start, cell_end (cleared to -1). */
__kernel void grid_cell_ranges(__global const ulong *restrict sort_keys,
                               __global int *restrict cell_start, __global int *restrict cell_end,
                               const int n)
{
    const int i = get_global_id(0);
    if (i < n)
        mark_cell_range(sort_keys, cell_start, cell_end, i, n);
}

/* Gathers one field into sorted order: out[i] = in[slot of sorted key i].
 * After the gather grid_copy puts `out` back into the field (one spare
 * serves every field: host/launch.c); from then on only the high
 * half of the keys (the cell) is read. */
#define GRID_GATHER(NAME, TYPE)                                                                    \
    __kernel void NAME(__global const ulong *restrict sort_keys, __global const TYPE *restrict in, \
                       __global TYPE *restrict out, const int n)                                   \
    {                                                                                              \
        const int i = get_global_id(0);                                                            \
        if (i < n)                                                                                 \
            out[i] = in[(int)(sort_keys[i] & 0xffffffffu)];                                        \
    }
GRID_GATHER(grid_gather_real, real)
GRID_GATHER(grid_gather_int, int)
GRID_GATHER(grid_gather_vec, vec)
GRID_GATHER(grid_gather_symt, symt)
GRID_GATHER(grid_gather_fullt, fullt)

/* Copies the gathered field back: out[i] = in[i]. A kernel, not
 * clEnqueueCopyBuffer, so that a checker's record of which elements were
 * written follows the copy element by element (oclgrind takes a buffer copy
 * for a host write of its extent and forgets the rest of the buffer). */
#define GRID_COPY(NAME, TYPE)                                                                      \
    __kernel void NAME(__global const TYPE *restrict in, __global TYPE *restrict out, const int n) \
    {                                                                                              \
        const int i = get_global_id(0);                                                            \
        if (i < n)                                                                                 \
            out[i] = in[i];                                                                        \
    }
GRID_COPY(grid_copy_real, real)
GRID_COPY(grid_copy_int, int)
GRID_COPY(grid_copy_vec, vec)
GRID_COPY(grid_copy_symt, symt)
GRID_COPY(grid_copy_fullt, fullt)

/* Test hook: for each particle, the original ids of its neighbours within
 * `radius` (excluding itself), through FOR_EACH_NEIGHBOUR (the cells the
 * one-lane pass loop visits; tests/test_neighbours.c against brute force).
 * reads pos, id; writes count, list (max_list per particle). */
__kernel void grid_neighbour_list(__global const vec *restrict pos, __global const int *restrict id,
                                  GRID_ARGS, const real radius, __global int *restrict count,
                                  __global int *restrict list, const int max_list, const int n)
{
    const int i = get_global_id(0);
    if (i >= n)
        return;
    const vec pi = pos[i];
    int c = 0;
    FOR_EACH_NEIGHBOUR_WITHIN(i, j, SPH_GRID_SPLIT)
    {
        const vec d = pi - pos[j];
        if (j != i && dot(d, d) < radius * radius) {
            if (c < max_list)
                list[i * max_list + c] = id[j];
            ++c;
        }
    }
    END_FOR_EACH_NEIGHBOUR
    count[i] = c;
}

#ifdef SPH_GRADED
/* Graded lattices: how many cells each particle's neighbour search must
 * reach (flags bits, kernels/common.cl). A particle of level k pairs with
 * coarser ones (level k + 1) at the mean smoothing length 1.5 h_k, so it
 * searches 1.5 supports when one lies within that reach, else one
 * support; plus the skin for motion until the next sort. Recomputed at
 * every sort, since material moves across the levels (a cavity pushes
 * fine particles outwards).
 *
 * In passes, so that no work-item reads a flag another one writes:
 * grid_cell_max_level gives each cell the coarsest level it holds,
 * grid_coarser_seed and grid_coarser_spread (once per axis) mark the cells
 * whose window holds a coarser cell, grid_neighbour_reach writes each
 * particle's reach to `reach` (looking at particles only in the cells of
 * its window that hold a coarser level, and only where the marks say there
 * is one; most particles, deep inside one level, look at nothing), and
 * grid_apply_reach puts it into the flags. */
static inline int reach_cells(real h_over_h0, real skin)
{
    return (int)ceil(SPH_GRID_SPLIT * (h_over_h0 + skin) / ((real)1 + skin) - (real)1e-6);
}

/* reads flags, cell ranges; writes cell_level (-1 for an empty cell) */
__kernel void grid_cell_max_level(__global const int *restrict flags,
                                  __global const int *restrict cell_start,
                                  __global const int *restrict cell_end,
                                  __global int *restrict cell_level, const int cells)
{
    const int c = get_global_id(0);
    if (c >= cells)
        return;
    int level = -1;
    const int first = cell_start[c], last = cell_end[c];
    for (int j = first < 0 ? 0 : first; j < last; ++j)
        level = max(level, SPH_LEVEL_OF(flags[j]));
    cell_level[c] = level;
}

/* The cells a particle of `level` searches for a coarser one, each way
 * along `axis` (0, 1, 2): grid_neighbour_reach's window. */
static inline int coarser_window(int level, real skin, int axis)
{
    return (axis == 2 ? GRID_DZ : 1) * reach_cells((real)1.5 * (real)(1 << level), skin);
}

/* Which levels each cell holds something coarser than: bit L set where
 * the cell's coarsest level is above L. reads cell_level; writes
 * coarser_out. */
__kernel void grid_coarser_seed(__global const int *restrict cell_level,
                                __global int *restrict coarser_out, const int cells)
{
    const int c = get_global_id(0);
    if (c < cells)
        coarser_out[c] = cell_level[c] > 0 ? (1 << cell_level[c]) - 1 : 0;
}

/* ... spread along one axis: bit L of a cell is set where one within
 * coarser_window(L) cells along `axis` had it. Run along each axis in turn
 * it gives, per cell, the levels L for which grid_neighbour_reach's window
 * about the cell holds a coarser cell (the window is a box, so the test
 * separates); a particle whose level's bit is clear has nothing coarser to
 * look for, which is most of them (every particle of the coarsest level,
 * whose window is the widest). One work-item per row of cells along the
 * axis, a sliding count of the marked cells in each level's window (two
 * loads per level and cell). reads coarser_in; writes coarser_out. */
__kernel void grid_coarser_spread(__global const int *restrict coarser_in,
                                  __global int *restrict coarser_out, const int4 grid_dims,
                                  const int axis, const real skin, const int coarsest,
                                  const int rows)
{
    const int row = get_global_id(0);
    if (row >= rows)
        return;
    /* the row's first cell and the step along it */
    int base, stride, extent;
    if (axis == 0) {
        base = row * grid_dims.x, stride = 1, extent = grid_dims.x;
    } else if (axis == 1) {
        base = (row / grid_dims.x) * grid_dims.x * grid_dims.y + row % grid_dims.x;
        stride = grid_dims.x, extent = grid_dims.y;
    } else {
        base = row, stride = grid_dims.x * grid_dims.y, extent = grid_dims.z;
    }
    /* a row with no mark (empty space, or deep inside the finest level)
     * spreads nothing: one load per cell */
    int any = 0;
    for (int k = 0; k < extent; ++k)
        any |= coarser_in[base + k * stride];
    if (!any) {
        for (int k = 0; k < extent; ++k)
            coarser_out[base + k * stride] = 0;
        return;
    }
    int window[SPH_LEVEL_MASK + 1], count[SPH_LEVEL_MASK + 1], widest = 0;
    for (int level = 0; level < coarsest; ++level) {
        window[level] = coarser_window(level, skin, axis);
        count[level] = 0;
        widest = max(widest, window[level]);
    }
    /* count[L]: marked cells in [k - window[L], k + window[L]] */
    for (int k = -widest; k < extent; ++k) {
        int bits = 0;
        for (int level = 0; level < coarsest; ++level) {
            const int enter = k + window[level], leave = k - window[level] - 1;
            if (enter >= 0 && enter < extent)
                count[level] += (coarser_in[base + enter * stride] >> level) & 1;
            if (leave >= 0)
                count[level] -= (coarser_in[base + leave * stride] >> level) & 1;
            bits |= count[level] > 0 ? 1 << level : 0;
        }
        if (k >= 0)
            coarser_out[base + k * stride] = bits;
    }
}

/* SPH_REACH_FULL_SCAN (tests/check_reach.py's reference): every particle
 * scans its whole window, every cell of it */
#ifdef SPH_REACH_FULL_SCAN
#define REACH_PRUNED 0
#else
#define REACH_PRUNED 1
#endif

/* How far x lies outside cell c's extent along one axis (0 inside), less a
 * thousandth of a cell for the rounding of the cell bounds: a lower bound
 * of the distance to any particle the cell holds. */
static inline real gap_to_cell(real x, real origin, real cell_size, int c)
{
    const real lo = origin + (real)c * cell_size;
    return fmax(fmax(lo - x, x - (lo + cell_size)) - (real)1e-3 * cell_size, (real)0);
}

/* reads pos, flags, cell_level, cell_coarser; writes reach */
__kernel void grid_neighbour_reach(__global const vec *restrict pos,
                                   __global const int *restrict flags, GRID_ARGS,
                                   __global const int *restrict cell_level,
                                   __global const int *restrict cell_coarser,
                                   __constant const struct sph_run_params *run, const real skin,
                                   const real4 grid_origin, const real cell_size,
                                   __global int *restrict reach, const int n)
{
    const int i = get_global_id(0);
    if (i >= n)
        return;
    const int flag = flags[i];
    const int level = SPH_LEVEL_OF(flag);
    const real scale = spacing_scale(flag);
    if (REACH_PRUNED && !((cell_coarser[(int)(sort_keys[i] >> 32)] >> level) & 1)) {
        reach[i] = reach_cells(scale, skin); /* no coarser cell in the window */
        return;
    }
    const int wide = reach_cells((real)1.5 * scale, skin);
    const real limit = (real)1.5 * run->support * scale + skin * run->support;
    const vec xi = pos[i];
    const int4 home = grid_cell_coords((int)(sort_keys[i] >> 32), grid_dims);
    const real limit2 = limit * limit;
    bool coarser_near = false;
    /* the window's cells, less those wholly farther than the limit (the
     * window is a cube about a sphere of that radius) */
    for (int dz = -GRID_DZ * wide; dz <= GRID_DZ * wide && !coarser_near; ++dz) {
        const int cz = home.z + dz;
        if (cz < 0 || cz >= grid_dims.z)
            continue;
        const real gz =
            SPH_DIM == 3 ? gap_to_cell(vec_get(xi, 2), grid_origin.z, cell_size, cz) : 0;
        for (int dy = -wide; dy <= wide && !coarser_near; ++dy) {
            const int cy = home.y + dy;
            if (cy < 0 || cy >= grid_dims.y)
                continue;
            const real gy = gap_to_cell(xi.y, grid_origin.y, cell_size, cy);
            if (REACH_PRUNED && gy * gy + gz * gz >= limit2)
                continue;
            const int row = (cz * grid_dims.y + cy) * grid_dims.x;
            for (int cx = max(home.x - wide, 0); cx <= min(home.x + wide, grid_dims.x - 1); ++cx) {
                const int cell = row + cx;
                const real gx = gap_to_cell(xi.x, grid_origin.x, cell_size, cx);
                if (cell_level[cell] <= level ||
                    (REACH_PRUNED && gx * gx + gy * gy + gz * gz >= limit2))
                    continue;
                for (int j = cell_start[cell]; j < cell_end[cell] && !coarser_near; ++j) {
                    const vec d = xi - pos[j];
                    coarser_near = SPH_LEVEL_OF(flags[j]) > level && dot(d, d) < limit2;
                }
            }
        }
    }
    reach[i] = coarser_near ? wide : reach_cells(scale, skin);
}

/* reads reach; updates flags */
__kernel void grid_apply_reach(__global int *restrict flags, __global const int *restrict reach,
                               const int n)
{
    const int i = get_global_id(0);
    if (i >= n)
        return;
    flags[i] = (flags[i] & ~(SPH_REACH_MASK << SPH_REACH_SHIFT)) | (reach[i] << SPH_REACH_SHIFT);
}
#endif
