/*
 * Passes 1 and 2 over lanes of particles (SPH_LANES; numerics.neighbour_loop:
 * lanes, the default where it applies: a plane or 3-D lattice, uniform or
 * graded, the updated Lagrangian form).
 *
 * Why: PoCL vectorises a kernel across work-items only when its body has
 * no inner loop of varying trip count, so pass1.cl and pass2.cl, whose
 * neighbour loops differ per particle, run one particle per instruction on
 * a CPU (docs/performance.md). Here a work-item takes SPH_LANES consecutive
 * particles of the cell-sorted order (mostly in the same or adjacent
 * cells), walks the union of their search boxes once, and evaluates each
 * candidate j for all lanes at once in realv arithmetic: j's data are
 * loaded once and broadcast, i's live in vector registers, a candidate no
 * lane reaches costs one vector distance test. A lane whose particle is not
 * within the support contributes exactly zero (select, not a multiply, so
 * the r = 0 of i itself cannot leak a NaN).
 *
 * The physics is pass1.cl's and pass2.cl's term by term; pass 2 here
 * forms its reciprocals (1/rho_i, m_j/rho_j, 1/rho_mean, 1/h) once instead
 * of dividing per term, and the sums over the neighbours run in the same
 * cell order, so the results agree with the plain passes to rounding
 * (tests: lanes_match_plain_*, every smoothing kernel).
 */
#if SPH_LANES > 0 /* 0: the plain passes (host/state.c, solver_lanes) */

#if SPH_LANES == 4
#ifdef SPH_DOUBLE
typedef double4 realv;
typedef long4 maskv;
#else
typedef float4 realv;
typedef int4 maskv;
#endif
#elif SPH_LANES == 8
#ifdef SPH_DOUBLE
typedef double8 realv;
typedef long8 maskv;
#else
typedef float8 realv;
typedef int8 maskv;
#endif
#elif SPH_LANES == 16
#ifdef SPH_DOUBLE
typedef double16 realv;
typedef long16 maskv;
#else
typedef float16 realv;
typedef int16 maskv;
#endif
#else
#error "SPH_LANES must be 4, 8 or 16"
#endif

#ifdef SPH_AXISYMMETRIC
#error "the lane passes serve plane and 3-D lattices (host/state.c picks the plain passes)"
#endif
#if defined(SPH_GRADED) && defined(SPH_ARTIFICIAL_STRESS)
#error "graded lattices take no artificial stress (host/case.c)"
#endif

/* The pair's smoothing length: one number on a uniform lattice, a lane
 * vector on a graded one (the mean of the two particles' h, common.cl
 * PAIR_H), where each lane's particle has its own level. */
#ifdef SPH_GRADED
typedef realv hreal;
#else
typedef real hreal;
#endif

#ifdef SPH_DOUBLE
typedef long mask_scalar;
#else
typedef int mask_scalar;
#endif

typedef union {
    realv v;
    real s[SPH_LANES];
} lanes_union;

typedef union {
    maskv v;
    mask_scalar s[SPH_LANES];
} mask_union;

static inline real lane_of(realv v, int l)
{
    lanes_union u;
    u.v = v;
    return u.s[l];
}

/* The smoothing kernel's shape f(q) and df/dq (smoothing.cl) on a vector
 * of q; SPH_KERNEL is a build constant, so one branch survives. */
