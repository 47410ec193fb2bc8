/*
 * Material update, from state n to n+1 with the velocity gradient of the
 * half-step velocity: Jaumann stress rate, von Mises radial return, density
 * and energy, then the equation of state and the artificial stress of the new
 * state (for the next pass 2). material_update_particle does one particle;
 * pass 1 (updated Lagrangian) and tl_deformation (total Lagrangian) call it
 * at the end of their neighbour sums.
 */

/* Equations of state take the compression mu = rho / rho0 - 1 computed from
 * the integrated density change: in single precision rho itself cannot hold
 * the per-step change of a stiff solid (1e-4 kg/m^3 against an ulp of 1e-3
 * at 7800 kg/m^3), its deviation from rho0 can. The EOS and yield stress
 * models are in material_models.cl. */

/* Strain rate D = sym(L) and spin W = skew(L); in plane stress D_zz follows
 * from sigma_zz = 0 for Hooke's law: D_zz = -nu/(1-nu) (D_xx + D_yy). */
static inline void strain_rate_and_spin(real l[3][3], real nu_factor, real d[3][3], real w[3][3])
{
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b) {
            d[a][b] = (real)0.5 * (l[a][b] + l[b][a]);
            w[a][b] = (real)0.5 * (l[a][b] - l[b][a]);
        }
#ifdef SPH_PLANE_STRESS
    d[2][2] = -nu_factor * (d[0][0] + d[1][1]);
#else
    (void)nu_factor;
#endif
}

/* Hooke with the Jaumann rate (thesis eq. 3.30; Gray, Monaghan & Swift 2001
 * eq. 5): dS/dt = 2G (D - tr(D)/3 I) + W S - S W. */
static inline void jaumann_stress_rate(real s[3][3], real d[3][3], real w[3][3], real shear_modulus,
                                       real rate[3][3])
{
    const real trace_third = (d[0][0] + d[1][1] + d[2][2]) / (real)3;
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b) {
            real rotation = 0;
#pragma unroll
            for (int e = 0; e < 3; ++e)
                rotation += w[a][e] * s[e][b] - s[a][e] * w[e][b];
            rate[a][b] =
                (real)2 * shear_modulus * (d[a][b] - (a == b ? trace_third : (real)0)) + rotation;
        }
}

#ifdef SPH_ARTIFICIAL_STRESS
/* symmetric_eigen: kernels/matrix.cl */

/* Monaghan (2000) / Gray, Monaghan & Swift (2001) eqs. 23-25: in the
 * principal frame R^a = -epsilon sigma^a / rho^2 where sigma^a > 0, else 0;
 * rotated back to the lab frame. Only the in-plane block matters in 2-D. */
static inline void artificial_stress_tensor(real sigma[3][3], real density, real epsilon,
                                            real r[3][3])
{
    real t[3][3], v[3][3];
    const int dims = SPH_DIM;
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b)
            t[a][b] = (a < dims && b < dims) ? sigma[a][b] : (real)0;
    symmetric_eigen(t, v);
    real principal[3];
#pragma unroll
    for (int a = 0; a < 3; ++a)
        principal[a] = t[a][a] > 0 ? -epsilon * t[a][a] / (density * density) : (real)0;
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b) {
            r[a][b] = 0;
            for (int k = 0; k < dims; ++k)
                r[a][b] += v[a][k] * principal[k] * v[b][k];
        }
}
#endif

/* D':D', D' the deviatoric part of the strain rate d, 1/s^2. */
static inline real deviatoric_rate_squared(real d[3][3])
{
    const real trace_third = (d[0][0] + d[1][1] + d[2][2]) / (real)3;
    real sum = 0;
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b) {
            const real dev = d[a][b] - (a == b ? trace_third : (real)0);
            sum += dev * dev;
        }
    return sum;
}

#ifdef SPH_PLASTICITY
/* Equivalent strain rate sqrt(2/3 D':D'), 1/s: the rate in Johnson-Cook. */
static inline real equivalent_strain_rate(real d[3][3])
{
    return sqrt((real)2 / (real)3 * deviatoric_rate_squared(d));
}

/* Plastic correction of the trial deviatoric stress s (radial return to
 * the current yield stress), the plastic strain increment, and the heating
 * rho c_p dT = beta sigma_y d eps_p of Johnson-Cook materials. */
