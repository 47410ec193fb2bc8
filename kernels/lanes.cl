/*
 * The neighbour loop of passes 1 and 2 (kernels/pass1.cl, pass2.cl, and
 * the total Lagrangian form's tl_deformation and tl_momentum), over
 * lanes of particles: SPH_LANES consecutive particles of the cell-sorted
 * order per work-item. It holds no physics: the passes write their pair
 * terms once, in `realv` arithmetic, and this file makes that arithmetic
 * one particle wide or several.
 *
 * SPH_LANES 1 (numerics.neighbour_loop: plain, the shape a GPU's compiler
 * expects): realv is real, a work-item is one particle, the loop visits
 * FOR_EACH_NEIGHBOUR's cells.
 * SPH_LANES 8 (lanes, the default on a CPU):
 * PoCL vectorises a kernel across work-items only when its body has no
 * inner loop of varying trip count, so a one-particle neighbour loop runs
 * one particle per instruction on a CPU (docs/performance.md). Here a
 * work-item takes SPH_LANES particles (mostly in the same or adjacent
 * cells), walks the union of their search boxes once, and evaluates each
 * candidate j for all lanes at once: j's data are loaded once and
 * broadcast, i's live in vector registers, a candidate no lane reaches
 * costs one vector distance test. A lane whose particle is not within the
 * support contributes exactly zero (select, not a multiply, so the r = 0
 * of i itself cannot leak a NaN). The sums over the neighbours run in the
 * same cell order for every width, so on PoCL the widths agree to the bit
 * with the polynomial smoothing kernels (vector cos and exp round
 * differently; tests: lanes_match_plain_*, every smoothing kernel).
 */

/* Whether any lane of a mask is set. OpenCL's any() on a vector mask runs
 * lane by lane in PoCL 3.1 and took a third of pass 1's time at 50k; an
 * OR of the mask's 64-bit words in halves is a few vector instructions
 * (pass 1 17.9 against 22.5 ms, docs/performance.md). */
#if SPH_LANES == 1
static inline int lanes_any(maskv m)
{
    return m != 0;
}
#else
static inline int lanes_any(maskv m)
{
#ifdef SPH_DOUBLE /* 8 64-bit words */
    const ulong8 w8 = as_ulong8(m);
    const ulong4 w4 = w8.lo | w8.hi;
#else             /* 8 32-bit lanes in 4 64-bit words */
    const ulong4 w4 = as_ulong4(m);
#endif
    const ulong2 w2 = w4.lo | w4.hi;
    return (w2.x | w2.y) != 0;
}
#endif

/* This work-item's lanes: the first particle, which lanes hold a real
 * particle (not past n, not a ghost), and the box of their cells. */
struct lane_block {
    int first;
    maskv live;
    int4 lo, hi;
#ifdef SPH_GRADED
    int reach;   /* cells the widest lane's search reaches (its flags) */
    realv scale; /* each lane's spacing over the finest, 2^level */
#endif
};

#ifdef SPH_GRADED
#define LANE_REACH(b) ((b).reach)
#else
#define LANE_REACH(b) SPH_GRID_SPLIT
#endif

static inline int lane_block_setup(struct lane_block *b, __global const int *restrict flags,
                                   __global const ulong *restrict sort_keys, int4 grid_dims,
                                   const int n)
{
    b->first = (int)get_global_id(0) * SPH_LANES;
    if (b->first >= n)
        return 0;
    b->lo = (int4)(INT_MAX);
    b->hi = (int4)(INT_MIN);
    mask_union live;
    int any_live = 0;
#ifdef SPH_GRADED
    lanes_union scale;
    b->reach = 0;
#endif
    for (int l = 0; l < SPH_LANES; ++l) {
        const int i = b->first + l;
        const int ok = i < n && !(flags[i] & SPH_FLAG_GHOST);
        live.s[l] = ok ? -1 : 0;
#ifdef SPH_GRADED
        scale.s[l] = ok ? spacing_scale(flags[i]) : (real)1;
        if (ok)
            b->reach = max(b->reach, NEIGHBOUR_REACH(i));
#endif
        if (ok) {
            const int4 c = grid_cell_coords((int)(sort_keys[i] >> 32), grid_dims);
            b->lo = min(b->lo, c);
            b->hi = max(b->hi, c);
            any_live = 1;
        }
    }
    b->live = live.v;
#ifdef SPH_GRADED
    b->scale = scale.v;
#endif
    return any_live;
}

