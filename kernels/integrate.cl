/*
 * Leap-frog in kick-drift form (thesis 3.3: predictor-corrector leap-frog),
 * one force evaluation per step. Per step:
 *   pass 2 at state n           -> a^n (uses the predicted velocity v~n)
 *   integrate_kick              v^(n+1/2) = v^(n-1/2) + (dt_prev + dt)/2 a^n,
 *                               predicted v~(n+1) = v^(n+1/2) + dt/2 a^n
 *   pass 1 at x^n, v^(n+1/2)    -> velocity gradient of the half-step velocity
 *   the material update         rho, e, S from n to n+1 (central in time),
 *                               particle by particle at the end of pass 1
 *   integrate_drift             u^(n+1) = u^n + dt (v^(n+1/2) + v_xsph),
 *                               x^(n+1) = x^0 + u^(n+1)
 * Stress and velocity are staggered as in the central-difference scheme of
 * explicit solid codes, which is stable for dt below the CFL limit; the
 * velocity with the lagged acceleration serves only the terms (artificial
 * viscosity, XSPH, energy) that need it at integer time.
 * a^n includes the external load on loaded particles, the rigid walls'
 * contact force and the optional velocity damping (-c v) of quasi-static
 * runs; fixed particles stay still and symmetry-plane ghosts are copies
 * (kernels/ghost.cl), never integrated.
 */

/* Rigid walls as a stiff penalty (a contact spring per particle): a particle
 * whose centre comes closer than gap = dx/2 to the plane (its half-spacing,
 * so the material's face lies on the plane) is pushed back with
 * f = k (gap - d) n, k = m c^2 / dx^2: the spring's frequency c/dx keeps the
 * explicit step stable at CFL <= 1 and the penetration small (v dx / c at
 * speed v, sigma dx / (rho c^2) under a stress sigma). The force is
 * conservative, so impact energy goes into the spring and comes back
 * instead of being lost as with a velocity reset; its work is counted
 * (kernels/reduce.cl) like the load's. Coulomb friction opposes the
 * tangential velocity with at most friction * |f_n|, and never more than
 * stops the particle in one step. Returns the force over the mass. */
static inline vec wall_acceleration(vec x, vec v, real sound_speed, real dx, real dt,
                                    __constant const struct sph_wall *walls, int wall_count)
{
    vec a = VEC_ZERO;
    for (int w = 0; w < wall_count; ++w) {
        __constant const struct sph_wall *wall = &walls[w];
        const vec normal = vec_make(wall->normal_x, wall->normal_y, wall->normal_z);
        const real depth =
            wall->gap - dot(x - vec_make(wall->point_x, wall->point_y, wall->point_z), normal);
        if (depth <= 0)
            continue;
        const real a_n = sound_speed * sound_speed * depth / (dx * dx);
        a += a_n * normal;
        const vec tangential = v - dot(v, normal) * normal;
        const real speed_t = length(tangential);
        if (wall->friction > 0 && speed_t > 0)
            a -= fmin(wall->friction * a_n, speed_t / dt) / speed_t * tangential;
    }
    return a;
}

/* reads acceleration, mass, flags, pos, material; updates vel_half; writes
 * vel, wall_force (on the particle, N or N/m in 2-D). */
__kernel void integrate_kick(__global vec *restrict vel, __global vec *restrict vel_half,
                             __global const vec *restrict acceleration,
                             __global const real *restrict mass, __global const int *restrict flags,
                             __global const vec *restrict pos,
                             __global const int *restrict material,
                             __constant const struct sph_material *materials,
                             __constant const struct sph_run_params *run,
                             __constant const struct sph_wall *walls, const int wall_count,
                             const real dx, const real dt, const real dt_prev,
                             const real4 load_force, __global vec *restrict wall_force, const int n)
{
    const int i = get_global_id(0);
    if (i >= n)
        return;
    const int flag = flags[i];
    if (wall_count > 0) /* wall_force is allocated only then */
        wall_force[i] = VEC_ZERO;
    if (flag & SPH_FLAG_GHOST)
        return;
    if (flag & SPH_FLAG_FIXED) {
        vel[i] = VEC_ZERO;
        vel_half[i] = VEC_ZERO;
        return;
    }
    vec a = acceleration[i] - run->damping * vel[i];
    if (flag & SPH_FLAG_LOADED)
        a += vec_make(load_force.x, load_force.y, load_force.z) / mass[i];
    if (wall_count > 0) {
        const vec a_wall = wall_acceleration(
            pos[i], vel_half[i], materials[material[i]].sound_speed, dx, dt, walls, wall_count);
        a += a_wall;
        wall_force[i] = mass[i] * a_wall;
    }
    const vec v_half = vel_half[i] + ((real)0.5 * (dt_prev + dt)) * a;
    vel_half[i] = v_half;
    vel[i] = v_half + ((real)0.5 * dt) * a;
}

