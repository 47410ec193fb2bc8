/*
 * Leap-frog in kick-drift form (thesis 3.3: predictor-corrector leap-frog),
 * one force evaluation per step. Per step:
 *   pass 2 at state n           -> a^n (uses the predicted velocity v~n)
 *   integrate_kick              v^(n+1/2) = v^(n-1/2) + (dt_prev + dt)/2 a^n,
 *                               predicted v~(n+1) = v^(n+1/2) + dt/2 a^n
 *   pass 1 at x^n, v^(n+1/2)    -> velocity gradient of the half-step velocity
 *   material_update             rho, e, S from n to n+1 (central in time)
 *   integrate_drift             u^(n+1) = u^n + dt (v^(n+1/2) + v_xsph),
 *                               x^(n+1) = x^0 + u^(n+1)
 * Stress and velocity are staggered as in the central-difference scheme of
 * explicit solid codes, which is stable for dt below the CFL limit; the
 * velocity with the lagged acceleration serves only the terms (artificial
 * viscosity, XSPH, energy) that need it at integer time.
 * a^n includes the external load on loaded particles and the optional
 * velocity damping (-c v) of quasi-static runs; fixed particles stay still.
 */

/* reads acceleration, mass, flags; updates vel_half; writes vel. */
__kernel void integrate_kick(__global vec *restrict vel, __global vec *restrict vel_half,
                             __global const vec *restrict acceleration,
                             __global const real *restrict mass, __global const int *restrict flags,
                             __constant const struct sph_run_params *run, const real dt,
                             const real dt_prev, const real4 load_force, const int n)
{
    const int i = get_global_id(0);
    if (i >= n)
        return;
    const int flag = flags[i];
    if (flag & SPH_FLAG_FIXED) {
        vel[i] = VEC_ZERO;
        vel_half[i] = VEC_ZERO;
        return;
    }
    vec a = acceleration[i] - run->damping * vel[i];
    if (flag & SPH_FLAG_LOADED)
        a += vec_make(load_force.x, load_force.y, load_force.z) / mass[i];
    const vec v_half = vel_half[i] + ((real)0.5 * (dt_prev + dt)) * a;
    vel_half[i] = v_half;
    vel[i] = v_half + ((real)0.5 * dt) * a;
}

/* The displacement, not the position, is integrated: in single precision a
 * position of 0.1 m has an ulp of 7e-9 m, more than a slow particle moves in
 * a step, while the displacement keeps its increments to N_steps * 2^-24.
 * reads vel_half, xsph_velocity, flags, pos0; updates displacement; writes pos. */
__kernel void integrate_drift(__global vec *restrict pos, __global vec *restrict displacement,
                              __global const vec *restrict pos0,
                              __global const vec *restrict vel_half,
                              __global const vec *restrict xsph_velocity,
                              __global const int *restrict flags, const real dt, const int n)
{
    const int i = get_global_id(0);
    if (i >= n || (flags[i] & SPH_FLAG_FIXED))
        return;
    const vec u = displacement[i] + dt * (vel_half[i] + xsph_velocity[i]);
    displacement[i] = u;
    pos[i] = pos0[i] + u;
}
