/*
 * Health checks of the particle arrangement (issue: stability where SPH
 * fails): the neighbour counts of the integrity measure, and the
 * indicators each history row reports (host/run.c watch_health).
 */

#ifdef SPH_TOTAL_LAGRANGIAN
/* |F_ij X_ij|^2, F_ij = (F_i + F_j) / 2: the squared separation the two
 * particles' deformation gives the pair (X = pos0, the reference). The
 * total Lagrangian form's health measures compare a pair with it, not with
 * a fixed length: a Taylor face squashed tenfold has pairs far closer than
 * dx / 2 and its lip pairs stretched more than twofold by its deformation
 * alone, which marked every Taylor bar in this form clumped (from about
 * 6 us) and the copper rod torn; what the form can suffer is a pair that
 * its F does not bring together (an hourglass mode, particles of one part
 * passing through each other) or pull apart (a tear). */
static inline real tl_predicted_separation2(int i, int j, __global const vec *restrict pos0,
                                            __global const fullt *restrict deformation_gradient)
{
    real f_i[3][3], f_j[3][3];
    fullt_load(deformation_gradient[i], f_i);
    fullt_load(deformation_gradient[j], f_j);
    const vec big_xij = pos0[i] - pos0[j];
    real predicted2 = 0;
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a) {
        real p = 0;
#pragma unroll
        for (int c = 0; c < SPH_DIM; ++c)
            p += (real)0.5 * (f_i[a][c] + f_j[a][c]) * vec_get(big_xij, c);
        predicted2 += p * p;
    }
    return predicted2;
}

/* Neighbours of each particle for the integrity measure (particles that
 * lost more than a third of their initial neighbours) in the total
 * Lagrangian form, where the interacting pairs change only at a reference
 * update: reference neighbours (within the support on the reference:
 * pos0) no further apart than twice the separation their deformation gives
 * them (tl_predicted_separation2), so that only a tear, not the finite
 * strain of a whole body, counts as a loss; with every_reference_neighbour
 * all of them, the count a particle had when the reference was taken (the
 * measure's baseline, host/health_watch.c). The updated Lagrangian form
 * counts the neighbours within the support, health_pairs' records
 * (host/step.c solver_neighbour_counts).
 * reads pos, pos0, deformation_gradient; writes neighbour_count. */
__kernel void health_neighbour_count(__global const vec *restrict pos,
                                     __global const vec *restrict pos0,
                                     __global const fullt *restrict deformation_gradient,
                                     __global const int *restrict flags, GRID_ARGS,
                                     __constant const struct sph_run_params *run,
                                     __global int *restrict neighbour_count,
                                     const int every_reference_neighbour, const int n)
{
    const int i = get_global_id(0);
    if (i >= n)
        return;
    const vec xi = pos[i];
    const real q2 = (run->support / run->h) * (run->support / run->h);
    int c = 0;
    FOR_EACH_NEIGHBOUR(i, j)
    {
        const real h = PAIR_H(i, j), support2 = q2 * h * h;
        const vec d = xi - pos[j];
        const vec d0 = pos0[i] - pos0[j];
        const real r02 = dot(d0, d0);
        c += (j != i && r02 < support2 &&
              (every_reference_neighbour ||
               dot(d, d) <= (real)4 * tl_predicted_separation2(i, j, pos0, deformation_gradient)))
                 ? 1
                 : 0;
    }
    END_FOR_EACH_NEIGHBOUR
    neighbour_count[i] = c;
}
#endif

/* Health indicators, in two kernels: health_pairs finds each particle's
 * neighbours within the support (count, nearest) and writes one record per
 * particle, health_indicators reduces the records per work-group like
 * reduce_step. The indicators: the smallest pair distance; the particles
 * with a neighbour closer than dx / 2 (clumping, the end state of the
 * tensile and pairing instabilities); the particles in Swegle's unstable
 * regime, W''(r) sigma_n > 0 for the nearest neighbour at distance r with
 * sigma_n = n . sigma . n the normal stress along that pair (Swegle, Hicks &
 * Attaway 1995; thesis eq. 3.1: tension where the kernel's second
 * derivative is positive); neighbour counts within the support. Ghosts and
 * fixed particles are not counted. The records live in the gather target
 * (gather_spare, host/step.c solver_health), which is free between sorts.
 *
 * The updated Lagrangian form finds the neighbours through the passes' lane
 * loop (kernels/lanes.cl: the lists, or the cell walk where there are
 * none), eight particles per work-item on a CPU: one particle per
 * work-item over the cells, as it was, cost 235 ms per row on the 3-D
 * gelatin case, twice its two passes together (docs/performance.md,
 * "The health indicators through the lanes"). The total Lagrangian form's
 * lists hold reference neighbours, not the current ones the indicators
 * are about, so it keeps the cell walk. Either way every particle within
 * the support is seen, in the cells' order, so the nearest of equally near
 * neighbours is the same one. */
