/*
 * Pass 1: velocity gradient, density rate and (with SPH_CSPH) the kernel
 * gradient correction.
 *
 * L_i = sum_j V_j (v_j - v_i) (x) grad_i W_ij, V_j = m_j / rho_j. With CSPH
 * (thesis eqs. 3.10-3.11; Chen et al. 1999, Bonet & Lok 1999) the gradient is
 * corrected so that a linear velocity field is differentiated exactly:
 * B_i = sum_j V_j (x_j - x_i) (x) grad_i W_ij, corrected gradient C_i^T grad W
 * with C_i = B_i^-1, hence L_i <- L_i C_i (one pass suffices because L is
 * linear in the gradient).
 * Density: continuity, drho_i/dt = -rho_i tr(L_i) (plus the out-of-plane
 * strain rate in plane stress).
 * Then each particle's material update (material.cl) with its L_i and
 * density rate, so neither is stored (64 + 4 B per particle in 3-D): it
 * writes only particle i's own state, none of what pass 1 reads of the
 * neighbours (integrate_drift writes the new density).
 *
 * With SPH_AV_LIMITED the (corrected) L_i is also stored, for pass 2's
 * reconstruction of the pair velocity jump (pass2.cl).
 *
 * reads: pos, vel (half step), rho, mass, material, flags, energy_rate;
 * writes: csph, velocity_gradient (SPH_AV_LIMITED); updates: av_alpha
 * (SPH_AV_SWITCH) and the material state (MATERIAL_STATE_ARGS).
 */

#ifdef SPH_AV_SWITCH
/* The switch viscosity's alpha over the step (Morris & Monaghan 1997, J.
 * Comput. Phys. 136:41, eq. 11 with the source of eq. 12): decay to
 * alpha_min over tau = h / (0.2 c), growth towards alpha_max (the case's
 * alpha) at the compression rate S = max(-div v, 0):
 *   d alpha / dt = -(alpha - alpha_min) / tau + S (alpha_max - alpha),
 * linear in alpha, so integrated exactly over dt (stable for any dt). The
 * first update (solver_prime, dt = 0) lifts the zeroed buffer to alpha_min.
 * h is the finest smoothing length: on a graded lattice the coarse shells
 * decay faster than their own h would make them. */
static inline real switch_alpha(real alpha, real divergence, real sound_speed, real dt,
                                __constant const struct sph_run_params *run)
{
    const real decay = (real)0.2 * sound_speed / run->h, source = fmax(-divergence, (real)0);
    const real rate = decay + source;
    const real target = (decay * run->av_alpha_min + source * run->av_alpha) / rate;
    const real next = target + (alpha - target) * exp(-rate * dt);
    return clamp(next, run->av_alpha_min, fmax(run->av_alpha, run->av_alpha_min));
}
#endif

/* What pass 1 does with particle i's sums (shared with kernels/lanes.cl):
 * the CSPH correction C_i = B_i^-1 (symmetric, since grad W_ij is along
 * x_ij) applied to L_i, the density rate, and the material update. */
static inline void
pass1_finish(int i, real grad_v[3][3], real moment[3][3], __global const real *restrict rho,
             __global const int *restrict material, __global const int *restrict flags,
             __constant const struct sph_material *materials,
             __constant const struct sph_run_params *run, __global symt *restrict csph,
             __global fullt *restrict velocity_gradient, __global real *restrict av_alpha,
             const real dt, __global const vec *restrict pos, __global const vec *restrict vel,
             MATERIAL_STATE_ARGS)
{
#ifndef SPH_CSPH
    (void)moment;
    (void)csph;
#endif
#ifdef SPH_CSPH
    real c[3][3], corrected[3][3];
    matrix_invert_or_identity(moment, c);
    matrix_product(grad_v, c, corrected);
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b)
            grad_v[a][b] = corrected[a][b];
    csph[i] = symt_store(c);
#endif
#ifdef SPH_AV_LIMITED
    velocity_gradient[i] = fullt_store(grad_v);
#else
    (void)velocity_gradient;
#endif
    real divergence = grad_v[0][0] + grad_v[1][1] + grad_v[2][2];
#ifdef SPH_AXISYMMETRIC
    divergence += vel[i].x / axis_radius(pos[i].x, run); /* hoop strain rate v_r / r */
#endif
#ifdef SPH_PLANE_STRESS
    /* sigma_zz = 0 needs eps_zz rate = -nu/(1-nu) (eps_xx + eps_yy) (Hooke) */
    divergence *= (real)1 - materials[material[i]].plane_stress_nu;
#endif
#ifdef SPH_AV_SWITCH
    av_alpha[i] = switch_alpha(av_alpha[i], divergence, sound_speed[i], dt, run);
#else
    (void)av_alpha;
#endif
    material_update_particle(i, grad_v, -rho[i] * divergence, dt, rho, material, flags, pos, vel,
                             materials, run, MATERIAL_STATE);
}

__kernel void pass1_velocity_gradient(
    __global const vec *restrict pos, __global const vec *restrict vel,
    __global const real *restrict rho, __global const real *restrict mass,
    __global const int *restrict material, __global const int *restrict flags, GRID_ARGS,
    __constant const struct sph_material *materials, __constant const struct sph_run_params *run,
    __global symt *restrict csph, __global fullt *restrict velocity_gradient,
    __global real *restrict av_alpha, const real dt, MATERIAL_STATE_ARGS, const int n)
{
    const int i = get_global_id(0);
    if (i >= n || (flags[i] & SPH_FLAG_GHOST))
        return;
    const real q2 = (run->support / run->h) * (run->support / run->h); /* (support / h)^2 */
    const vec xi = pos[i], vi = vel[i];
#ifndef SPH_CSPH
    (void)csph;
#endif
    real grad_v[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
#ifdef SPH_CSPH
    real moment[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
#endif
    FOR_EACH_NEIGHBOUR(i, j)
    {
        const vec xij = xi - pos[j];
        const real r2 = dot(xij, xij);
        const real h = PAIR_H(i, j);
        if (r2 > 0 && r2 < q2 * h * h) { /* excludes i, and a coincident pair (grad W = 0) */
            const real r = sqrt(r2);
            const real volume = plane_mass(mass[j], pos[j], run) / rho[j];
            const vec grad = (kernel_dwdr(r, h) / r) * xij; /* grad_i W_ij */
            const vec vji = vel[j] - vi;
#pragma unroll
            for (int a = 0; a < SPH_DIM; ++a)
#pragma unroll
                for (int b = 0; b < SPH_DIM; ++b) {
                    grad_v[a][b] += volume * vec_get(vji, a) * vec_get(grad, b);
#ifdef SPH_CSPH
                    moment[a][b] -= volume * vec_get(xij, a) * vec_get(grad, b);
#endif
                }
        }
    }
    END_FOR_EACH_NEIGHBOUR
#ifndef SPH_CSPH
    real moment[3][3];
#endif
    pass1_finish(i, grad_v, moment, rho, material, flags, materials, run, csph, velocity_gradient,
                 av_alpha, dt, pos, vel, MATERIAL_STATE);
}