/* The pair's smoothing length h, its support squared and 1 / h for the
 * lanes with candidate j. LANE_PASS_CONSTANTS goes before the loop,
 * LANE_PAIR_SUPPORT(b, j) before the distance test and LANE_PAIR_INV_H after
 * it (so a candidate no lane reaches pays no division). On a uniform
 * lattice all three are run constants, set once; on a graded one h is each
 * lane's pair mean (common.cl PAIR_H_OF) and the support scales with it. */
#ifdef SPH_GRADED
#define LANE_PASS_CONSTANTS const real q2 = (run->support / run->h) * (run->support / run->h)
#define LANE_PAIR_SUPPORT(b, j)                                                                    \
    const hreal h = PAIR_H_OF((b).scale, spacing_scale(flags[j])), support2 = q2 * h * h
#define LANE_PAIR_INV_H const hreal inv_h = (real)1 / h
#else
#define LANE_PASS_CONSTANTS                                                                        \
    const real h = run->h, inv_h = (real)1 / h, support2 = run->support * run->support
#define LANE_PAIR_SUPPORT(b, j)
#define LANE_PAIR_INV_H
#endif

/* Whether lane l of a block holds a particle its pass updates (set up by
 * lane_block_setup: not past n, not a ghost). */
static inline bool lane_live(const struct lane_block *b, int l)
{
    mask_union u;
    u.v = b->live;
    return u.s[l] != 0;
}

/* The lane passes' grid: the cell grid (GRID_ARGS) and each block's list
 * of candidates, lane_list[lane_list_range[b].x .. lane_list_range[b].y),
 * built at each sort by lane_list_build (host/step.c,
 * solver_lane_lists_build). */
#define LANE_GRID_ARGS                                                                             \
    GRID_ARGS, __global const int2 *restrict lane_list_range, __global const int *restrict lane_list

/* LANE_CELL_ROWS(block, reach, row, x0, x1) { ... } END_LANE_CELL_ROWS:
 * the rows of grid cells within `reach` cells of the block's box, each as
 * the index of its first cell, `row`, and the box's cells x0..x1 in it. */
