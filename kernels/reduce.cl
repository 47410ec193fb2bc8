/*
 * Per-step reduction: next time step, health checks, energies, probe.
 * Each work-group writes SPH_RED_SLOTS partials; the host combines them in
 * double (sums add, maxima take the max, the bad index takes the min).
 *
 * Velocities are the half-step ones the positions moved with, so the load
 * power times dt is the exact work of the step's load.
 * reads: pos, displacement, vel_half, xsph_velocity, mass, energy, rho,
 * sound_speed, flags, id, wall_force (with walls), viscous_heating,
 * hourglass_power (total Lagrangian); writes: partials.
 */
static inline bool slot_is_max(int slot)
{
    return slot == SPH_RED_MAX_SIGNAL || slot == SPH_RED_MAX_SPEED || slot == SPH_RED_MAX_DRIFT;
}

__kernel __attribute__((reqd_work_group_size(REDUCE_WG, 1, 1))) void
reduce_step(__global const vec *restrict pos, __global const vec *restrict displacement,
            __global const vec *restrict vel_half, __global const vec *restrict xsph_velocity,
            __global const real *restrict mass, __global const real *restrict energy,
            __global const real *restrict rho, __global const real *restrict sound_speed,
            __global const int *restrict flags, __global const int *restrict id,
            __global const vec *restrict wall_force, const int wall_count,
            __global const real *restrict viscous_heating,
            __global const real *restrict hourglass_power,
            __constant const struct sph_run_params *run, const real4 load_force,
            __global real *restrict partials, const int n)
{
    __local real acc[REDUCE_WG][SPH_RED_SLOTS];
    real mine[SPH_RED_SLOTS];
    for (int k = 0; k < SPH_RED_SLOTS; ++k)
        mine[k] = 0;
    mine[SPH_RED_BAD_INDEX] = (real)INT_MAX;
    const vec f = vec_make(load_force.x, load_force.y, load_force.z);
    FOR_GROUP_BLOCK (i, n) {
        const int flag = flags[i];
        if (flag & SPH_FLAG_GHOST)
            continue;
        const vec v = vel_half[i], x = pos[i];
        const real speed = length(v);
        mine[SPH_RED_MAX_SIGNAL] = fmax(mine[SPH_RED_MAX_SIGNAL], sound_speed[i] + speed);
        mine[SPH_RED_MAX_SPEED] = fmax(mine[SPH_RED_MAX_SPEED], speed);
        mine[SPH_RED_MAX_DRIFT] = fmax(mine[SPH_RED_MAX_DRIFT], length(v + xsph_velocity[i]));
        const bool bad = isnan(speed) || isinf(speed) || !(speed <= run->velocity_limit) ||
                         isnan(dot(x, x)) || isinf(dot(x, x)) || isnan(rho[i]) || isnan(energy[i]);
        if (bad)
            mine[SPH_RED_BAD_INDEX] = fmin(mine[SPH_RED_BAD_INDEX], (real)id[i]);
        if (flag & SPH_FLAG_LOADED)
            mine[SPH_RED_LOAD_POWER] += dot(f, v + xsph_velocity[i]); /* as the drift moves it */
        mine[SPH_RED_KINETIC] += (real)0.5 * mass[i] * dot(v, v);
        mine[SPH_RED_INTERNAL] += mass[i] * energy[i];
        mine[SPH_RED_VISCOUS_POWER] += mass[i] * viscous_heating[i];
#ifdef SPH_TOTAL_LAGRANGIAN /* hourglass_power exists only then */
        mine[SPH_RED_HOURGLASS_POWER] += mass[i] * hourglass_power[i];
#else
        (void)hourglass_power;
#endif
        if (flag & SPH_FLAG_PROBE) {
            const vec u = displacement[i];
            mine[SPH_RED_PROBE_DISP_X] += u.x;
            mine[SPH_RED_PROBE_DISP_Y] += u.y;
#if SPH_DIM == 3
            mine[SPH_RED_PROBE_DISP_Z] += u.z;
#endif
            mine[SPH_RED_PROBE_COUNT] += 1;
        }
        if (wall_count > 0) { /* wall_force is allocated only then */
            const vec fw = wall_force[i];
            mine[SPH_RED_WALL_POWER] += dot(fw, v + xsph_velocity[i]); /* as the drift moves it */
            mine[SPH_RED_WALL_FORCE_X] += fw.x;
            mine[SPH_RED_WALL_FORCE_Y] += fw.y;
#if SPH_DIM == 3
            mine[SPH_RED_WALL_FORCE_Z] += fw.z;
#endif
        }
        mine[SPH_RED_MOMENTUM_X] += mass[i] * v.x;
        mine[SPH_RED_MOMENTUM_Y] += mass[i] * v.y;
#if SPH_DIM == 3
        mine[SPH_RED_MOMENTUM_Z] += mass[i] * v.z;
#endif
    }
    uchar op[SPH_RED_SLOTS];
    for (int k = 0; k < SPH_RED_SLOTS; ++k)
        op[k] = slot_is_max(k) ? REDUCE_MAX : k == SPH_RED_BAD_INDEX ? REDUCE_MIN : REDUCE_SUM;
    work_group_reduce(&acc[0][0], mine, op, SPH_RED_SLOTS, partials);
}

/* Neighbours of each particle, for the integrity measure (particles that
 * lost more than a third of their initial neighbours). Updated Lagrangian:
 * particles within the support. Total Lagrangian, where the interacting
 * pairs never change: reference neighbours (within the support at t = 0)
 * whose separation has not more than doubled, so that only a tear, not the
 * finite strain of a whole body, counts as a loss.
 * reads pos, pos0; writes neighbour_count. */