static inline realv shape_v(realv q)
{
    const realv zero = (realv)0, one = (realv)1, two = (realv)2;
    if (SPH_KERNEL == SPH_KERNEL_CUBIC_SPLINE) {
        const realv t = fmax(two - q, zero);
        return select((real)0.25 * t * t * t, one - (real)1.5 * q * q + (real)0.75 * q * q * q,
                      q < one);
    }
    if (SPH_KERNEL == SPH_KERNEL_GAUSSIAN)
        return select(zero, exp(-q * q) - (real)SPH_EXPM9, q <= (real)3);
    if (SPH_KERNEL == SPH_KERNEL_QUINTIC_SPLINE) {
        const realv a = fmax((real)3 - q, zero), b = fmax(two - q, zero), c = fmax(one - q, zero);
        const realv a2 = a * a, b2 = b * b, c2 = c * c;
        return a2 * a2 * a - (real)6 * b2 * b2 * b + (real)15 * c2 * c2 * c;
    }
    if (SPH_KERNEL == SPH_KERNEL_WENDLAND_C2) {
        const realv t = fmax(one - (real)0.5 * q, zero);
        return (t * t) * (t * t) * ((real)2 * q + one);
    }
    if (SPH_KERNEL == SPH_KERNEL_DOUBLE_COSINE) {
        const real k = (real)SPH_DOUBLE_COSINE_K, pi = (real)SPH_PI;
        return select(zero, (real)4 * cos(pi * q / k) + cos((real)2 * pi * q / k) + (real)3,
                      q <= k);
    }
    /* SPH_KERNEL_HYPERBOLIC */
    const realv t = fmax(two - q, zero);
    return select(t * t * t, q * q * q - (real)6 * q + (real)6, q <= one);
}

static inline realv shape_dq_v(realv q)
{
    const realv zero = (realv)0, one = (realv)1, two = (realv)2;
    if (SPH_KERNEL == SPH_KERNEL_CUBIC_SPLINE) {
        const realv t = fmax(two - q, zero);
        return select((real)-0.75 * t * t, (real)-3 * q + (real)2.25 * q * q, q < one);
    }
    if (SPH_KERNEL == SPH_KERNEL_GAUSSIAN)
        return select(zero, (real)-2 * q * exp(-q * q), q <= (real)3);
    if (SPH_KERNEL == SPH_KERNEL_QUINTIC_SPLINE) {
        const realv a = fmax((real)3 - q, zero), b = fmax(two - q, zero), c = fmax(one - q, zero);
        const realv a2 = a * a, b2 = b * b, c2 = c * c;
        return (real)-5 * a2 * a2 + (real)30 * b2 * b2 - (real)75 * c2 * c2;
    }
    if (SPH_KERNEL == SPH_KERNEL_WENDLAND_C2) {
        const realv t = fmax(one - (real)0.5 * q, zero);
        return (real)-5 * q * t * t * t;
    }
    if (SPH_KERNEL == SPH_KERNEL_DOUBLE_COSINE) {
        const real k = (real)SPH_DOUBLE_COSINE_K, pi = (real)SPH_PI;
        return select(zero,
                      -(real)4 * pi / k * sin(pi * q / k) -
                          (real)2 * pi / k * sin((real)2 * pi * q / k),
                      q <= k);
    }
    const realv t = fmax(two - q, zero);
    return select((real)-3 * t * t, (real)3 * q * q - (real)6, q <= one);
}

/* df/dq / q, what the kernel gradient dW/dr x_ij / r needs: for the
 * Wendland C2 and the Gaussian kernels q cancels, so the pair loops do not
 * divide by r (a vector division costs many multiply-adds on a CPU); the
 * others divide. */
static inline realv shape_dq_over_q_v(realv q)
{
    if (SPH_KERNEL == SPH_KERNEL_WENDLAND_C2) {
        const realv t = fmax((realv)1 - (real)0.5 * q, (realv)0);
        return (real)-5 * t * t * t;
    }
    if (SPH_KERNEL == SPH_KERNEL_GAUSSIAN)
        return select((realv)0, (real)-2 * exp(-q * q), q <= (real)3);
    return shape_dq_v(q) / q;
}

/* W of q = r / h: the pair loops form q with a product by 1 / h
 * and keep their divisions out of the per-candidate work, since a vector
 * division costs many multiply-adds on a CPU (docs/performance.md). */
/* 1 / h^dim, as sph_inv_h_pow (smoothing.cl) */
static inline hreal inv_h_pow_v(hreal h)
{
    const hreal ih = (real)1 / h;
    return SPH_DIM == 2 ? ih * ih : ih * ih * ih;
}

