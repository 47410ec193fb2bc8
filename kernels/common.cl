/*
 * Types, tensor storage, the cell grid and its per-particle neighbour loop
 * (FOR_EACH_NEIGHBOUR: the total Lagrangian form, health, the grid's test
 * hook; passes 1 and 2 walk lane blocks, kernels/lanes.cl), the shared
 * stress, kernel-function and reduction helpers.
 *
 * Build options (set by host/device.c from the case):
 *   SPH_DIM 2|3, SPH_KERNEL 0..5 (enum sph_kernel_type), SPH_PLANE_STRESS,
 *   SPH_CSPH, SPH_ARTIFICIAL_STRESS, SPH_XSPH, SPH_PLASTICITY, SPH_DOUBLE.
 *
 * Storage: positions and velocities are real2 (2-D) or real4 with w = 0
 * (3-D). Symmetric tensors (deviatoric stress, artificial stress) are real4
 * (xx, yy, zz, xy) in 2-D, real8 (xx, yy, zz, xy, xz, yz, 0, 0) in 3-D; zz is
 * kept in 2-D for plane stress / plane strain. Full tensors (velocity
 * gradient L[a][b] = dv_a/dx_b, CSPH correction) are real4 (xx, xy, yx, yy)
 * in 2-D and real16 (row-major, 9 used) in 3-D. Inside kernels every tensor
 * is a real[3][3] so the physics is written once.
 */
#ifndef SPH_DIM
#error "SPH_DIM must be defined (2 or 3)"
#endif
#ifndef SPH_KERNEL
#error "SPH_KERNEL must be defined (enum sph_kernel_type)"
#endif

#ifdef SPH_DOUBLE
typedef double2 real2;
typedef double4 real4;
typedef double8 real8;
typedef double16 real16;
#else
typedef float2 real2;
typedef float4 real4;
typedef float8 real8;
typedef float16 real16;
#endif

#if SPH_DIM == 2
typedef real2 vec;
typedef real4 symt;
typedef real4 fullt;
#define VEC_ZERO ((vec)(0, 0))
#elif SPH_DIM == 3
typedef real4 vec;
/* a symmetric tensor stored as its six components xx, yy, zz, xy, xz, yz:
 * 24 B in float, where a real8 would take 32 (docs/performance.md) */
typedef struct {
    real c[6];
} symt;
typedef real16 fullt;
#define VEC_ZERO ((vec)(0, 0, 0, 0))
#else
#error "SPH_DIM must be 2 or 3"
#endif

static inline real vec_get(vec v, int a)
{
#if SPH_DIM == 2
    return a == 0 ? v.x : a == 1 ? v.y : (real)0;
#else
    return a == 0 ? v.x : a == 1 ? v.y : v.z;
#endif
}

static inline vec vec_make(real x, real y, real z)
{
#if SPH_DIM == 2
    (void)z;
    return (vec)(x, y);
#else
    return (vec)(x, y, z, 0);
#endif
}

static inline void symt_load(symt s, real t[3][3])
{
#if SPH_DIM == 2
    t[0][0] = s.s0;
    t[1][1] = s.s1;
    t[2][2] = s.s2;
    t[0][1] = t[1][0] = s.s3;
    t[0][2] = t[2][0] = t[1][2] = t[2][1] = 0;
#else
    t[0][0] = s.c[0];
    t[1][1] = s.c[1];
    t[2][2] = s.c[2];
    t[0][1] = t[1][0] = s.c[3];
    t[0][2] = t[2][0] = s.c[4];
    t[1][2] = t[2][1] = s.c[5];
#endif
}

static inline symt symt_store(real t[3][3])
{
#if SPH_DIM == 2
    return (symt)(t[0][0], t[1][1], t[2][2], t[0][1]);
#else
    const symt s = {{t[0][0], t[1][1], t[2][2], t[0][1], t[0][2], t[1][2]}};
    return s;
#endif
}