static inline void plastic_correction(__constant const struct sph_material *m, real s[3][3],
                                      real d[3][3], real density, __global real *plastic_strain,
                                      __global real *temperature)
{
    real flat[9];
#pragma unroll
    for (int k = 0; k < 9; ++k)
        flat[k] = s[k / 3][k % 3];
    /* the same test radial_return makes, against a floor of the yield
     * stress: the elastic bulk skips the Johnson-Cook transcendentals
     * (taylor3d-200k: docs/performance.md, "The material update's elastic
     * fast path") */
    if (von_mises_equivalent(flat) <= yield_stress_floor(m, *temperature))
        return;
    const real yield = yield_stress_of(m, *plastic_strain, equivalent_strain_rate(d), *temperature);
    const real increment = radial_return(flat, yield, m->shear_modulus);
    if (increment <= 0)
        return;
#pragma unroll
    for (int k = 0; k < 9; ++k)
        s[k / 3][k % 3] = flat[k];
    *plastic_strain += increment;
    /* without a heat capacity (a Johnson-Cook law with m = 0 needs none)
     * the temperature stays at T_room, as README says */
    if (m->strength == SPH_STRENGTH_JOHNSON_COOK && m->heat_capacity > 0)
        *temperature += m->taylor_quinney * yield * increment / (density * m->heat_capacity);
}
#endif

/* Failure (thesis 4.3.2): past the material's plastic strain (0: at first
 * yield; negative: never) the particle keeps only its pressure, and no
 * tension. */
static inline bool particle_failed(__constant const struct sph_material *m, real plastic_strain,
                                   real density_change)
{
#ifdef SPH_PLASTICITY
    /* the critical stretch: rho0 / rho - 1 above failure_stretch, i.e. a
     * density change below -rho0 s / (1 + s) */
    const bool stretched =
        m->failure_stretch > 0 &&
        density_change < -m->density * m->failure_stretch / ((real)1 + m->failure_stretch);
    return stretched || (m->failure_strain >= 0 && plastic_strain > m->failure_strain);
#else
    (void)m;
    (void)plastic_strain;
    (void)density_change;
    return false;
#endif
}

/* The state the material update carries from step to step (the kernel
 * arguments, and the same names passed on), in this order. */
#define MATERIAL_STATE_ARGS                                                                        \
    __global real *restrict density_change, __global real *restrict energy,                        \
        __global symt *restrict deviatoric_stress, __global real *restrict plastic_strain,         \
        __global real *restrict temperature, __global const real *restrict energy_rate,            \
        __global real *restrict pressure, __global real *restrict sound_speed,                     \
        __global symt *restrict artificial_stress, __global symt *restrict viscous_stress,         \
        __global real *restrict av_alpha, __global real *restrict av_divergence
#define MATERIAL_STATE                                                                             \
    density_change, energy, deviatoric_stress, plastic_strain, temperature, energy_rate, pressure, \
        sound_speed, artificial_stress, viscous_stress, av_alpha, av_divergence

#ifdef SPH_VISCOSITY
/* The Newtonian viscous stress 2 eta D' (D' the deviatoric part of the
 * strain rate; axisymmetric: the hoop rate is in D) of particle i, and the
 * elastic part of the stored deviatoric stress: deviatoric_stress holds
 * their sum, which is what pass 2's forces and the energy equation use, so
 * the viscous heating 2 eta D' : D' enters the internal energy with the
 * stress power; viscous_stress keeps the viscous part apart so that only
 * the elastic part is rotated, integrated and returned to the yield
 * surface. */
static inline void viscous_stress_of(__constant const struct sph_material *m, real d[3][3],
                                     real sv[3][3])
{
    const real trace_third = (d[0][0] + d[1][1] + d[2][2]) / (real)3;
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b)
            sv[a][b] = (real)2 * m->viscosity * (d[a][b] - (a == b ? trace_third : (real)0));
}
#endif

#ifdef SPH_AV_SWITCH
/* The switch viscosity's alpha over the step (both formulations; div v
 * the strain rate's trace, hoop rate included) (Morris & Monaghan 1997, J.
 * Comput. Phys. 136:41, eq. 11 with the source of eq. 12): decay to
 * alpha_min over tau = h / (0.2 c), growth towards alpha_max (the case's
 * alpha) at the compression rate S = max(-div v, 0):
 *   d alpha / dt = -(alpha - alpha_min) / tau + S (alpha_max - alpha),
 * linear in alpha, so integrated exactly over dt (stable for any dt). The
 * first update (solver_prime, dt = 0) lifts the zeroed buffer to alpha_min.
 * h is the finest smoothing length: on a graded lattice the coarse shells
 * decay faster than their own h would make them. */