static inline realv kernel_w_q_v(realv q, hreal h)
{
    return sph_kernel_sigma(SPH_KERNEL, SPH_DIM) * inv_h_pow_v(h) * shape_v(q);
}

/* (dW/dr) / r of q = r / h, for grad_i W_ij = (dW/dr) / r x_ij */
static inline realv kernel_dwdr_over_r_q_v(realv q, hreal h)
{
    return sph_kernel_sigma(SPH_KERNEL, SPH_DIM) * inv_h_pow_v(h) / (h * h) * shape_dq_over_q_v(q);
}

/* Whether any lane of a mask is set. OpenCL's any() on a vector mask runs
 * lane by lane in PoCL 3.1 and took a third of pass 1's time at 50k; an
 * OR of the mask's 64-bit words in halves is a few vector instructions
 * (pass 1 17.9 against 22.5 ms, docs/performance.md). */
#ifdef SPH_DOUBLE
#define LANE_MASK_WORDS SPH_LANES
#else
#define LANE_MASK_WORDS (SPH_LANES / 2)
#endif
static inline int lanes_any(maskv m)
{
#if LANE_MASK_WORDS == 16
    const ulong16 w16 = as_ulong16(m);
    const ulong8 w8 = w16.lo | w16.hi;
#elif LANE_MASK_WORDS == 8
    const ulong8 w8 = as_ulong8(m);
#endif
#if LANE_MASK_WORDS >= 8
    const ulong4 w4 = w8.lo | w8.hi;
#elif LANE_MASK_WORDS == 4
    const ulong4 w4 = as_ulong4(m);
#endif
#if LANE_MASK_WORDS >= 4
    const ulong2 w2 = w4.lo | w4.hi;
#else
    const ulong2 w2 = as_ulong2(m);
#endif
    return (w2.x | w2.y) != 0;
}

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

/* The pair smoothing length of the lanes with candidate j; on a uniform
 * lattice run->h, set once before the loop. */
#ifdef SPH_GRADED
#define LANE_PAIR_H(b, j) ((real)0.5 * run->h * ((b).scale + spacing_scale(flags[j])))
#endif

/* Whether lane l of a block holds a particle its pass updates (set up by
 * lane_block_setup: not past n, not a ghost). */
static inline bool lane_live(const struct lane_block *b, int l)
{
    mask_union u;
    u.v = b->live;
    return u.s[l] != 0;
}

/* FOR_EACH_LANE_NEIGHBOUR(block, j) { ... } END_FOR_EACH_LANE_NEIGHBOUR:
 * every j in the cells within SPH_GRID_SPLIT of the block's box; rows of
 * cells are contiguous in the sorted order, as in FOR_EACH_NEIGHBOUR. */
#define FOR_EACH_LANE_NEIGHBOUR(b, j)                                                              \
    for (int cz_ = max((b).lo.z - GRID_DZ * LANE_REACH(b), 0);                                     \
         cz_ <= min((b).hi.z + GRID_DZ * LANE_REACH(b), grid_dims.z - 1); ++cz_)                   \
        for (int cy_ = max((b).lo.y - LANE_REACH(b), 0);                                           \
             cy_ <= min((b).hi.y + LANE_REACH(b), grid_dims.y - 1); ++cy_) {                       \
            const int row_ = (cz_ * grid_dims.y + cy_) * grid_dims.x;                              \
            const int2 span_ =                                                                     \
                cell_row_span(cell_start, cell_end, row_, max((b).lo.x - LANE_REACH(b), 0),        \
                              min((b).hi.x + LANE_REACH(b), grid_dims.x - 1));                     \
            for (int j = span_.x; j < span_.y; ++j) {

#define END_FOR_EACH_LANE_NEIGHBOUR                                                                \
    }                                                                                              \
    }

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

/* The lanes' positions; a lane that is not live is put LANE_FAR away, out
 * of every candidate's reach, so lane_pair needs no live mask. */