__kernel void health_neighbour_count(__global const vec *restrict pos,
                                     __global const vec *restrict pos0,
                                     __global const int *restrict flags, GRID_ARGS,
                                     __constant const struct sph_run_params *run,
                                     __global int *restrict neighbour_count, const int n)
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
#ifdef SPH_TOTAL_LAGRANGIAN
        const vec d0 = pos0[i] - pos0[j];
        const real r02 = dot(d0, d0);
        c += (j != i && r02 < support2 && dot(d, d) <= (real)4 * r02) ? 1 : 0;
#else
        (void)pos0;
        c += (j != i && dot(d, d) < support2) ? 1 : 0;
#endif
    }
    END_FOR_EACH_NEIGHBOUR
    neighbour_count[i] = c;
}

/* Health indicators (issue: stability where SPH fails), reduced per
 * work-group like reduce_step: the smallest pair distance; the particles
 * with a neighbour closer than dx / 2 (clumping, the end state of the
 * tensile and pairing instabilities); the particles in Swegle's unstable
 * regime, W''(r) sigma_n > 0 for the nearest neighbour at distance r with
 * sigma_n = n . sigma . n the normal stress along that pair (Swegle, Hicks &
 * Attaway 1995; thesis eq. 3.1: tension where the kernel's second
 * derivative is positive); neighbour counts within the support. Ghosts and
 * fixed particles are not counted. W'' is a central difference of dW/dr
 * over 1e-3 h, enough for its sign.
 * reads pos, pressure, deviatoric_stress, flags; writes health partials. */
static inline real kernel_d2wdr2(real r, real h)
{
    const real step = (real)1e-3 * h;
    return (kernel_dwdr(r + step, h) - kernel_dwdr(fmax(r - step, (real)0), h)) /
           (r + step - fmax(r - step, (real)0));
}

static inline bool health_slot_is_min(int slot)
{
    return slot == SPH_HEALTH_MIN_DISTANCE || slot == SPH_HEALTH_NEIGHBOURS_MIN;
}

__kernel __attribute__((reqd_work_group_size(REDUCE_WG, 1, 1))) void
health_indicators(__global const vec *restrict pos, __global const real *restrict pressure,
                  __global const symt *restrict deviatoric_stress,
                  __global const int *restrict flags, GRID_ARGS,
                  __constant const struct sph_run_params *run, const real dx,
                  __global real *restrict partials, const int n)
{
    __local real acc[REDUCE_WG][SPH_HEALTH_SLOTS];
    real mine[SPH_HEALTH_SLOTS];
    for (int k = 0; k < SPH_HEALTH_SLOTS; ++k)
        mine[k] = health_slot_is_min(k) ? (real)INFINITY : (real)0;
    const real q2 = (run->support / run->h) * (run->support / run->h);
    FOR_GROUP_BLOCK (i, n) {
        if (flags[i] & (SPH_FLAG_GHOST | SPH_FLAG_FIXED))
            continue;
        const vec xi = pos[i];
        /* distances in units of the particle's own spacing over dx */
        const real scale_i = spacing_scale(flags[i]);
        real nearest2 = INFINITY;
        vec nearest = VEC_ZERO;
        int count = 0;
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
            }
        }
        END_FOR_EACH_NEIGHBOUR
        mine[SPH_HEALTH_PARTICLES] += 1;
        mine[SPH_HEALTH_NEIGHBOURS_MIN] = fmin(mine[SPH_HEALTH_NEIGHBOURS_MIN], (real)count);
        mine[SPH_HEALTH_NEIGHBOURS_MAX] = fmax(mine[SPH_HEALTH_NEIGHBOURS_MAX], (real)count);
        mine[SPH_HEALTH_NEIGHBOURS_SUM] += (real)count;
        if (count == 0)
            continue;
        const real r = sqrt(nearest2) / scale_i;
        mine[SPH_HEALTH_MIN_DISTANCE] = fmin(mine[SPH_HEALTH_MIN_DISTANCE], r);
        /* failed material (a fluid without tension: no tensile
         * instability) compacts against a projectile's contact; clumping
         * counts intact material only */
        if (r < (real)0.5 * dx && !(flags[i] & SPH_FLAG_DAMAGED))
            mine[SPH_HEALTH_CLUMPED] += 1;
        real sigma[3][3], normal[3];
        total_stress(pressure[i], deviatoric_stress[i], sigma);
#pragma unroll
        for (int a = 0; a < 3; ++a)
            normal[a] = vec_get(nearest, a) / (r * scale_i);
        real sigma_n = 0;
#pragma unroll
        for (int a = 0; a < SPH_DIM; ++a)
#pragma unroll
            for (int b = 0; b < SPH_DIM; ++b)
                sigma_n += normal[a] * sigma[a][b] * normal[b];
        if (kernel_d2wdr2(r, run->h) * sigma_n > 0) /* in units of its own spacing */
            mine[SPH_HEALTH_SWEGLE] += 1;
    }
    uchar op[SPH_HEALTH_SLOTS];
    for (int k = 0; k < SPH_HEALTH_SLOTS; ++k)
        op[k] = health_slot_is_min(k)            ? REDUCE_MIN
                : k == SPH_HEALTH_NEIGHBOURS_MAX ? REDUCE_MAX
                                                 : REDUCE_SUM;
    work_group_reduce(&acc[0][0], mine, op, SPH_HEALTH_SLOTS, partials);
}
