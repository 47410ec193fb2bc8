/*
 * Contact between parts (bodies[].part) in the total Lagrangian form.
 *
 * The total Lagrangian passes (total_lagrangian.cl) sum over the neighbours
 * a particle had at t = 0, searched once on the reference positions, so two
 * parts that start apart never meet there. Their contact needs the current
 * positions: the particles' current cells are keyed and sorted into a
 * second cell list (contact_keys, contact_cell_start / end: the same grid
 * geometry as the reference one), again whenever a particle may have
 * drifted out of its reach (host/step.c tl_contact_list_current), which
 * this pass and the health records read, and for every pair of different parts closer than the
 * lattice spacing d it adds what pass 2 adds in the updated form
 * (pass2.cl, part_contact): the contact pressure
 *   dv_i/dt += -m_j 2 p_c / (rho_i rho_j) grad W_ij,
 *   p_c = K_ij (1 - r / d) / (2 d^(dim+1) |W'(d)|),
 * and the artificial viscosity of the touching pair, on the plain kernel
 * gradient (antisymmetric: momentum is kept pair by pair). The pressure's
 * work goes to and comes back from the internal energy as in the updated
 * form, the viscosity's to viscous_heating too, so the ledger closes
 * without a new term. The total Lagrangian form has no tensile
 * instability (Belytschko et al. 2000), so colliding elastic bodies that
 * the updated form tears (the rubber rings of Gray, Monaghan & Swift 2001)
 * can stay whole; it cannot follow fracture or mixing within a part.
 */

#if defined(SPH_TOTAL_LAGRANGIAN) && defined(SPH_PART_CONTACT)

/* reads pos; writes contact_keys: (current cell << 32) | slot. */
__kernel void contact_cell_keys(__global const vec *restrict pos,
                                __global ulong *restrict contact_keys, const int n,
                                const real4 grid_origin, const real grid_inv_cell_size,
                                const int4 grid_dims)
{
    const int i = get_global_id(0);
    if (i >= n)
        return;
    const uint cell = cell_of_position(pos[i], grid_origin, grid_inv_cell_size, grid_dims);
    contact_keys[i] = ((ulong)cell << 32) | (ulong)(uint)i;
}

/* reads contact_keys (sorted); writes contact_cell_start, contact_cell_end
 * (cleared to -1). */
__kernel void contact_cell_ranges(__global const ulong *restrict contact_keys,
                                  __global int *restrict contact_cell_start,
                                  __global int *restrict contact_cell_end, const int n)
{
    const int i = get_global_id(0);
    if (i < n)
        mark_cell_range(contact_keys, contact_cell_start, contact_cell_end, i, n);
}

/* A part's bit in a cell's set of parts: parts 0-30 their own, the rest
 * share bit 31 (a block of such a part is never skipped). */
static inline uint part_bit(int part)
{
    return part < 31 ? 1u << part : 1u << 31;
}

/* reads contact_keys (sorted), flags; updates contact_cell_parts (cleared
 * to 0): the set of the parts in each cell. */
__kernel void contact_cell_parts(__global const ulong *restrict contact_keys,
                                 __global const int *restrict flags,
                                 __global int *restrict contact_cell_part_bits, const int n)
{
    const int k = get_global_id(0);
    if (k >= n)
        return;
    const ulong key = contact_keys[k];
    atomic_or(&contact_cell_part_bits[(int)(key >> 32)],
              (int)part_bit(SPH_PART_OF(flags[(int)(key & 0xffffffffu)])));
}

/* Whether no other part than the block's own is in the cells its search
 * reaches: then no lane has a contact and the block's walk is skipped
 * (most blocks: the contact is a face). A block of two parts, or of a
 * part above 30, is never skipped. */
static inline bool contact_block_alone(const struct lane_block *b,
                                       __global const int *restrict flags,
                                       __global const int *restrict contact_cell_part_bits,
                                       const int4 grid_dims, const int reach)
{
    const int first_part = SPH_PART_OF(flags[b->first]);
    for (int l = 1; l < SPH_LANES; ++l)
        if (lane_live(b, l) && SPH_PART_OF(flags[b->first + l]) != first_part)
            return false;
    if (first_part >= 31)
        return false;
    uint others = 0;
    LANE_CELL_ROWS(*b, reach, row, x0, x1)
    for (int cx = x0; cx <= x1; ++cx)
        others |= (uint)contact_cell_part_bits[row + cx];
    END_LANE_CELL_ROWS
    return (others & ~part_bit(first_part)) == 0;
}