static inline symt symt_zero(void)
{
    real t[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    return symt_store(t);
}

static inline void fullt_load(fullt f, real t[3][3])
{
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b)
            t[a][b] = 0;
#if SPH_DIM == 2
    t[0][0] = f.s0;
    t[0][1] = f.s1;
    t[1][0] = f.s2;
    t[1][1] = f.s3;
#else
    t[0][0] = f.s0;
    t[0][1] = f.s1;
    t[0][2] = f.s2;
    t[1][0] = f.s3;
    t[1][1] = f.s4;
    t[1][2] = f.s5;
    t[2][0] = f.s6;
    t[2][1] = f.s7;
    t[2][2] = f.s8;
#endif
}

static inline fullt fullt_store(real t[3][3])
{
#if SPH_DIM == 2
    return (fullt)(t[0][0], t[0][1], t[1][0], t[1][1]);
#else
    return (fullt)(t[0][0], t[0][1], t[0][2], t[1][0], t[1][1], t[1][2], t[2][0], t[2][1], t[2][2],
                   0, 0, 0, 0, 0, 0, 0);
#endif
}

/* A particle's lattice spacing over numerics.dx (graded lattices:
 * host/scene.c); 1 on a uniform lattice. */
static inline real spacing_scale(int flag)
{
    return (real)(1 << SPH_LEVEL_OF(flag));
}

/* The neighbour grid as the passes see it: cells of edge `cell_size` from
 * `origin`, `dims` cells per axis, particles sorted by cell, and each
 * particle's cell (from its position at the last sort) in the high half of
 * its sort key. Cells are support * (1 + skin) / SPH_GRID_SPLIT wide and the
 * grid is re-sorted before any particle moves skin * support / 2, so every
 * neighbour within the support lies in the (2 SPH_GRID_SPLIT + 1)^d cells
 * around the sort-time cell. */
#define GRID_ARGS                                                                                  \
    __global const ulong *restrict sort_keys, __global const int *restrict cell_start,             \
        __global const int *restrict cell_end, const int4 grid_dims

static inline int4 grid_cell_coords(int cell, int4 dims)
{
    int4 c;
    c.x = cell % dims.x;
    c.y = (cell / dims.x) % dims.y;
    c.z = cell / (dims.x * dims.y);
    c.w = 0;
    return c;
}

/* The particles of cells x0..x1 of one grid row, [x, y): a row's cells are
 * contiguous in the sorted order; (-1, -1) when every cell is empty. */
static inline int2 cell_row_span(__global const int *restrict cell_start,
                                 __global const int *restrict cell_end, int row, int x0, int x1)
{
    int first = -1, last = -1;
    for (int cx = x0; cx <= x1; ++cx) {
        const int s = cell_start[row + cx];
        if (s < 0)
            continue;
        if (first < 0)
            first = s;
        last = cell_end[row + cx];
    }
    return (int2)(first, last);
}

#if SPH_DIM == 2
#define GRID_DZ 0
#else
#define GRID_DZ 1
#endif

/* Graded lattices (SPH_GRADED; host/scene.c): a particle of spacing level
 * k has smoothing length 2^k h, a pair uses the mean of the two (Monaghan
 * 1992's symmetrisation, so the pair forces stay equal and opposite), and
 * the grid, sized for the finest level, is searched as many cells out as
 * the particle's flags say (its coarser neighbours' support reaches that
 * far). On a uniform lattice both are constants. Kernels that use them
 * take `flags` and `run`. */
#define PAIR_H_OF(scale_i, scale_j) ((real)0.5 * run->h * ((scale_i) + (scale_j)))
#ifdef SPH_GRADED
#define PAIR_H(i, j) PAIR_H_OF(spacing_scale(flags[i]), spacing_scale(flags[j]))
#define NEIGHBOUR_REACH(i) ((flags[i] >> SPH_REACH_SHIFT) & SPH_REACH_MASK)
#else
#define PAIR_H(i, j) (run->h)
#define NEIGHBOUR_REACH(i) SPH_GRID_SPLIT
#endif