struct health_record {
    real nearest; /* the nearest neighbour's distance over the particle's own spacing scale, m */
    int code;     /* neighbours within the support | SPH_HEALTH_* marks (sph_shared.h) */
};

/* W'' at r, a central difference of dW/dr over 1e-3 h, enough for its sign */
static inline real kernel_d2wdr2(real r, real h)
{
    const real step = (real)1e-3 * h;
    return (kernel_dwdr(r + step, h) - kernel_dwdr(fmax(r - step, (real)0), h)) /
           (r + step - fmax(r - step, (real)0));
}

/* Particle i's record from its neighbour count and nearest neighbour
 * (offset `nearest`, squared distance nearest2); `collapsed` is the total
 * Lagrangian form's clumping verdict (health_pairs there), unused in the
 * updated form */
static inline struct health_record health_record_of(
    int i, int count, real nearest2, const real nearest[3], bool collapsed,
    __global const real *restrict pressure, __global const symt *restrict deviatoric_stress,
    __global const int *restrict flags, __constant const struct sph_run_params *run, const real dx)
{
    /* a fixed particle's count serves the integrity measure only */
    struct health_record rec = {(real)INFINITY,
                                count | (flags[i] & SPH_FLAG_FIXED ? 0 : SPH_HEALTH_COUNTED)};
    if (count == 0)
        return rec;
    /* distances in units of the particle's own spacing over dx */
    const real scale_i = spacing_scale(flags[i]);
    const real r = sqrt(nearest2) / scale_i;
    rec.nearest = r;
    /* failed material (a fluid without tension: no tensile instability)
     * compacts against a projectile's contact; clumping counts intact
     * material only */
#ifdef SPH_TOTAL_LAGRANGIAN
    const bool clumped = collapsed;
#else
    (void)collapsed;
    const bool clumped = r < (real)0.5 * dx;
#endif
    if (clumped && !(flags[i] & SPH_FLAG_DAMAGED))
        rec.code |= SPH_HEALTH_CLUMPED_MARK;
    real sigma[3][3], normal[3];
    total_stress(pressure[i], deviatoric_stress[i], sigma);
#pragma unroll
    for (int a = 0; a < 3; ++a)
        normal[a] = nearest[a] / (r * scale_i);
    real sigma_n = 0;
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a)
#pragma unroll
        for (int b = 0; b < SPH_DIM; ++b)
            sigma_n += normal[a] * sigma[a][b] * normal[b];
    if (kernel_d2wdr2(r, run->h) * sigma_n > 0) /* in units of its own spacing */
        rec.code |= SPH_HEALTH_SWEGLE_MARK;
    return rec;
}

#ifdef SPH_TOTAL_LAGRANGIAN
#ifdef SPH_PART_CONTACT
/* the contact search's current cells (contact_current.cl) */
#define TL_HEALTH_CONTACT_ARGS                                                                     \
    , __global const ulong *restrict contact_keys,                                                 \
        __global const int *restrict contact_cell_start,                                           \
        __global const int *restrict contact_cell_end, const real4 grid_origin,                    \
        const real grid_inv_cell_size
#else
#define TL_HEALTH_CONTACT_ARGS
#endif
/* One particle per work-item over the reference cells (FOR_EACH_NEIGHBOUR),
 * and with parts (SPH_PART_CONTACT) the other parts' particles near it now
 * through the contact search's cells, so that the nearest pair is of any
 * part, as in the updated form; the count stays the walk's. A particle is
 * clumped when a neighbour of its own part is closer than half the
 * separation their deformation gives the pair (tl_predicted_separation2),
 * or one of another part closer than dx / 2.
 * reads pos, pos0, deformation_gradient, pressure, deviatoric_stress,
 * flags (and contact_keys, contact_cell_start, contact_cell_end); writes
 * records. */