static inline real switch_decay_rate(real sound_speed, __constant const struct sph_run_params *run)
{
    return (real)0.2 * sound_speed / run->h;
}

static inline real switch_alpha(real alpha, real divergence, real floor, real sound_speed, real dt,
                                __constant const struct sph_run_params *run)
{
    const real decay = switch_decay_rate(sound_speed, run), source = fmax(-divergence, (real)0);
    const real rate = decay + source;
    const real target = (decay * floor + source * run->av_alpha) / rate;
    const real next = target + (alpha - target) * exp(-rate * dt);
    return clamp(next, floor, fmax(run->av_alpha, floor));
}

/* The floor alpha decays to: alpha_min, or with SPH_AV_BALSARA
 * (numerics.artificial_viscosity.balsara) alpha_min times Balsara's factor
 * |div v| / (|div v| + |curl v| + 1e-4 c / h) (Balsara 1995, J. Comput.
 * Phys. 121:357): about 1 in compression, about 0 in shear and
 * rotation, so the floor no longer damps a shear flow (a viscous liquid
 * past a sphere, a gel's wake) while a shock still lifts alpha at the
 * compression rate. |curl v|^2 = 2 w:w, w the spin. */
static inline real switch_floor(real divergence, real w[3][3], real sound_speed,
                                __constant const struct sph_run_params *run)
{
#ifdef SPH_AV_BALSARA
    real spin2 = 0;
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b)
            spin2 += w[a][b] * w[a][b];
    const real div = fabs(divergence);
    return run->av_alpha_min * div /
           (div + sqrt((real)2 * spin2) + (real)1e-4 * sound_speed / run->h);
#else
    (void)divergence;
    (void)w;
    (void)sound_speed;
    return run->av_alpha_min;
#endif
}
#endif

#ifdef SPH_AV_CULLEN_DEHNEN
/* Cullen & Dehnen's indicator (2010, MNRAS 408:669, section 3): alpha
 * follows the rate at which compression grows, A = xi max(-d(div v)/dt, 0),
 * so it rises ahead of a shock and stays low in steady compression (where
 * the Morris-Monaghan source, -div v itself, keeps it up):
 *   alpha_loc = alpha_max h^2 A / (c^2 + h^2 A),
 * alpha jumps up to alpha_loc and otherwise decays to it at the switch's
 * rate 0.2 c / h, never below the floor (switch_floor). d(div v)/dt is taken from two
 * successive steps' div v (av_divergence); xi = (div v)^2 / ((div v)^2 +
 * S':S'), S' the traceless strain rate (Balsara's form of their limiter,
 * without the neighbour sign sum), keeps it off in shear. c is the
 * particle's own sound speed, h the finest smoothing length. */
static inline real cullen_dehnen_alpha(real alpha, real divergence, real d[3][3], real floor,
                                       __global real *previous_divergence, real sound_speed,
                                       real dt, __constant const struct sph_run_params *run)
{
    const real rate = dt > 0 ? (divergence - *previous_divergence) / dt : (real)0;
    *previous_divergence = divergence;
    const real div2 = divergence * divergence;
    const real xi = div2 / (div2 + deviatoric_rate_squared(d) + (real)1e-30);
    const real h2a = run->h * run->h * xi * fmax(-rate, (real)0);
    const real alpha_local = run->av_alpha * h2a / (sound_speed * sound_speed + h2a);
    const real decayed =
        alpha_local + (alpha - alpha_local) * exp(-switch_decay_rate(sound_speed, run) * dt);
    return fmax(alpha < alpha_local ? alpha_local : decayed, floor);
}
#endif

/* S^(n+1) from S^n: the Jaumann rate with the step's strain rate d and spin
 * w (none for failed material: a fluid), then the plastic return. Returns
 * the deviatoric stress power's two halves, S^n : d + S^(n+1) : d: the
 * mid-step stress (sigma^n + sigma^(n+1)) / 2 with the half-step strain
 * rate integrates an elastic solid's strain energy exactly, and the SPH
 * form of L makes it the counterpart of the stress forces' work (see
 * pass2.cl). Its second half uses the stress after the return (plastic
 * work heats; in plane stress the return also scales S_zz, so sigma_zz = 0
 * holds only while the material is elastic). */
