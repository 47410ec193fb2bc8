/*
 * The rigid projectile: a sphere with one position, velocity and mass,
 * pushed by the target particles it touches (issue: micro-particle
 * penetration). The target sees it as a moving boundary through a stiff
 * penalty on the analytic surface: a particle whose centre comes closer
 * than R - dx_i/2 to the sphere's centre is pushed out along the radius
 * with f = m k^2 (R - dx_i/2 - d) / dx_i^2, and the sphere takes the opposite force, so
 * the pair conserves momentum exactly and the spring stores (and gives
 * back) its energy. The layer in contact is held with its centres half a
 * spacing inside the sphere (d >= R - dx_i/2), not half a spacing outside
 * it as at the plane walls (integrate.cl): the layer rides on the sphere,
 * and the gel flows around the layer's outer face, half a spacing beyond
 * its centres. Held at R + a, the body the gel flows around is a sphere of
 * radius R + a + dx/2, (1 + (a + dx/2)/R)^2 larger in area: an error
 * proportional to dx (at a plane wall the same offset moves the face, not
 * the force). Measured with the sphere held at 600 m/s in gelatin
 * (docs/shock_capturing.md, "Steady resistance"; switch viscosity): with
 * the centres on R the resistance is 92.4 / 77.0 / 71.0 / 68.6 MPa at d/dx
 * 8 / 16 / 32 / 64 (Richardson limit 66.9 MPa); with them at R - dx/2,
 * 71.3 / 66.4 / 66.9 MPa at d/dx 8 / 16 / 32. -DSPH_CONTACT_INSET=0 (in
 * SPH_BUILD_OPTIONS) gives the contact on R for such comparisons. k is the target's
 * longitudinal wave speed plus the impact speed: the spring's frequency
 * k / dx_i stays below the step's stability limit (dt = cfl h / (c + |v|))
 * while the overlap at impact stays under v dx / k < dx / 2 (a centre never
 * comes nearer the sphere's than R - dx, so the normal stays defined for
 * d / dx >= 4). A damper in
 * parallel, critical for the spring (2 k / dx_i per unit mass) and acting
 * only while the particle closes on the sphere, takes the energy of each
 * particle-sphere impact: without it the first layer of the surface,
 * struck at v0 and backed by nothing, bounces off the spring at up to 2 v0
 * and sets the time step for the rest of the run. The normal force never
 * pulls (no adhesion); the dampers' work is counted in the energy
 * balance.
 * Why a penalty and not particles moved rigidly: docs/validation_penetration.md.
 *
 * Per step (host/step.c): projectile_contact after pass 2 adds the contact
 * acceleration and writes per-group force partials; projectile_advance sums
 * them and moves the sphere with the particles' leap-frog. At history rows
 * projectile_cavity measures the cavity around the track.
 */

/* spacings inside the sphere the contact layer is held at (above) */
#ifndef SPH_CONTACT_INSET
#define SPH_CONTACT_INSET 0.5
#endif

/* A particle's contact force m a, into its work-item's partial sums. */
static inline void contact_add_force(real mine[SPH_CONTACT_SLOTS], real m, vec a)
{
    mine[SPH_CONTACT_FX] += m * a.x;
    mine[SPH_CONTACT_FX + 1] += m * a.y;
#if SPH_DIM == 3
    mine[SPH_CONTACT_FX + 2] += m * a.z;
#endif
}

/* reads pos, vel, vel_half, mass, flags, state (and with SPH_SPHERE_WALL,
 * projectile.boundary: integral, deviatoric_stress, pressure, rho, csph
 * for the wall's force, sphere_wall.cl); updates acceleration; writes
 * contact partials. With no_slip (projectile.contact) the contact also
 * sticks the particle to the sphere's surface tangentially; the sphere
 * does not rotate (it has no angular velocity), so the stick's torque is
 * not integrated: exact for a shot along a symmetry axis, where the
 * torques cancel. */