/* The box of the live lanes' current cells (the block's reference box is
 * lane_block_setup's). */
static inline void contact_block_box(struct lane_block *b, __global const vec *restrict pos,
                                     const real4 origin, const real inv_cell_size,
                                     const int4 grid_dims)
{
    b->lo = (int4)(INT_MAX);
    b->hi = (int4)(INT_MIN);
    for (int l = 0; l < SPH_LANES; ++l) {
        if (!lane_live(b, l))
            continue;
        const int4 c = cell_coords_of_position(pos[b->first + l], origin, inv_cell_size, grid_dims);
        b->lo = min(b->lo, c);
        b->hi = max(b->hi, c);
    }
}

/* The nearest particle of another part to particle i at xi, through the
 * current cells around xi (for the health records: the reference cells
 * that health_pairs walks hold only the reference neighbours): lowers
 * *nearest2 and sets *nearest (x_j - x_i) where one is closer. The list
 * may be many steps old (host/step.c tl_contact_list_current searches
 * again once a particle may have drifted out of the walk's reach), which
 * still finds every pair closer than the contact's d and a tenth of the
 * reach's margin beyond. */
static inline void contact_nearest_other_part(int i, vec xi, __global const vec *restrict pos,
                                              __global const int *restrict flags,
                                              __global const ulong *restrict contact_keys,
                                              __global const int *restrict contact_cell_start,
                                              __global const int *restrict contact_cell_end,
                                              const real4 origin, const real inv_cell_size,
                                              const int4 grid_dims, real *nearest2, vec *nearest)
{
    struct lane_block box;
    box.lo = box.hi = cell_coords_of_position(xi, origin, inv_cell_size, grid_dims);
    LANE_CELL_WALK_IN(box, k, contact_cell_start, contact_cell_end, SPH_GRID_SPLIT)
    {
        const int j = (int)(contact_keys[k] & 0xffffffffu);
        if (SPH_PART_OF(flags[j]) == SPH_PART_OF(flags[i]))
            continue;
        const vec d = pos[j] - xi;
        const real r2 = dot(d, d);
        if (r2 < *nearest2) {
            *nearest2 = r2;
            *nearest = d;
        }
    }
    END_LANE_CELL_WALK
}

/* What the contact pass holds of its own particles, one lane each. */
struct contact_lanes_i {
    realv x[3], v[3], rho, inv_rho, c, parts;
    realv alpha;         /* SPH_AV_SWITCH: each lane's own alpha */
    real beta_per_alpha; /* SPH_AV_SWITCH: the case's beta / alpha */
};

/* One candidate j of another part: the contact pressure and the touching
 * pair's viscosity, added to acc, de (all of it) and de_viscous (the
 * viscosity's share). */
static inline void
contact_pair(const struct contact_lanes_i *I, int j, real d2, realv face,
             __global const vec *restrict pos, __global const vec *restrict vel,
             __global const real *restrict rho, __global const real *restrict mass,
             __global const real *restrict sound_speed, __global const real *restrict av_alpha,
             __global const int *restrict flags, __constant const struct sph_run_params *run,
             realv acc[3], realv *de, realv *de_viscous)
{
    realv xij[3], r2;
    const maskv touching = lane_pair(I->x, pos[j], d2, xij, &r2) & !SAME_PART(I->parts, j);
    if (!lanes_any(touching))
        return;
    const real h = run->h, inv_h = (real)1 / h, rho_j = rho[j], c_j = sound_speed[j];
    const vec vj = vel[j];
    realv vij[3];
#pragma unroll
    for (int a = 0; a < 3; ++a)
        vij[a] = a < SPH_DIM ? I->v[a] - vec_get(vj, a) : (realv)0;
    const realv vx = vij[0] * xij[0] + vij[1] * xij[1] + vij[2] * xij[2];
    const realv pi_c =
        part_contact_term(I->rho, I->c, I->inv_rho, rho_j, c_j, part_overlap(r2, h, run), face);
    const realv pi_v =
        pair_artificial_viscosity(vx, r2, h, (real)0.5 * (I->c + c_j), (real)2 / (I->rho + rho_j),
                                  I->alpha, I->beta_per_alpha, j, av_alpha, run);
    /* m_j Pi grad W = s x_ij, zero outside `touching` */
    const realv dwdr_r = kernel_dwdr_over_r_q(sqrt(r2) * inv_h, inv_h);
    const realv s_c = SPH_SELECT((realv)0, mass[j] * pi_c * dwdr_r, touching);
    const realv s_v = SPH_SELECT((realv)0, mass[j] * pi_v * dwdr_r, touching);
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a)
        acc[a] -= (s_c + s_v) * xij[a];
    *de += (real)0.5 * (s_c + s_v) * vx;
    *de_viscous += (real)0.5 * s_v * vx;
}