#define LANE_FAR ((real)1e18)
static inline void lane_positions(__global const vec *restrict pos, const struct lane_block *b,
                                  int n, realv xi[3])
{
    gather_vec(pos, b, n, xi);
#pragma unroll
    for (int a = 0; a < 3; ++a)
        xi[a] = select((realv)LANE_FAR, xi[a], b->live);
}

/* reads: pos, vel (half step), rho, mass, material, flags, energy_rate;
 * writes: csph, velocity_gradient (SPH_AV_LIMITED); updates: the material
 * state (as pass1_velocity_gradient). */
__kernel void pass1_lanes(__global const vec *restrict pos, __global const vec *restrict vel,
                          __global const real *restrict rho, __global const real *restrict mass,
                          __global const int *restrict material, __global const int *restrict flags,
                          GRID_ARGS, __constant const struct sph_material *materials,
                          __constant const struct sph_run_params *run, __global symt *restrict csph,
                          __global fullt *restrict velocity_gradient,
                          __global real *restrict av_alpha, const real dt, MATERIAL_STATE_ARGS,
                          const int n)
{
    struct lane_block b;
    if ((int)get_global_id(0) * SPH_LANES >= n ||
        !lane_block_setup(&b, flags, sort_keys, grid_dims, n))
        return;
#ifdef SPH_GRADED
    const real q2 = (run->support / run->h) * (run->support / run->h); /* (support / h)^2 */
#else
    const real h = run->h, inv_h = (real)1 / h, support2 = run->support * run->support;
#endif
    realv xi[3], vi[3];
    lane_positions(pos, &b, n, xi);
    gather_vec(vel, &b, n, vi);
    realv grad_v[3][3], moment[3][3];
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int c = 0; c < 3; ++c)
            grad_v[a][c] = moment[a][c] = (realv)0;
    FOR_EACH_LANE_NEIGHBOUR(b, j)
    {
        realv xij[3], r2;
#ifdef SPH_GRADED
        const hreal h = LANE_PAIR_H(b, j), inv_h = (real)1 / h, support2 = q2 * h * h;
#endif
        const maskv near = lane_pair(xi, pos[j], support2, xij, &r2);
        if (!lanes_any(near))
            continue;
        const realv r = sqrt(r2);
        const real volume = mass[j] / rho[j];
        /* grad_i W_ij = dW/dr x_ij / r; zero for lanes out of reach */
        const realv dwdr_r = select((realv)0, kernel_dwdr_over_r_q_v(r * inv_h, h), near);
        const vec vj = vel[j];
#pragma unroll
        for (int a = 0; a < SPH_DIM; ++a) {
            const realv vji = vec_get(vj, a) - vi[a];
#pragma unroll
            for (int c = 0; c < SPH_DIM; ++c) {
                const realv g = dwdr_r * xij[c];
                grad_v[a][c] += volume * vji * g;
#ifdef SPH_CSPH
                moment[a][c] -= volume * xij[a] * g;
#endif
            }
        }
    }
    END_FOR_EACH_LANE_NEIGHBOUR
    for (int l = 0; l < SPH_LANES; ++l) {
        if (!lane_live(&b, l))
            continue;
        const int i = b.first + l;
        real gv[3][3], m[3][3];
#pragma unroll
        for (int a = 0; a < 3; ++a)
#pragma unroll
            for (int c = 0; c < 3; ++c) {
                gv[a][c] = lane_of(grad_v[a][c], l);
                m[a][c] = lane_of(moment[a][c], l);
            }
        pass1_finish(i, gv, m, rho, material, flags, materials, run, csph, velocity_gradient,
                     av_alpha, dt, pos, vel, MATERIAL_STATE);
    }
}

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

#ifdef SPH_AV_LIMITED
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