__kernel void health_pairs(__global const vec *restrict pos, __global const vec *restrict pos0,
                           __global const fullt *restrict deformation_gradient,
                           __global const real *restrict pressure,
                           __global const symt *restrict deviatoric_stress,
                           __global const int *restrict flags, GRID_ARGS,
                           __constant const struct sph_run_params *run, const real dx,
                           __global struct health_record *restrict records,
                           const int n TL_HEALTH_CONTACT_ARGS)
{
    const int i = get_global_id(0);
    if (i >= n)
        return;
    if (flags[i] & SPH_FLAG_GHOST) {
        records[i] = (struct health_record){(real)INFINITY, 0};
        return;
    }
    const real q2 = (run->support / run->h) * (run->support / run->h);
    const real scale = spacing_scale(flags[i]), /* another part's pair: dx / 2 */
        apart2 = (real)0.25 * dx * dx * scale * scale;
    const vec xi = pos[i];
    const int part = SPH_PART_OF(flags[i]);
    real nearest2 = INFINITY;
    vec nearest = VEC_ZERO;
    int count = 0;
    bool collapsed = false;
    FOR_EACH_NEIGHBOUR(i, j)
    {
        const vec d = pos[j] - xi;
        const real r2 = dot(d, d);
        const real h = PAIR_H(i, j);
        if (j != i && r2 < q2 * h * h) {
            ++count;
            if (r2 < nearest2) {
                nearest2 = r2;
                nearest = d;
            }
            /* closer than half the separation their deformation gives
             * them; another part's pair, which no F relates, dx / 2 */
            collapsed |=
                r2 < (SPH_PART_OF(flags[j]) == part
                          ? (real)0.25 * tl_predicted_separation2(i, j, pos0, deformation_gradient)
                          : apart2);
        }
    }
    END_FOR_EACH_NEIGHBOUR
#ifdef SPH_PART_CONTACT
    real other2 = INFINITY;
    vec other = VEC_ZERO;
    contact_nearest_other_part(i, xi, pos, flags, contact_keys, contact_cell_start,
                               contact_cell_end, grid_origin, grid_inv_cell_size, grid_dims,
                               &other2, &other);
    collapsed |= other2 < apart2;
    if (other2 < nearest2) {
        nearest2 = other2;
        nearest = other;
    }
#endif
    real offset[3];
#pragma unroll
    for (int a = 0; a < 3; ++a)
        offset[a] = vec_get(nearest, a);
    records[i] = health_record_of(i, count, nearest2, offset, collapsed, pressure,
                                  deviatoric_stress, flags, run, dx);
}
#else
/* One work-item per lane block (FOR_EACH_LANE_NEIGHBOUR).
 * reads pos, pressure, deviatoric_stress, flags; writes records. */