#define LANE_CELL_ROWS(b, reach, row, x0, x1)                                                      \
    for (int cz_ = max((b).lo.z - GRID_DZ * (reach), 0);                                           \
         cz_ <= min((b).hi.z + GRID_DZ * (reach), grid_dims.z - 1); ++cz_)                         \
        for (int cy_ = max((b).lo.y - (reach), 0);                                                 \
             cy_ <= min((b).hi.y + (reach), grid_dims.y - 1); ++cy_) {                             \
            const int row = (cz_ * grid_dims.y + cy_) * grid_dims.x;                               \
            const int x0 = max((b).lo.x - (reach), 0),                                             \
                      x1 = min((b).hi.x + (reach), grid_dims.x - 1);

#define END_LANE_CELL_ROWS }

/* LANE_CELL_WALK_IN(block, k, start, end, reach) { ... } END_LANE_CELL_WALK:
 * every slot k of the sorted order in the cells within `reach` of the
 * block's box, in the cells' order, with the cell ranges start / end (the
 * grid's, or the total Lagrangian contact search's); rows of cells are
 * contiguous in the sorted order, as in FOR_EACH_NEIGHBOUR.
 * LANE_CELL_WALK(block, j): the grid's, whose slots are the particles. */
#define LANE_CELL_WALK_IN(b, k, start, end, reach)                                                 \
    LANE_CELL_ROWS(b, reach, row_, x0_, x1_)                                                       \
    const int2 span_ = cell_row_span(start, end, row_, x0_, x1_);                                  \
    for (int k = span_.x; k < span_.y; ++k) {

#define END_LANE_CELL_WALK                                                                         \
    }                                                                                              \
    END_LANE_CELL_ROWS

#define LANE_CELL_WALK(b, j) LANE_CELL_WALK_IN(b, j, cell_start, cell_end, LANE_REACH(b))

/* FOR_EACH_LANE_NEIGHBOUR(block, j) { ... } END_FOR_EACH_LANE_NEIGHBOUR:
 * the candidates of the block's list, which are the cell walk's less those
 * no lane could reach before the next sort, in the walk's order: the sums
 * are the walk's to the bit (a candidate no lane reaches adds nothing).
 * The walk tests about three times as many candidates (docs/performance.md,
 * "The lane lists"). One particle per work-item (SPH_LANES 1, a GPU's loop)
 * and SPH_LANE_CELL_WALK (numerics.lane_lists false, host/state.c; the
 * reference of tests/check_lane_lists.py) walk the cells. */
#if SPH_LANES == 1 || defined(SPH_LANE_CELL_WALK)
#define FOR_EACH_LANE_NEIGHBOUR(b, j) LANE_CELL_WALK(b, j)
#define END_FOR_EACH_LANE_NEIGHBOUR END_LANE_CELL_WALK
#else
#define FOR_EACH_LANE_NEIGHBOUR(b, j)                                                              \
    const int2 range_ = lane_list_range[(b).first / SPH_LANES];                                    \
    for (int k_ = range_.x; k_ < range_.y; ++k_) {                                                 \
        const int j = lane_list[k_];

#define END_FOR_EACH_LANE_NEIGHBOUR }
#endif

/* x_i - x_j and its square for every lane against candidate j, and the
 * lanes for which j is a neighbour: within the support and not j itself
 * (r > 0; a lane that is not live sits at LANE_FAR, lane_positions). One
 * vector test per candidate, so it holds no more than it must. */
static inline maskv lane_pair(realv xi[3], vec xj, hreal support2, realv xij[3], realv *r2)
{
#pragma unroll
    for (int a = 0; a < 3; ++a)
        xij[a] = a < SPH_DIM ? xi[a] - vec_get(xj, a) : (realv)0;
    *r2 = xij[0] * xij[0] + xij[1] * xij[1] + xij[2] * xij[2];
    return (*r2 < support2) & (*r2 > (real)0);
}

/* One lane's particle data gathered into vectors: a real field. */
static inline realv gather_real(__global const real *restrict f, const struct lane_block *b, int n)
{
    lanes_union u;
    for (int l = 0; l < SPH_LANES; ++l)
        u.s[l] = b->first + l < n ? f[b->first + l] : (real)0;
    return u.v;
}

/* ... and a vector field, by component (z = 0 in 2-D). */
static inline void gather_vec(__global const vec *restrict f, const struct lane_block *b, int n,
                              realv out[3])
{
    lanes_union u[3];
    for (int l = 0; l < SPH_LANES; ++l) {
        const vec v = b->first + l < n ? f[b->first + l] : VEC_ZERO;
#pragma unroll
        for (int a = 0; a < 3; ++a)
            u[a].s[l] = a < SPH_DIM ? vec_get(v, a) : (real)0;
    }
#pragma unroll
    for (int a = 0; a < 3; ++a)
        out[a] = u[a].v;
}

#ifdef SPH_PART_CONTACT
/* The lanes' parts (bodies[].part), as reals so that a neighbour's compares
 * in one vector test: SAME_PART(parts, j) is the mask of the lanes of j's
 * part. The passes keep a pair of different parts out of every continuum
 * sum; pass 2 gives it the contact force instead. */
static inline realv lane_parts(__global const int *restrict flags, const struct lane_block *b,
                               int n)
{
    lanes_union u;
    for (int l = 0; l < SPH_LANES; ++l)
        u.s[l] = b->first + l < n ? (real)SPH_PART_OF(flags[b->first + l]) : (real)-1;
    return u.v;
}
#define SAME_PART(parts, j) ((parts) == (real)SPH_PART_OF(flags[j]))
#define OWN_PART(parts, j) SAME_PART(parts, j)
#else
#define OWN_PART(parts, j) ((maskv)(-1)) /* every lane: one continuum */
#endif

/* The lanes' positions; a lane that is not live is put LANE_FAR away, out
 * of every candidate's reach, so lane_pair needs no live mask. */
#define LANE_FAR ((real)1e18)
static inline void lane_positions(__global const vec *restrict pos, const struct lane_block *b,
                                  int n, realv xi[3])
{
    gather_vec(pos, b, n, xi);
#pragma unroll
    for (int a = 0; a < 3; ++a)
        xi[a] = SPH_SELECT((realv)LANE_FAR, xi[a], b->live);
}

/* |x_i - x_j|^2 for every lane against candidate j. Unrolled: the same
 * loop written inside a macro, where it cannot be marked so, took the
 * lists' build twice as long on gelatin3d-120k (docs/performance.md). */
static inline realv lane_distance2(const realv xi[3], vec xj)
{
    realv r2 = (realv)0;
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a) {
        const realv d = xi[a] - vec_get(xj, a);
        r2 += d * d;
    }
    return r2;
}

/* LANE_LIST_CANDIDATES(b, xi, reach2, j, keep) { ... } END_LANE_LIST_CANDIDATES:
 * every candidate j of the block's cell walk, in the walk's order, with
 * keep = 1 when some lane is within sqrt(reach2) times the pair's support
 * of it, else 0. */
#define LANE_LIST_CANDIDATES(b, xi, reach2, j, keep)                                               \
    LANE_CELL_WALK(b, j)                                                                           \
    {                                                                                              \
        LANE_PAIR_SUPPORT(b, j);                                                                   \
        (void)h;                                                                                   \
        const int keep = lanes_any(lane_distance2(xi, at[j]) < (reach2)*support2);

#define END_LANE_LIST_CANDIDATES                                                                   \
    }                                                                                              \
    END_LANE_CELL_WALK

/* Entries a block keeps in private memory before the one write of its
 * list; a block with more is walked again by a second launch (host/step.c). */
#ifndef SPH_LANE_LIST_ROOM
#define SPH_LANE_LIST_ROOM 1024
#endif

#ifdef SPH_TENSOR_SMOOTHING
/* With numerics.smoothing tensor (tensor_smoothing.cl), the lists' reach,
 * squared, in units of the search's support (run->support: the longest
 * axis SPH_TENSOR_AXIS_MAX allows), for lanes whose longest semi-axes over
 * h0 are axis_i against a neighbour's axis_j: the longer of the two
 * ellipsoids plus the grid's whole skin of the search's support (margin:
 * the sort waits for a move of half of it, whatever the particles' own
 * axes; host/step.c) */
static inline realv tensor_list_reach2(realv axis_i, real axis_j, real margin)
{
    const realv reach = fmax(axis_i, (realv)axis_j) * (real)(1.0 / SPH_TENSOR_AXIS_MAX) + margin;
    return reach * reach;
}
#endif

/* Each lane block's candidate list (FOR_EACH_LANE_NEIGHBOUR), one
 * work-item per block, one walk per sort (host/step.c,
 * solver_lane_lists_build). A candidate of the cell walk is kept when some
 * lane is within reach_scale times the pair's support of it: 1 + skin in
 * the updated form, where the list serves until the next sort (the grid's
 * own margin: each particle moves less than skin support / 2 before it, so
 * a pair within the support then is within (1 + skin) support now); 1 in
 * the total Lagrangian form, whose passes test the reference positions,
 * which never move. r = 0 is kept (the lane's own particle, or one that
 * coincides with it now and may not later).
 * The first launch (rewalk 0) keeps a block's candidates in private memory,
 * claims their place in lane_list with an atomic add on list_claim[0] (the
 * blocks' lists lie in any order, each in its walk's order, so the passes'
 * sums do not depend on where) and writes them there when they fit both the
 * private room and `capacity`; a block that does not counts itself in
 * list_claim[1]. If the list was short (list_claim[0] > capacity) the host
 * grows it and launches the first again; then, only if list_claim[1] > 0,
 * it launches again with rewalk 1: the blocks with more candidates than
 * the room walk again and write into their claimed place directly.
 * reads: at (the positions the passes test: pos, or pos0 in the total
 * Lagrangian form), flags, the grid; writes: lane_list_range, lane_list,
 * list_claim (zeroed by the host before the first launch). */
__kernel void lane_list_build(__global const vec *restrict at, __global const int *restrict flags,
                              __global const real *restrict smoothing_reach, GRID_ARGS,
                              __constant const struct sph_run_params *run, const real reach_scale,
                              __global int2 *restrict lane_list_range,
                              __global int *restrict lane_list,
                              volatile __global int *restrict list_claim, const int capacity,
                              const int rewalk, const int n)
{
    const int block = (int)get_global_id(0);
    if (block * SPH_LANES >= n) /* the launch rounds up: no entry of this block */
        return;
    int2 range = rewalk ? lane_list_range[block] : (int2)(0, 0);
    if (rewalk && range.y - range.x <= SPH_LANE_LIST_ROOM)
        return; /* written by the first launch (the list was long enough) */
    struct lane_block b;
    if (!lane_block_setup(&b, flags, sort_keys, grid_dims, n)) {
        lane_list_range[block] = range;
        return;
    }
    LANE_PASS_CONSTANTS;
#ifndef SPH_GRADED
    (void)inv_h; /* the walk tests distances only */
#endif
    realv xi[3];
    lane_positions(at, &b, n, xi);
#ifdef SPH_TENSOR_SMOOTHING
    /* a pair is kept within the longer of its two particles' ellipsoids
     * (tensor_list_reach2 above) */
    const realv axis_i = gather_real(smoothing_reach, &b, n);
    const real margin = reach_scale - (real)1;
#define LIST_REACH2(j) tensor_list_reach2(axis_i, smoothing_reach[j], margin)
#else
    (void)smoothing_reach;
    const real reach2 = reach_scale * reach_scale;
#define LIST_REACH2(j) reach2
#endif
    int count = 0;
    if (rewalk) { /* the place is claimed: no store past it */
        LANE_LIST_CANDIDATES(b, xi, LIST_REACH2(j), j, keep)
        if (keep)
            lane_list[range.x + count++] = j;
        END_LANE_LIST_CANDIDATES
        return;
    }
    /* every candidate is stored, then counted if kept (+ 1: the last store
     * of a full room): with the store under a branch a launch took 79-84
     * against 66-69 ms on gelatin3d-120k */
    int room[SPH_LANE_LIST_ROOM + 1];
    LANE_LIST_CANDIDATES(b, xi, LIST_REACH2(j), j, keep)
    room[min(count, SPH_LANE_LIST_ROOM)] = j;
    count += keep;
    END_LANE_LIST_CANDIDATES
    range.x = count > 0 ? atomic_add(&list_claim[0], count) : 0;
    range.y = range.x + count;
    lane_list_range[block] = range;
    if (count <= SPH_LANE_LIST_ROOM && range.y <= capacity)
        for (int k = 0; k < count; ++k)
            lane_list[range.x + k] = room[k];
    else
        atomic_inc(&list_claim[1]);
}
#undef LIST_REACH2

/* Lane l of a tensor per lane, and the tensor of lanes. */
static inline void lanes_tensor_put(lanes_union u[3][3], int l, real t[3][3])
{
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int c = 0; c < 3; ++c)
            u[a][c].s[l] = t[a][c];
}