/* Adds the contact of other parts to the accelerations and energy rates
 * tl_momentum wrote. One work-item per lane block (kernels/lanes.cl), the
 * candidates from the current cells around the block's lanes.
 * reads: pos, vel, rho, mass, sound_speed, av_alpha (SPH_AV_SWITCH), flags,
 * contact_keys, contact_cell_start, contact_cell_end, contact_cell_part_bits;
 * updates: acceleration, energy_rate, viscous_heating. */
__kernel void
tl_part_contact(__global const vec *restrict pos, __global const vec *restrict vel,
                __global const real *restrict rho, __global const real *restrict mass,
                __global const real *restrict sound_speed, __global const real *restrict av_alpha,
                __global const int *restrict flags, __global const ulong *restrict sort_keys,
                const int4 grid_dims, __global const ulong *restrict contact_keys,
                __global const int *restrict contact_cell_start,
                __global const int *restrict contact_cell_end,
                __global const int *restrict contact_cell_part_bits, const real4 grid_origin,
                const real grid_inv_cell_size, __constant const struct sph_run_params *run,
                __global vec *restrict acceleration, __global real *restrict energy_rate,
                __global real *restrict viscous_heating, const int n)
{
    struct lane_block b;
    if (!lane_block_setup(&b, flags, sort_keys, grid_dims, n))
        return;
    contact_block_box(&b, pos, grid_origin, grid_inv_cell_size, grid_dims);
    const int reach = SPH_GRID_SPLIT; /* cells of the support: d is within */
    if (contact_block_alone(&b, flags, contact_cell_part_bits, grid_dims, reach))
        return;
    struct contact_lanes_i I;
    lane_positions(pos, &b, n, I.x);
    gather_vec(vel, &b, n, I.v);
    I.rho = SPH_SELECT((realv)1, gather_real(rho, &b, n), b.live);
    I.inv_rho = (real)1 / I.rho;
    I.c = gather_real(sound_speed, &b, n);
    I.parts = lane_parts(flags, &b, n);
    switch_lanes(av_alpha, &b, n, run, &I.alpha, &I.beta_per_alpha);
    const real d = run->h * run->av_eta_crit; /* the lattice spacing */
    const realv face = part_contact_face(run);
    realv acc[3] = {(realv)0, (realv)0, (realv)0}, de = (realv)0, de_viscous = (realv)0;
    LANE_CELL_WALK_IN(b, k, contact_cell_start, contact_cell_end, reach)
    {
        contact_pair(&I, (int)(contact_keys[k] & 0xffffffffu), d * d, face, pos, vel, rho, mass,
                     sound_speed, av_alpha, flags, run, acc, &de, &de_viscous);
    }
    END_LANE_CELL_WALK
    for (int l = 0; l < SPH_LANES; ++l) {
        if (!lane_live(&b, l))
            continue;
        const int i = b.first + l;
        acceleration[i] += vec_make(lane_of(acc[0], l), lane_of(acc[1], l), lane_of(acc[2], l));
        energy_rate[i] += lane_of(de, l);
        viscous_heating[i] += lane_of(de_viscous, l);
    }
}

#endif