__kernel __attribute__((reqd_work_group_size(REDUCE_WG, 1, 1))) void projectile_contact(
    __global const vec *restrict pos, __global const vec *restrict vel,
    __global const vec *restrict vel_half, __global const real *restrict mass,
    __global const int *restrict flags, __global vec *restrict acceleration,
    __global const real *restrict state, __constant const struct sph_run_params *run,
    const real stiffness_speed, const real dx, const real dt, const real dt_prev, const int no_slip,
#ifdef SPH_SPHERE_WALL
    __global const symt *restrict deviatoric_stress, __global const real *restrict pressure,
    __global const real *restrict rho, __global const symt *restrict csph,
#endif
    __global real *restrict partials, const int n)
{
    __local real acc[REDUCE_WG][SPH_CONTACT_SLOTS];
    real mine[SPH_CONTACT_SLOTS];
    for (int k = 0; k < SPH_CONTACT_SLOTS; ++k)
        mine[k] = 0;
    const vec centre = vec_make(state[SPH_PROJ_X], state[SPH_PROJ_X + 1], state[SPH_PROJ_X + 2]);
    const vec sphere_velocity =
        vec_make(state[SPH_PROJ_V], state[SPH_PROJ_V + 1], state[SPH_PROJ_V + 2]);
    const real radius = run->sphere_radius;
    const real k2 = stiffness_speed * stiffness_speed;
    const real kick = (real)0.5 * (dt_prev + dt); /* the particles' kick (integrate.cl) */
    FOR_GROUP_BLOCK (i, n) {
        const int flag = flags[i];
        if (flag & (SPH_FLAG_GHOST | SPH_FLAG_FIXED))
            continue;
        const real dx_i = dx * spacing_scale(flag);
#ifdef SPH_SPHERE_WALL
        {
            real defect;
            const vec a_wall = sphere_wall_acceleration(i, pos, vel, flags, deviatoric_stress,
                                                        pressure, rho, csph, state, run, &defect);
            acceleration[i] += a_wall;
            contact_add_force(mine, mass[i], a_wall);
            mine[SPH_CONTACT_DISSIPATION] -= mass[i] * defect;
        }
#endif
        const vec d = pos[i] - centre;
        const real distance = length(d);
        const real depth = radius - (real)SPH_CONTACT_INSET * dx_i - distance;
        if (depth <= 0 || distance <= 0)
            continue;
        const vec normal = d / distance;
        /* positive while the particle closes on the sphere */
        const real approach = dot(sphere_velocity - vel[i], normal);
        const real spring = k2 * depth / (dx_i * dx_i);
        /* the damper never more than stops the approach within the kick
         * (an explicit damper this stiff would reverse it and feed energy
         * in) */
        const real damper =
            approach > 0 ? fmin((real)2 * stiffness_speed / dx_i * approach, approach / kick) : 0;
        const real a_n = spring + damper;
        vec a = a_n * normal, a_stick = VEC_ZERO;
        if (no_slip) {
            /* the tangential velocity relative to the sphere, as the kick
             * would leave it, removed within the kick (an impulsive stick:
             * the discrete no-slip condition at the contact layer, whose
             * shear the gel's own viscous stress then carries outwards) */
            const vec relative = vel_half[i] + kick * (acceleration[i] + a) - sphere_velocity;
            a_stick = -(relative - dot(relative, normal) * normal) / kick;
            a += a_stick;
        }
        acceleration[i] += a;
        const real m = mass[i];
        contact_add_force(mine, m, a);
        mine[SPH_CONTACT_ENERGY] += (real)0.5 * m * spring * depth;
        mine[SPH_CONTACT_COUNT] += 1;
        /* the damper's work over this step: the particle drifts with
         * v^(n+1/2) = v^(n-1/2) + (dt_prev + dt)/2 a (integrate.cl, a now
         * complete), the sphere with its velocity (it changes by a
         * negligible fraction per step) */
        const vec v_next = vel_half[i] + kick * acceleration[i];
        mine[SPH_CONTACT_DISSIPATION] += m * (a_n - spring) * dot(sphere_velocity - v_next, normal);
        /* ... and the stick's, on the relative velocity at the middle of the
         * kick: zero for a particle already stuck, whose stick only
         * balances the other tangential forces */
        mine[SPH_CONTACT_DISSIPATION] +=
            m * dot(a_stick, sphere_velocity - (real)0.5 * (vel_half[i] + v_next));
    }
    uchar op[SPH_CONTACT_SLOTS];
    for (int k = 0; k < SPH_CONTACT_SLOTS; ++k)
        op[k] = REDUCE_SUM;
    work_group_reduce(&acc[0][0], mine, op, SPH_CONTACT_SLOTS, partials);
}

/* One work-item: the force on the sphere is minus the sum of the contact
 * forces on the particles, times `scale` (2 pi for an axisymmetric ring
 * mass per radian, 2 per symmetry plane, the thickness in plane strain),
 * with the components normal to symmetry planes zeroed (`mask`: they cancel
 * against the mirror images). Then the leap-frog of the particles:
 * v^(n+1/2) = v^(n-1/2) + (dt_prev + dt)/2 F/M, x^(n+1) = x^n + dt v^(n+1/2);
 * with `prescribed` (projectile.motion) the velocity stays the initial one
 * (a sphere pushed at constant speed: the force is the target's steady
 * resistance). reads partials; updates state. */
