/*
 * Per-step reduction: next time step, energies, probe (the health checks
 * are in health.cl).
 * Each work-group writes SPH_RED_SLOTS partials; the host combines them in
 * double (sums add, maxima take the max, the bad index takes the min).
 *
 * Velocities are the half-step ones the positions moved with, so the load
 * power times dt is the exact work of the step's load.
 * reads: pos, displacement, vel_half, xsph_velocity, mass, energy, rho,
 * sound_speed, flags, id, wall_force (with walls), viscous_heating,
 * hourglass_power and reference_offset (total Lagrangian: the probe's
 * displacement from the initial position), deformation_gradient
 * (numerics.reference_update: the largest Green strain), smoothing_metric and
 * smoothing_reach (numerics.smoothing tensor: the time step's signal over
 * the shortest axis); writes: partials.
 */
static inline bool slot_is_max(int slot)
{
    return slot == SPH_RED_MAX_SIGNAL || slot == SPH_RED_MAX_SPEED || slot == SPH_RED_MAX_DRIFT ||
           slot == SPH_RED_MAX_DISTORTION;
}

#ifdef SPH_REFERENCE_UPDATE
/* |E|, the Frobenius norm of the Green strain E = (F^T F - I) / 2 against
 * the reference: zero for a rigid motion, the measure numerics.
 * reference_update compares with */
static inline real green_strain_norm(fullt packed)
{
    real f[3][3];
    fullt_load(packed, f);
    real sum = 0;
    for (int a = 0; a < SPH_DIM; ++a)
        for (int b = 0; b < SPH_DIM; ++b) {
            real e = a == b ? (real)-1 : (real)0;
            for (int k = 0; k < SPH_DIM; ++k)
                e += f[k][a] * f[k][b];
            sum += e * e;
        }
    return (real)0.5 * sqrt(sum);
}
#endif

__kernel __attribute__((reqd_work_group_size(REDUCE_WG, 1, 1))) void reduce_step(
    __global const vec *restrict pos, __global const vec *restrict displacement,
    __global const vec *restrict vel_half, __global const vec *restrict xsph_velocity,
    __global const real *restrict mass, __global const real *restrict energy,
    __global const real *restrict rho, __global const real *restrict sound_speed,
    __global const int *restrict flags, __global const int *restrict id,
    __global const vec *restrict wall_force, const int wall_count,
    __global const real *restrict viscous_heating, __global const real *restrict hourglass_power,
    __global const fullt *restrict deformation_gradient,
    __global const vec *restrict reference_offset, __global const symt *restrict smoothing_metric,
    __global const real *restrict smoothing_reach, __constant const struct sph_run_params *run,
    const real4 load_force, __global real *restrict partials, const int n)
{
#ifndef SPH_TOTAL_LAGRANGIAN
    (void)reference_offset;
#endif
#ifndef SPH_TENSOR_SMOOTHING
    (void)smoothing_metric;
    (void)smoothing_reach;
#endif
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
#ifdef SPH_TENSOR_SMOOTHING
        /* the time step follows the shortest axis: the signal crosses it in
         * dt (tensor_smoothing.cl) */
        real metric[3][3];
        symt_load(smoothing_metric[i], metric);
        const real signal =
            (sound_speed[i] + speed) * metric_shortest_axis_factor(metric, smoothing_reach[i]);
#else
        const real signal = sound_speed[i] + speed;
#endif
        mine[SPH_RED_MAX_SIGNAL] = fmax(mine[SPH_RED_MAX_SIGNAL], signal);
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
#ifdef SPH_REFERENCE_UPDATE /* F read only where an update may follow (64 B a particle in 3-D) */
        mine[SPH_RED_MAX_DISTORTION] =
            fmax(mine[SPH_RED_MAX_DISTORTION], green_strain_norm(deformation_gradient[i]));
#else
        (void)deformation_gradient;
#endif
        if (flag & SPH_FLAG_PROBE) {
#ifdef SPH_TOTAL_LAGRANGIAN /* from the initial position, not the reference */
            const vec u = displacement[i] + reference_offset[i];
#else
            const vec u = displacement[i];
#endif
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