/* FOR_EACH_NEIGHBOUR(i, j) { ... } END_FOR_EACH_NEIGHBOUR visits every j in
 * the (2 reach + 1)^d cells around i's cell (reach 1 on a uniform
 * lattice), including i itself; the body tests the distance against the
 * pair's support. FOR_EACH_NEIGHBOUR_WITHIN(i, j, reach) takes the reach
 * (kernels that only run on uniform lattices: the total Lagrangian form,
 * the grid's test hook). */
#define FOR_EACH_NEIGHBOUR(i, j) FOR_EACH_NEIGHBOUR_WITHIN(i, j, NEIGHBOUR_REACH(i))
#define FOR_EACH_NEIGHBOUR_WITHIN(i, j, reach)                                                     \
    {                                                                                              \
        const int4 home_ = grid_cell_coords((int)(sort_keys[i] >> 32), grid_dims);                 \
        const int reach_ = (reach);                                                                \
        for (int dz_ = -GRID_DZ * reach_; dz_ <= GRID_DZ * reach_; ++dz_) {                        \
            const int cz_ = home_.z + dz_;                                                         \
            if (cz_ < 0 || cz_ >= grid_dims.z)                                                     \
                continue;                                                                          \
            for (int dy_ = -reach_; dy_ <= reach_; ++dy_) {                                        \
                const int cy_ = home_.y + dy_;                                                     \
                if (cy_ < 0 || cy_ >= grid_dims.y)                                                 \
                    continue;                                                                      \
                const int row_ = (cz_ * grid_dims.y + cy_) * grid_dims.x;                          \
                const int2 span_ =                                                                 \
                    cell_row_span(cell_start, cell_end, row_, max(home_.x - reach_, 0),            \
                                  min(home_.x + reach_, grid_dims.x - 1));                         \
                for (int j = span_.x; j < span_.y; ++j) {

#define END_FOR_EACH_NEIGHBOUR                                                                     \
    }                                                                                              \
    }                                                                                              \
    }                                                                                              \
    }

/* sigma = S - p I */
static inline void total_stress(real p, symt dev, real out[3][3])
{
    symt_load(dev, out);
#pragma unroll
    for (int a = 0; a < 3; ++a)
        out[a][a] -= p;
}

/* out = a . b, summed over the first SPH_DIM indices (out must not be a
 * or b) */
static inline void matrix_product(real a[3][3], real b[3][3], real out[3][3])
{
#pragma unroll
    for (int p = 0; p < 3; ++p)
#pragma unroll
        for (int q = 0; q < 3; ++q) {
            out[p][q] = 0;
#pragma unroll
            for (int k = 0; k < SPH_DIM; ++k)
                out[p][q] += a[p][k] * b[k][q];
        }
}

/* matrix_identity, matrix_invert_or_identity and the CSPH correction:
 * kernels/matrix.cl (host-compilable, tests/test_matrix.c). */

/* A neighbour's mass as the sums over the plane weigh it. Axisymmetric
 * (SPH_AXISYMMETRIC, x = r, y = z): the mass field holds the ring's mass
 * per radian m = M / (2 pi) and the plane sums take m / r, so that
 * sum_j (m_j / r_j) W_ij = rho and V_j = m_j / (r_j rho_j) is the area the
 * ring covers in the (r, z) plane (the "Cartesian" axisymmetric SPH of
 * Petschek & Libersky 1993, J. Comput. Phys. 109; hoop terms in pass 1,
 * the material update and pass 2). Ghosts beyond the axis have r < 0.
 * Every 1/r uses axis_radius(r) >= run->axis_radius (dx / 4): material
 * swept onto the axis (a cavity closing behind a projectile) would
 * otherwise see its hoop terms diverge; a ring with its centre within a
 * quarter spacing of the axis is not resolved anyway. */
static inline real axis_radius(real r, __constant const struct sph_run_params *run)
{
    return fmax(fabs(r), run->axis_radius);
}