__kernel void projectile_advance(__global real *restrict state,
                                 __global const real *restrict partials, const int groups,
                                 const real4 mask, const real scale, const real sphere_mass,
                                 const int prescribed, const real dt, const real dt_prev)
{
    if (get_global_id(0) != 0)
        return;
    real sum[SPH_CONTACT_SLOTS];
    for (int k = 0; k < SPH_CONTACT_SLOTS; ++k)
        sum[k] = 0;
    for (int g = 0; g < groups; ++g)
        for (int k = 0; k < SPH_CONTACT_SLOTS; ++k)
            sum[k] += partials[g * SPH_CONTACT_SLOTS + k];
    const real m[3] = {mask.x, mask.y, mask.z};
    const real kick = (real)0.5 * (dt_prev + dt); /* the particles' kick */
    for (int a = 0; a < 3; ++a) {
        const real force = -scale * m[a] * sum[SPH_CONTACT_FX + a];
        state[SPH_PROJ_F + a] = force;
        if (prescribed) {
            /* held at its velocity by a force -F, whose work and impulse
             * the energy and momentum balances count */
            state[SPH_PROJ_DRIVER_WORK] -= kick * force * state[SPH_PROJ_V + a];
            state[SPH_PROJ_DRIVER_IMPULSE + a] -= kick * force;
        } else {
            state[SPH_PROJ_V + a] += kick * force / sphere_mass;
        }
        state[SPH_PROJ_X + a] += dt * state[SPH_PROJ_V + a];
    }
    state[SPH_PROJ_CONTACT_ENERGY] = scale * sum[SPH_CONTACT_ENERGY];
    state[SPH_PROJ_DISSIPATED] += dt * scale * sum[SPH_CONTACT_DISSIPATION];
    state[SPH_PROJ_CONTACTS] = sum[SPH_CONTACT_COUNT];
}

/* Cavity probes: for probe k at depth z_k below the target's surface along
 * the impact axis `axis` (a unit vector; the track is the line through
 * `origin` along it), the particles whose depth lies within 0.55 of their
 * spacing of z_k (one or two lattice layers); the smallest distance of any of
 * them from the track, less half a spacing, is the empty cavity's radius
 * (D1 / 2; thesis Fig. 4.18) and the largest distance of a damaged one,
 * plus half a spacing, the damaged zone's (D2 / 2).
 * Slots: 2k the minimum distance - dx_i/2 (min), 2k + 1 the damaged
 * radius (max, 0 when none). reads pos, flags; writes partials. */
__kernel __attribute__((reqd_work_group_size(REDUCE_WG, 1, 1))) void
projectile_cavity(__global const vec *restrict pos, __global const int *restrict flags,
                  const real4 origin, const real4 axis, const real surface,
                  const real probe_spacing, const int probe_count, const real dx,
                  __global real *restrict partials, const int n)
{
    __local real acc[REDUCE_WG][2 * SPH_MAX_CAVITY_PROBES];
    real mine[2 * SPH_MAX_CAVITY_PROBES];
    for (int k = 0; k < SPH_MAX_CAVITY_PROBES; ++k) {
        mine[2 * k] = INFINITY;
        mine[2 * k + 1] = 0;
    }
    const vec o = vec_make(origin.x, origin.y, origin.z);
    const vec u = vec_make(axis.x, axis.y, axis.z);
    FOR_GROUP_BLOCK (i, n) {
        const int flag = flags[i];
        if (flag & SPH_FLAG_GHOST)
            continue;
        const real half_dx = (real)0.5 * dx * spacing_scale(flag);
        const vec x = pos[i];
        const real depth = dot(x, u) - surface;
        const int k = (int)round(depth / probe_spacing) - 1;
        if (k < 0 || k >= probe_count ||
            fabs(depth - (k + 1) * probe_spacing) > (real)1.1 * half_dx)
            continue;
        const vec along = dot(x - o, u) * u;
        const real r = length(x - o - along);
        mine[2 * k] = fmin(mine[2 * k], fmax(r - half_dx, (real)0));
        if (flag & SPH_FLAG_DAMAGED)
            mine[2 * k + 1] = fmax(mine[2 * k + 1], r + half_dx);
    }
    uchar op[2 * SPH_MAX_CAVITY_PROBES];
    for (int k = 0; k < 2 * SPH_MAX_CAVITY_PROBES; ++k)
        op[k] = (k & 1) ? REDUCE_MAX : REDUCE_MIN;
    work_group_reduce(&acc[0][0], mine, op, 2 * SPH_MAX_CAVITY_PROBES, partials);
}