static inline void lanes_tensor_get(lanes_union u[3][3], realv out[3][3])
{
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int c = 0; c < 3; ++c)
            out[a][c] = u[a][c].v;
}

/* A symmetric 3 x 3 tensor per lane (stress, artificial stress, CSPH). */
static inline void gather_symt(__global const symt *restrict f, const struct lane_block *b, int n,
                               realv out[3][3])
{
    lanes_union u[3][3];
    for (int l = 0; l < SPH_LANES; ++l) {
        real t[3][3];
        symt_load(b->first + l < n ? f[b->first + l] : symt_zero(), t);
        lanes_tensor_put(u, l, t);
    }
    lanes_tensor_get(u, out);
}

/* Zero, one lane's and a sum of outer products: t += s a (x) b over the
 * first SPH_DIM indices (velocity gradients, moment matrices and
 * deformation gradients: pass1.cl, total_lagrangian.cl). */
static inline void tensor_zero_v(realv t[3][3])
{
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int c = 0; c < 3; ++c)
            t[a][c] = (realv)0;
}

static inline void tensor_lane(realv t[3][3], int l, real out[3][3])
{
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int c = 0; c < 3; ++c)
            out[a][c] = lane_of(t[a][c], l);
}

static inline void outer_add(realv t[3][3], realv s, const realv a[3], const realv b[3])
{
#pragma unroll
    for (int p = 0; p < SPH_DIM; ++p)
#pragma unroll
        for (int q = 0; q < SPH_DIM; ++q)
            t[p][q] += s * a[p] * b[q];
}