static inline real plane_mass(real mass, vec x, __constant const struct sph_run_params *run)
{
#ifdef SPH_AXISYMMETRIC
    return mass / axis_radius(x.x, run);
#else
    (void)x;
    (void)run;
    return mass;
#endif
}

/* Work-group size of the reduction kernels (grid bounds, per-step reduce). */
#define REDUCE_WG 64

/* How a slot of a work-group reduction combines two values. */
#define REDUCE_SUM 0
#define REDUCE_MIN 1
#define REDUCE_MAX 2

/* The work-group's tree reduction of `slots` values per work-item (mine,
 * combined slot by slot as op[k] says) into partials[group * slots + k],
 * for the host to combine over the groups. acc: __local scratch of
 * REDUCE_WG * slots reals. Every work-item of the group must call it. */
static inline void work_group_reduce(__local real *acc, const real *mine, const uchar *op,
                                     int slots, __global real *partials)
{
    const int lid = get_local_id(0);
    for (int k = 0; k < slots; ++k)
        acc[lid * slots + k] = mine[k];
    barrier(CLK_LOCAL_MEM_FENCE);
    for (int stride = REDUCE_WG / 2; stride > 0; stride >>= 1) {
        if (lid < stride)
            for (int k = 0; k < slots; ++k) {
                const real a = acc[lid * slots + k], b = acc[(lid + stride) * slots + k];
                acc[lid * slots + k] = op[k] == REDUCE_MIN   ? fmin(a, b)
                                       : op[k] == REDUCE_MAX ? fmax(a, b)
                                                             : a + b;
            }
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    if (lid == 0)
        for (int k = 0; k < slots; ++k)
            partials[get_group_id(0) * slots + k] = acc[k];
}

/* The particles of a reduction's work-item: its work-group takes one
 * contiguous block of [0, n) and the group's work-items stride through the
 * block, so that on a GPU neighbouring work-items read neighbouring words and
 * on a CPU, where a work-item runs its whole loop before the next one starts,
 * the block stays in cache. A stride of the whole grid instead made every
 * work-item touch every cache line of every array it read: at 1M particles
 * reduce_step took 83 ms a step against 5 ms at 200k (docs/performance.md). */
#define FOR_GROUP_BLOCK(i, n)                                                                      \
    for (int blk_ = ((n) + (int)get_num_groups(0) - 1) / (int)get_num_groups(0),                   \
             end_ = min((n), ((int)get_group_id(0) + 1) * blk_),                                   \
             i = (int)get_group_id(0) * blk_ + (int)get_local_id(0);                               \
         i < end_; i += (int)get_local_size(0))

/* dW/dr at r (the health indicators' W'', health.cl). */
static inline real kernel_dwdr(real r, real h)
{
    return sph_kernel_dwdr(SPH_KERNEL, SPH_DIM, r, h);
}

/* W and (dW/dr) / r on lane vectors, of q = r / h and 1 / h: the pair
 * loops form q with a product by 1 / h and the powers of 1 / h by products,
 * so no division is left in the per-pair work (a vector division costs
 * many multiply-adds on a CPU, docs/performance.md). */
static inline hreal inv_h_pow_dim(hreal inv_h) /* 1 / h^dim */
{
    return SPH_DIM == 2 ? inv_h * inv_h : inv_h * inv_h * inv_h;
}

static inline realv kernel_w_q(realv q, hreal inv_h)
{
    return sph_kernel_sigma(SPH_KERNEL, SPH_DIM) * inv_h_pow_dim(inv_h) *
           sph_kernel_shape(SPH_KERNEL, q);
}

/* (dW/dr) / r, for grad_i W_ij = (dW/dr) / r x_ij */
static inline realv kernel_dwdr_over_r_q(realv q, hreal inv_h)
{
    return sph_kernel_sigma(SPH_KERNEL, SPH_DIM) * inv_h_pow_dim(inv_h) * (inv_h * inv_h) *
           sph_kernel_shape_dq_over_q(SPH_KERNEL, q);
}