/* The displacement, not the position, is integrated: in single precision a
 * position of 0.1 m has an ulp of 7e-9 m, more than a slow particle moves in
 * a step, while the displacement keeps its increments to N_steps * 2^-24.
 * A particle that would come within a quarter of its spacing of a symmetry
 * plane (side[a] = +1 or -1 on the plane's axis a, 0 elsewhere; the gap is
 * plane_gap times its level's spacing scale; 0 in the total Lagrangian
 * form, host/step.c) moving towards it is reflected
 * back off that gap and its normal velocity reversed, as its mirror image
 * would meet it: material swept onto the axis of an axisymmetric case (a
 * cavity closing) must not pass it, and a particle may not sit on the plane
 * within a few nanometres of its own image, where the kernel's gradient,
 * and so the pair's repulsion, vanishes while the continuity equation
 * still compresses it (the 3-D SEBS quarter at d/dx 10 went unstable so at
 * 305 ns: docs/validation_penetration.md). A lattice starts half a spacing
 * from the plane, so the gap touches only material driven onto it.
 * The drift also writes what the material update (run inside pass 1 in
 * the updated Lagrangian form) must leave to after every particle's pass 1:
 * the new density rho0 + density_change, and the damage flag.
 * With SPH_TENSOR_SMOOTHING it carries the kernel's ellipsoid with the
 * material too (pass 1's L over the step, tensor_smoothing.cl).
 * reads xsph_velocity, pos0, density_change, plastic_strain, material,
 * velocity_gradient (SPH_TENSOR_SMOOTHING); updates vel_half,
 * displacement, flags, smoothing_metric (SPH_TENSOR_SMOOTHING); writes pos,
 * rho, smoothing_reach (SPH_TENSOR_SMOOTHING). */
__kernel void
integrate_drift(__global vec *restrict pos, __global vec *restrict displacement,
                __global const vec *restrict pos0, __global vec *restrict vel_half,
                __global const vec *restrict xsph_velocity, __global int *restrict flags,
                __global real *restrict rho, __global const real *restrict density_change,
                __global const real *restrict plastic_strain, __global const int *restrict material,
                __global const fullt *restrict velocity_gradient,
                __global symt *restrict smoothing_metric, __global real *restrict smoothing_reach,
                __constant const struct sph_material *materials, const real dt, const real4 plane,
                const real4 side, const real plane_gap, const int n)
{
    const int i = get_global_id(0);
    if (i >= n || (flags[i] & SPH_FLAG_GHOST))
        return;
    __constant const struct sph_material *m = &materials[material[i]];
    rho[i] = m->density + density_change[i];
    if (particle_failed(m, plastic_strain[i], density_change[i]))
        flags[i] |= SPH_FLAG_DAMAGED;
    if (flags[i] & SPH_FLAG_FIXED)
        return;
#ifdef SPH_TENSOR_SMOOTHING
    real metric[3][3], grad_v[3][3];
    symt_load(smoothing_metric[i], metric);
    fullt_load(velocity_gradient[i], grad_v);
    /* carried with the material: tensor_smoothing.cl */
    smoothing_reach[i] = metric_advance(metric, grad_v, dt);
    smoothing_metric[i] = symt_store(metric);
#else
    (void)velocity_gradient;
    (void)smoothing_metric;
    (void)smoothing_reach;
#endif
    const vec u = displacement[i] + dt * (vel_half[i] + xsph_velocity[i]);
    const vec x0 = pos0[i];
    real x[3] = {vec_get(x0 + u, 0), vec_get(x0 + u, 1), vec_get(x0 + u, 2)};
    real v[3] = {vec_get(vel_half[i], 0), vec_get(vel_half[i], 1), vec_get(vel_half[i], 2)};
    const real planes[3] = {plane.x, plane.y, plane.z}, sides[3] = {side.x, side.y, side.z};
    const real gap = plane_gap * spacing_scale(flags[i]);
    bool reflected = false;
    for (int a = 0; a < SPH_DIM; ++a) {
        const real d = (x[a] - planes[a]) * sides[a], towards = v[a] * sides[a];
        if (sides[a] != 0 && (d < 0 || (d < gap && towards < 0))) {
            x[a] = (real)2 * (planes[a] + sides[a] * gap) - x[a];
            v[a] = towards < 0 ? -v[a] : v[a];
            reflected = true;
        }
    }
    if (reflected) {
        const vec moved = vec_make(x[0], x[1], x[2]);
        vel_half[i] = vec_make(v[0], v[1], v[2]);
        displacement[i] = moved - x0;
        pos[i] = moved;
        return;
    }
    displacement[i] = u;
    pos[i] = x0 + u;
}