static inline real deviatoric_update(__constant const struct sph_material *m, real s[3][3],
                                     real d[3][3], real w[3][3], bool was_failed, real dt,
                                     real rho_i, __global real *plastic_strain_i,
                                     __global real *temperature_i)
{
    real rate[3][3];
    jaumann_stress_rate(s, d, w, was_failed ? (real)0 : m->shear_modulus, rate);
    real power = 0;
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b) {
            power += s[a][b] * d[a][b];
            s[a][b] += dt * rate[a][b];
        }
#ifdef SPH_PLASTICITY
    if (m->strength != SPH_STRENGTH_ELASTIC)
        plastic_correction(m, s, d, rho_i, plastic_strain_i, temperature_i);
#else
    (void)rho_i;
    (void)plastic_strain_i;
    (void)temperature_i;
#endif
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b)
            power += s[a][b] * d[a][b];
    return power;
}

/* Failed material (thesis 4.3.2) carries no tension beyond its cavitation
 * pressure p_cav (materials[].cavitation_pressure, default 0): below
 * -p_cav it opens voids instead of stretching. */
static inline real failed_pressure(__constant const struct sph_material *m, real p)
{
    return fmax(p, -m->cavitation_pressure);
}

/* ... so its density stops falling where the EOS's tension branch reaches
 * -p_cav: rho0 (1 - p_cav / K0), K0 = rho0 c^2 - 4G/3 the EOS's bulk
 * modulus at rho0 (c the reference longitudinal wave speed); rho0 itself
 * with the default p_cav = 0. */
static inline real failed_density_change_floor(__constant const struct sph_material *m)
{
    const real bulk =
        m->density * m->sound_speed * m->sound_speed - (real)4 / (real)3 * m->shear_modulus;
    return -m->density * fmin(m->cavitation_pressure / bulk, (real)0.99);
}

/* The end-of-step stress state from the elastic deviatoric stress s: a
 * particle that has failed (thesis 4.3.2) keeps no elastic deviatoric
 * stress and no tension, but its viscous stress (a viscous fluid); the
 * artificial stress R of the total stress (Monaghan 2000) for the next
 * pass 2. */
static inline void store_stress(__constant const struct sph_material *m, real s[3][3], real p,
                                real density, bool was_failed,
                                __constant const struct sph_run_params *run,
                                __global const real *plastic_strain_i, real sv[3][3],
                                __global symt *deviatoric_stress_i, __global real *pressure_i,
                                __global symt *artificial_stress_i)
{
#ifdef SPH_PLASTICITY
    const bool failed = was_failed || particle_failed(m, *plastic_strain_i, density - m->density);
    if (failed) {
#pragma unroll
        for (int a = 0; a < 3; ++a)
#pragma unroll
            for (int b = 0; b < 3; ++b)
                s[a][b] = 0;
    }
    *pressure_i = failed ? failed_pressure(m, p) : p;
#else
    (void)m;
    (void)was_failed;
    (void)plastic_strain_i;
    *pressure_i = p;
#endif
#ifdef SPH_VISCOSITY
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b)
            s[a][b] += sv[a][b];
#else
    (void)sv; /* not set without viscosity */
#endif
    *deviatoric_stress_i = symt_store(s);
#ifdef SPH_ARTIFICIAL_STRESS
    real sigma[3][3], r[3][3];
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b)
            sigma[a][b] = s[a][b] - (a == b ? p : (real)0);
    artificial_stress_tensor(sigma, density, run->as_epsilon, r);
    *artificial_stress_i = symt_store(r);
#else
    (void)density;
    (void)run;
    (void)artificial_stress_i;
#endif
}

/* The material update of particle i (not a ghost) from its velocity
 * gradient l (1/s) and density rate (kg/m^3/s) over the step dt (s): called
 * at the end of pass 1 in the updated Lagrangian form (pass1.cl),
 * so the velocity gradient is never stored, and at the end of
 * tl_deformation in the total Lagrangian form (total_lagrangian.cl). It writes only particle i's
 * own state, and not its density or flags, which neighbours' pass 1 reads while it runs: it returns
 * the new density, and integrate_drift writes that and the damage flag (particle_failed) after
 * every particle's update. */