/* A symmetric sum of outer products, t += s a (x) a, over its upper
 * triangle only (the CSPH moment matrix: grad W_ij lies along x_ij, so
 * B_i is symmetric, pass1.cl); moment_mirror fills the lower triangle once
 * the sum is complete. Six products per pair instead of nine. */
static inline void moment_add(realv t[3][3], realv s, const realv a[3])
{
#pragma unroll
    for (int p = 0; p < SPH_DIM; ++p) {
        const realv sa = s * a[p];
#pragma unroll
        for (int q = p; q < SPH_DIM; ++q)
            t[p][q] += sa * a[q];
    }
}

static inline void moment_mirror(realv t[3][3])
{
#pragma unroll
    for (int p = 1; p < SPH_DIM; ++p)
#pragma unroll
        for (int q = 0; q < p; ++q)
            t[p][q] = t[q][p];
}

/* A full 3 x 3 tensor per lane (the velocity gradient). */
static inline void gather_fullt(__global const fullt *restrict f, const struct lane_block *b, int n,
                                realv out[3][3])
{
    lanes_union u[3][3];
    for (int l = 0; l < SPH_LANES; ++l) {
        real t[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
        if (b->first + l < n)
            fullt_load(f[b->first + l], t);
        lanes_tensor_put(u, l, t);
    }
    lanes_tensor_get(u, out);
}