__kernel void health_pairs(__global const vec *restrict pos, __global const real *restrict pressure,
                           __global const symt *restrict deviatoric_stress,
                           __global const int *restrict flags, LANE_GRID_ARGS,
                           __constant const struct sph_run_params *run, const real dx,
                           __global struct health_record *restrict records, const int n)
{
    struct lane_block b;
    const int live = lane_block_setup(&b, flags, sort_keys, grid_dims, n);
    if (b.first >= n)
        return;
    LANE_PASS_CONSTANTS; /* the passes' support: the pairs they see */
#ifndef SPH_GRADED
    (void)inv_h;
#endif
    realv xi[3];
    lane_positions(pos, &b, n, xi);
    mask_union index; /* each lane's particle, to leave j = i out */
    for (int l = 0; l < SPH_LANES; ++l)
        index.s[l] = b.first + l;
    realv nearest2 = (realv)INFINITY, count = (realv)0, nearest[3];
#ifdef SPH_PART_CONTACT
    /* the integrity measure counts the neighbours a particle's own
     * continuum sums over (pass1.cl): two parts that come apart lose
     * nothing; the nearest neighbour (clumping) is of any part */
    const realv parts = lane_parts(flags, &b, n);
#endif
#pragma unroll
    for (int a = 0; a < 3; ++a)
        nearest[a] = (realv)0;
    if (live) {
        FOR_EACH_LANE_NEIGHBOUR(b, j)
        {
            LANE_PAIR_SUPPORT(b, j);
            (void)h;
            realv xij[3], r2;
            /* lane_pair's offset and distance; its mask leaves out r = 0,
             * which a coincident pair (clumping at its end) must not be */
            (void)lane_pair(xi, pos[j], support2, xij, &r2);
#ifdef SPH_TENSOR_SMOOTHING
            /* counted within the isotropic support, not the search's reach
             * of TENSOR_AXIS_MAX supports (tensor_smoothing.cl) */
            const real counted2 = support2 * (real)(1.0 / (TENSOR_AXIS_MAX * TENSOR_AXIS_MAX));
#else
            const hreal counted2 = support2;
#endif
            const maskv within = (r2 < counted2) & (index.v != (maskv)j);
            if (!lanes_any(within))
                continue;
#ifdef SPH_PART_CONTACT
            count += SPH_SELECT((realv)0, (realv)1, within & SAME_PART(parts, j));
#else
            count += SPH_SELECT((realv)0, (realv)1, within);
#endif
            const maskv closer = within & (r2 < nearest2);
            nearest2 = SPH_SELECT(nearest2, r2, closer);
#pragma unroll
            for (int a = 0; a < 3; ++a)
                nearest[a] = SPH_SELECT(nearest[a], xij[a], closer);
        }
        END_FOR_EACH_LANE_NEIGHBOUR
    }
    for (int l = 0; l < SPH_LANES && b.first + l < n; ++l) {
        const int i = b.first + l;
        if (!lane_live(&b, l)) { /* a ghost */
            records[i] = (struct health_record){(real)INFINITY, 0};
            continue;
        }
        const real offset[3] = {lane_of(nearest[0], l), lane_of(nearest[1], l),
                                lane_of(nearest[2], l)};
        records[i] = health_record_of(i, (int)lane_of(count, l), lane_of(nearest2, l), offset,
                                      false, pressure, deviatoric_stress, flags, run, dx);
    }
}
#endif

static inline bool health_slot_is_min(int slot)
{
    return slot == SPH_HEALTH_MIN_DISTANCE || slot == SPH_HEALTH_NEIGHBOURS_MIN;
}

/* The records reduced per work-group (host/step.c solver_health combines
 * the groups). reads records; writes health partials. */
__kernel __attribute__((reqd_work_group_size(REDUCE_WG, 1, 1))) void
health_indicators(__global const struct health_record *restrict records,
                  __global real *restrict partials, const int n)
{
    __local real acc[REDUCE_WG][SPH_HEALTH_SLOTS];
    real mine[SPH_HEALTH_SLOTS];
    for (int k = 0; k < SPH_HEALTH_SLOTS; ++k)
        mine[k] = health_slot_is_min(k) ? (real)INFINITY : (real)0;
    FOR_GROUP_BLOCK (i, n) {
        const struct health_record rec = records[i];
        if (!(rec.code & SPH_HEALTH_COUNTED))
            continue;
        const real count = (real)(rec.code & SPH_HEALTH_COUNT_MASK);
        mine[SPH_HEALTH_PARTICLES] += 1;
        mine[SPH_HEALTH_NEIGHBOURS_MIN] = fmin(mine[SPH_HEALTH_NEIGHBOURS_MIN], count);
        mine[SPH_HEALTH_NEIGHBOURS_MAX] = fmax(mine[SPH_HEALTH_NEIGHBOURS_MAX], count);
        mine[SPH_HEALTH_NEIGHBOURS_SUM] += count;
        if (count == 0)
            continue;
        mine[SPH_HEALTH_MIN_DISTANCE] = fmin(mine[SPH_HEALTH_MIN_DISTANCE], rec.nearest);
        if (rec.code & SPH_HEALTH_CLUMPED_MARK)
            mine[SPH_HEALTH_CLUMPED] += 1;
        if (rec.code & SPH_HEALTH_SWEGLE_MARK)
            mine[SPH_HEALTH_SWEGLE] += 1;
    }
    uchar op[SPH_HEALTH_SLOTS];
    for (int k = 0; k < SPH_HEALTH_SLOTS; ++k)
        op[k] = health_slot_is_min(k)            ? REDUCE_MIN
                : k == SPH_HEALTH_NEIGHBOURS_MAX ? REDUCE_MAX
                                                 : REDUCE_SUM;
    work_group_reduce(&acc[0][0], mine, op, SPH_HEALTH_SLOTS, partials);
}