/* av_limiter (pass2.cl) per lane */
static inline realv av_limiter_v(realv g_i, realv g_j, realv eta, real eta_crit)
{
    const realv sum = g_i + g_j, fold = (eta - eta_crit) / ((real)0.2 * eta_crit);
    const realv phi = select((realv)0, (real)4 * g_i * g_j / (sum * sum), g_i * g_j > (real)0);
    return select(phi, phi * exp(-fold * fold), eta < eta_crit);
}

/* limited_jump (pass2.cl) per lane: jump = v_ij - phi / 2 (L_i + L_j) x_ij */
static inline void limited_jump_v(realv vij[3], realv xij[3], realv r, hreal inv_h, realv l_i[3][3],
                                  __global const fullt *restrict velocity_gradient, int j,
                                  __constant const struct sph_run_params *run, realv jump[3])
{
    real l_j[3][3];
    fullt_load(velocity_gradient[j], l_j);
    realv d[3], g_i = (realv)0, g_j = (realv)0;
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a) {
        realv d_i = (realv)0, d_j = (realv)0;
#pragma unroll
        for (int c = 0; c < SPH_DIM; ++c) {
            d_i += l_i[a][c] * xij[c];
            d_j += l_j[a][c] * xij[c];
        }
        g_i += xij[a] * d_i;
        g_j += xij[a] * d_j;
        d[a] = d_i + d_j;
    }
    const realv half_phi = (real)0.5 * av_limiter_v(g_i, g_j, r * inv_h, run->av_eta_crit);
#pragma unroll
    for (int a = 0; a < 3; ++a)
        jump[a] = a < SPH_DIM ? vij[a] - half_phi * d[a] : (realv)0;
}
#endif

#ifdef SPH_ARTIFICIAL_STRESS
/* Monaghan's (2000) weight (W(r) / W(dx))^n per lane (pass2.cl). */
static inline realv artificial_stress_weight_v(realv r, real h,
                                               __constant const struct sph_run_params *run)
{
    const realv f = kernel_w_q_v(r * ((real)1 / h), h) * run->as_inv_w_dx;
    realv fn = (realv)1;
    for (int k = 0; k < run->as_exponent; ++k)
        fn *= f;
    return fn;
}
#endif

/* reads: pos, pos0, vel, rho, mass, pressure, deviatoric_stress,
 * artificial_stress, csph, sound_speed, velocity_gradient (limited), av_alpha (switch);
 * writes: acceleration, energy_rate, viscous_heating, xsph_velocity (as
 * pass2_momentum_energy, whose comments give the equations). */