static inline real
material_update_particle(int i, real l[3][3], real density_rate_i, real dt,
                         __global const real *restrict rho, __global const int *restrict material,
                         __global const int *restrict flags, __global const vec *restrict pos,
                         __global const vec *restrict vel_half,
                         __constant const struct sph_material *materials,
                         __constant const struct sph_run_params *run, MATERIAL_STATE_ARGS)
{
    __constant const struct sph_material *m = &materials[material[i]];
    real s[3][3], d[3][3], w[3][3];
    symt_load(deviatoric_stress[i], s);
    strain_rate_and_spin(l, m->plane_stress_nu, d, w);
#ifdef SPH_AXISYMMETRIC
    d[2][2] = vel_half[i].x / axis_radius(pos[i].x, run); /* hoop strain rate v_r / r */
#else
    (void)pos;
    (void)vel_half;
#endif
    /* a failed particle (thesis 4.3.2) is a fluid: no deviatoric stress,
     * and no tension in the pressure it works with */
    const bool was_failed = (flags[i] & SPH_FLAG_DAMAGED) != 0;
    const real p_old = pressure[i];
    const real trace_d = d[0][0] + d[1][1] + d[2][2];
#if defined(SPH_AV_CULLEN_DEHNEN)
    av_alpha[i] =
        cullen_dehnen_alpha(av_alpha[i], trace_d, d, switch_floor(trace_d, w, sound_speed[i], run),
                            &av_divergence[i], sound_speed[i], dt, run);
#elif defined(SPH_AV_SWITCH)
    av_alpha[i] = switch_alpha(av_alpha[i], trace_d, switch_floor(trace_d, w, sound_speed[i], run),
                               sound_speed[i], dt, run);
    (void)av_divergence;
#else
    (void)av_alpha;
    (void)av_divergence;
#endif
    real sv[3][3];
#ifdef SPH_VISCOSITY
    /* s is the elastic part below; the viscous part's two halves of the
     * stress power, S_v^n : d + S_v^(n+1) : d, are added to its own */
    symt_load(viscous_stress[i], sv);
    real power_viscous = 0;
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b) {
            s[a][b] -= sv[a][b];
            power_viscous += sv[a][b] * d[a][b];
        }
    viscous_stress_of(m, d, sv);
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b)
            power_viscous += sv[a][b] * d[a][b];
    viscous_stress[i] = symt_store(sv);
#else
    (void)viscous_stress;
    const real power_viscous = 0;
#endif
    const real power_deviatoric =
        power_viscous +
        deviatoric_update(m, s, d, w, was_failed, dt, rho[i], &plastic_strain[i], &temperature[i]);
    /* continuity drho/dt = -rho div v integrated exactly for the step's
     * divergence: rho^(n+1) = rho^n exp(-dt div v), which stays positive
     * where fragments fly apart (the explicit update crosses zero once
     * dt div v > 1) and agrees with it to first order otherwise */
    const real rho_old = m->density + density_change[i];
    /* ... and, once failed, not below the density of its cavitation
     * pressure (rho0 by default): material that carries no more tension
     * opens voids between its pieces instead of stretching, so the pieces
     * keep the density of the pressure cut-off. In the continuity equation a piece flung
     * off the target (debris in a cavity) would otherwise keep expanding
     * until its density underflows, and when it meets the cavity wall
     * again the pair force, (sigma_i + sigma_j) / (rho_i rho_j), grows as
     * 1 / rho_i (a 100x force at the former floor rho0 / 100 blew up the
     * SEBS runs). Intact material keeps that floor against underflow. */
    const real change_floor =
        was_failed ? failed_density_change_floor(m) : (real)-0.99 * m->density;
    const real change =
        fmax(density_change[i] + rho_old * expm1(dt * density_rate_i / rho_old), change_floor);
    const real density = m->density + change;
    const real e_trial = energy[i] + dt * energy_rate[i];
    real p_trial = pressure_eos(m, change / m->density, e_trial);
    if (was_failed)
        p_trial = failed_pressure(m, p_trial);
    const real power = (real)0.5 * (power_deviatoric - (p_old + p_trial) * trace_d);
    const real e = e_trial + dt * power / rho[i];
    const real p = pressure_eos(m, change / m->density, e);
    density_change[i] = change;
    energy[i] = e;
    /* the artificial viscosity and the time step follow the stiffening of
     * compressed material (Monaghan 1992: c_i is particle i's own speed) */
    sound_speed[i] = sound_speed_current(m, density, e);
    store_stress(m, s, p, density, was_failed, run, &plastic_strain[i], sv, &deviatoric_stress[i],
                 &pressure[i], &artificial_stress[i]);
    return density;
}