__kernel void
pass2_lanes(__global const vec *restrict pos, __global const vec *restrict pos0,
            __global const vec *restrict vel, __global const real *restrict rho,
            __global const real *restrict mass, __global const real *restrict pressure,
            __global const symt *restrict deviatoric_stress,
            __global const symt *restrict artificial_stress, __global const symt *restrict csph,
            __global const real *restrict sound_speed,
            __global const fullt *restrict velocity_gradient,
            __global const real *restrict av_alpha, __global const int *restrict flags, GRID_ARGS,
            __constant const struct sph_run_params *run, __global vec *restrict acceleration,
            __global real *restrict energy_rate, __global real *restrict viscous_heating,
            __global vec *restrict xsph_velocity, const int n)
{
    struct lane_block b;
    if ((int)get_global_id(0) * SPH_LANES >= n ||
        !lane_block_setup(&b, flags, sort_keys, grid_dims, n))
        return;
#ifdef SPH_GRADED
    const real q2 = (run->support / run->h) * (run->support / run->h); /* (support / h)^2 */
#else
    const real h = run->h, inv_h = (real)1 / h, support2 = run->support * run->support;
#endif
    realv xi[3], vi[3], sigma_i[3][3];
    lane_positions(pos, &b, n, xi);
    gather_vec(vel, &b, n, vi);
    const realv rho_i = select((realv)1, gather_real(rho, &b, n), b.live),
                inv_rho_i = (real)1 / rho_i;
    gather_symt(deviatoric_stress, &b, n, sigma_i);
    {
        const realv p_i = gather_real(pressure, &b, n);
#pragma unroll
        for (int a = 0; a < 3; ++a) {
            sigma_i[a][a] -= p_i;
#pragma unroll
            for (int c = 0; c < 3; ++c)
                sigma_i[a][c] /= rho_i; /* sigma_i / rho_i */
        }
    }
    const realv c_i = gather_real(sound_speed, &b, n);
#ifdef SPH_ARTIFICIAL_STRESS
    realv r_i[3][3];
    gather_symt(artificial_stress, &b, n, r_i);
#ifndef SPH_AS_LATTICE_WEIGHT
    realv x0_i[3];
    gather_vec(pos0, &b, n, x0_i);
#endif
#else
    (void)artificial_stress;
    (void)pos0;
#endif
#ifdef SPH_CSPH
    realv c_i_t[3][3];
    gather_symt(csph, &b, n, c_i_t);
#else
    (void)csph;
#endif
#ifdef SPH_AV_LIMITED
    realv l_i[3][3];
    gather_fullt(velocity_gradient, &b, n, l_i);
#else
    (void)velocity_gradient;
#endif
#ifdef SPH_AV_SWITCH
    const realv alpha_i = gather_real(av_alpha, &b, n);
    const real beta_per_alpha = run->av_alpha > 0 ? run->av_beta / run->av_alpha : (real)0;
#else
    (void)av_alpha;
#endif
    realv acc[3] = {(realv)0, (realv)0, (realv)0}, xsph[3] = {(realv)0, (realv)0, (realv)0};
    realv de_viscous = (realv)0, de_stress = (realv)0; /* the two artificial heatings */
    FOR_EACH_LANE_NEIGHBOUR(b, j)
    {
        realv xij[3], r2;
#ifdef SPH_GRADED
        const hreal h = LANE_PAIR_H(b, j), inv_h = (real)1 / h, support2 = q2 * h * h;
#endif
        const maskv near = lane_pair(xi, pos[j], support2, xij, &r2);
        if (!lanes_any(near))
            continue;
        const realv r = sqrt(r2);
        const vec vj = vel[j];
        realv vij[3];
#pragma unroll
        for (int a = 0; a < 3; ++a)
            vij[a] = a < SPH_DIM ? vi[a] - vec_get(vj, a) : (realv)0;
        const real rho_j = rho[j], m_j = mass[j], m_over_rho_j = m_j / rho_j;
        const realv inv_rho_mean = (real)2 / (rho_i + rho_j);
        /* Monaghan (1992) viscosity, approaching pairs only */
#ifdef SPH_AV_LIMITED
        realv jump[3];
        limited_jump_v(vij, xij, r, inv_h, l_i, velocity_gradient, j, run, jump);
#else
        realv *jump = vij;
#endif
        const realv vr = jump[0] * xij[0] + jump[1] * xij[1] + jump[2] * xij[2];
        const realv mu = h * vr / (r2 + (real)0.01 * h * h);
        const realv c_mean = (real)0.5 * (c_i + sound_speed[j]);
#ifdef SPH_AV_SWITCH
        const realv alpha_ij = (real)0.5 * (alpha_i + av_alpha[j]),
                    beta_ij = beta_per_alpha * alpha_ij;
#else
        const real alpha_ij = run->av_alpha, beta_ij = run->av_beta;
#endif
        const realv pi_ij = select(
            (realv)0, (-alpha_ij * c_mean * mu + beta_ij * mu * mu) * inv_rho_mean, vr < (real)0);
        const realv q = r * inv_h;
        const realv dwdr_r = select((realv)0, kernel_dwdr_over_r_q_v(q, h), near);
        de_viscous += (real)0.5 * m_j * pi_ij * dwdr_r *
                      (vij[0] * xij[0] + vij[1] * xij[1] + vij[2] * xij[2]);
        realv grad[3], g_i[3], g_j[3];
#pragma unroll
        for (int a = 0; a < 3; ++a)
            grad[a] = a < SPH_DIM ? dwdr_r * xij[a] : (realv)0;
#ifdef SPH_CSPH
        real c_j[3][3];
        symt_load(csph[j], c_j);
#pragma unroll
        for (int a = 0; a < 3; ++a) {
            g_i[a] = g_j[a] = (realv)0;
#pragma unroll
            for (int c = 0; c < SPH_DIM; ++c) {
                g_i[a] += c_i_t[c][a] * grad[c];
                g_j[a] += c_j[c][a] * grad[c];
            }
        }
#else
#pragma unroll
        for (int a = 0; a < 3; ++a)
            g_i[a] = g_j[a] = grad[a];
#endif
        /* (sigma_i . g_i + sigma_j . g_j) / (rho_i rho_j) and the
         * artificial terms (f^n (R_i + R_j) - Pi I) . g */
        real sigma_j[3][3];
        symt_load(deviatoric_stress[j], sigma_j);
        const real p_j = pressure[j];
#pragma unroll
        for (int a = 0; a < 3; ++a)
            sigma_j[a][a] -= p_j;
        realv t_i[3], t_j[3], extra[3];
#pragma unroll
        for (int a = 0; a < SPH_DIM; ++a) {
            t_i[a] = t_j[a] = (realv)0;
#pragma unroll
            for (int c = 0; c < SPH_DIM; ++c) {
                t_i[a] += sigma_i[a][c] * g_i[c];
                t_j[a] += sigma_j[a][c] * g_j[c];
            }
            extra[a] = -pi_ij * grad[a];
        }
#ifdef SPH_ARTIFICIAL_STRESS
        {
            realv fn = artificial_stress_weight_v(r, h, run);
#ifndef SPH_AS_LATTICE_WEIGHT
            const vec x0_j = pos0[j];
            realv d0[3];
#pragma unroll
            for (int a = 0; a < 3; ++a)
                d0[a] = a < SPH_DIM ? x0_i[a] - vec_get(x0_j, a) : (realv)0;
            const realv r0 = sqrt(d0[0] * d0[0] + d0[1] * d0[1] + d0[2] * d0[2]);
            fn = fmax(fn - artificial_stress_weight_v(r0, h, run), (realv)0);
#endif
            real r_j[3][3];
            symt_load(artificial_stress[j], r_j);
#pragma unroll
            for (int a = 0; a < SPH_DIM; ++a) {
                realv rg = (realv)0;
#pragma unroll
                for (int c = 0; c < SPH_DIM; ++c)
                    rg += (r_j[a][c] + r_i[a][c]) * grad[c];
                extra[a] += fn * rg;
                de_stress -= (real)0.5 * m_j * fn * vij[a] * rg;
            }
        }
#endif
#pragma unroll
        for (int a = 0; a < SPH_DIM; ++a)
            acc[a] += m_over_rho_j * (t_i[a] + t_j[a] * inv_rho_i) + m_j * extra[a];
#ifdef SPH_XSPH
        const realv w = select((realv)0, kernel_w_q_v(q, h), near);
#pragma unroll
        for (int a = 0; a < SPH_DIM; ++a)
            xsph[a] -= (m_j * inv_rho_mean * w) * vij[a];
#endif
    }
    END_FOR_EACH_LANE_NEIGHBOUR
    for (int l = 0; l < SPH_LANES; ++l) {
        if (!lane_live(&b, l))
            continue;
        const int i = b.first + l;
        acceleration[i] = vec_make(lane_of(acc[0], l), lane_of(acc[1], l), lane_of(acc[2], l));
        energy_rate[i] = lane_of(de_viscous + de_stress, l);
        viscous_heating[i] = lane_of(de_viscous, l);
#ifdef SPH_XSPH
        xsph_velocity[i] = run->xsph_epsilon *
                           vec_make(lane_of(xsph[0], l), lane_of(xsph[1], l), lane_of(xsph[2], l));
#else
        xsph_velocity[i] = VEC_ZERO;
#endif
    }
}

#endif /* SPH_LANES */
