/*
 * Total Lagrangian SPH (numerics.formulation: total_lagrangian) for solids
 * that stay whole: every derivative is taken in the reference (initial)
 * configuration, over the neighbours a particle had at t = 0. Bonet & Lok
 * (1999) and Vidal, Bonet & Huerta (2007) give the formulation; Ganzenmueller
 * (2015, Comput. Methods Appl. Mech. Engrg. 286) the hourglass control.
 * Because neighbours and kernel gradients never change, the method has no
 * tensile instability (Belytschko et al. 2000) and needs no artificial
 * stress; the price is that it cannot follow fracture or mixing.
 *
 * The neighbour grid is built once on the reference positions (the host
 * never re-sorts in this formulation) and every pair test uses them.
 * Notation: X reference position (pos0), x current, g_ij = grad_X W(|X_i -
 * X_j|) (the gradient with respect to X_i), V0_j = m_j / rho0_j,
 * C_i = (sum_j V0_j (X_j - X_i) (x) g_ij)^-1 the reference correction
 * (stored in the csph field), so that G_ij = C_i^T g_ij differentiates
 * linear fields exactly.
 *
 * Per step (see kernels/integrate.cl for the leap-frog):
 *   tl_momentum (pass 2)  dv_i/dt = 1/rho0_i sum_j V0_j (A_i + A_j) g_ij
 *                         with A = P C^T, P = J sigma F^-T (first Piola-Kirchhoff);
 *                         plus artificial viscosity, XSPH and hourglass control
 *   tl_deformation (pass 1) F and its rate from the motion of the step;
 *                         L = dF/dt F_mid^-1 for the material update
 *   material_update       the same constitutive update as the updated form
 *   tl_first_piola        A^(n+1) for the next step's momentum
 * The stress force is the derivative of sum_i V0_i Psi(F_i) with respect to
 * x_i, hence antisymmetric in the pair (momentum is conserved exactly) and
 * work-conjugate to the deformation rate that the material update uses.
 */

#ifdef SPH_TOTAL_LAGRANGIAN
#if SPH_LANES != 1
#error "the total Lagrangian form runs one particle per work-item (host/state.c, solver_lanes)"
#endif

/* The three components of a vec, as the tensor helpers take them. */
static inline void vec_components(vec v, real out[3])
{
#pragma unroll
    for (int a = 0; a < 3; ++a)
        out[a] = a < SPH_DIM ? vec_get(v, a) : (real)0;
}

/* Whether j (not i) is a reference neighbour of i, given X_ij = X_i - X_j;
 * if so its reference volume V0_j = m_j / rho0_j and the gradient
 * g_ij = grad_X W(|X_ij|) (with respect to X_i). */
static inline bool tl_reference_pair(bool distinct, vec big_xij, real support2, real inv_h,
                                     real volume_j, real *volume, vec *grad)
{
    const real r2 = dot(big_xij, big_xij);
    if (!distinct || r2 >= support2)
        return false;
    *volume = volume_j;
    *grad = kernel_dwdr_over_r_q(sqrt(r2) * inv_h, inv_h) * big_xij;
    return true;
}

/* C_i from the reference lattice; run once, before the first step.
 * reads: pos0, mass, material; writes: csph (C_i). */
__kernel void tl_correction(__global const vec *restrict pos0, __global const real *restrict mass,
                            __global const int *restrict material, GRID_ARGS,
                            __constant const struct sph_material *materials,
                            __constant const struct sph_run_params *run,
                            __global symt *restrict csph, const int n)
{
    const int i = get_global_id(0);
    if (i >= n)
        return;
    const real inv_h = (real)1 / run->h, support2 = run->support * run->support;
    const vec xi = pos0[i];
    real moment[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    FOR_EACH_NEIGHBOUR_WITHIN(i, j, SPH_GRID_SPLIT)
    {
        const vec xij = xi - pos0[j];
        real volume;
        vec grad;
        if (tl_reference_pair(j != i, xij, support2, inv_h,
                              mass[j] / materials[material[j]].density, &volume, &grad)) {
            real x[3], g[3];
            vec_components(xij, x);
            vec_components(grad, g);
            outer_add(moment, -volume, x, g);
        }
    }
    END_FOR_EACH_NEIGHBOUR
    real c[3][3];
    matrix_invert_or_identity(moment, c);
    csph[i] = symt_store(c); /* symmetric: grad W_ij is along X_ij */
}

/* F^n from the positions x^n, and its rate from the motion of this step,
 * w = v^(n+1/2) + v_xsph (the velocity integrate_drift moves particles
 * with), so that F^(n+1) = F^n + dt dF/dt is exactly the gradient of
 * x^(n+1). The material update gets L = dF/dt (F^n + dt/2 dF/dt)^-1, the
 * mid-step velocity gradient.
 * reads: pos, pos0, vel_half, xsph_velocity, mass, rho, material, csph;
 * writes: velocity_gradient, density_rate, deformation_gradient (F^(n+1)). */
__kernel void
tl_deformation(__global const vec *restrict pos, __global const vec *restrict pos0,
               __global const vec *restrict vel_half, __global const vec *restrict xsph_velocity,
               __global const real *restrict mass, __global const real *restrict rho,
               __global const int *restrict material, __global const int *restrict flags, GRID_ARGS,
               __constant const struct sph_material *materials,
               __constant const struct sph_run_params *run, __global const symt *restrict csph,
               const real dt, __global fullt *restrict velocity_gradient,
               __global real *restrict density_rate, __global fullt *restrict deformation_gradient,
               const int n)
{
    const int i = get_global_id(0);
    if (i >= n || (flags[i] & SPH_FLAG_GHOST))
        return;
    const real inv_h = (real)1 / run->h, support2 = run->support * run->support;
    const vec big_xi = pos0[i], xi = pos[i], wi = vel_half[i] + xsph_velocity[i];
    real sum_x[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    real sum_w[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    FOR_EACH_NEIGHBOUR_WITHIN(i, j, SPH_GRID_SPLIT)
    {
        real volume;
        vec grad;
        if (tl_reference_pair(j != i, big_xi - pos0[j], support2, inv_h,
                              mass[j] / materials[material[j]].density, &volume, &grad)) {
            real x[3], w[3], g[3];
            vec_components(pos[j] - xi, x);
            vec_components(vel_half[j] + xsph_velocity[j] - wi, w);
            vec_components(grad, g);
            outer_add(sum_x, volume, x, g);
            outer_add(sum_w, volume, w, g);
        }
    }
    END_FOR_EACH_NEIGHBOUR
    real c[3][3], f[3][3], f_rate[3][3], f_mid[3][3], f_mid_inv[3][3], l[3][3];
    symt_load(csph[i], c);
    matrix_product(sum_x, c, f);
    matrix_product(sum_w, c, f_rate);
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b) {
            f_mid[a][b] = f[a][b] + (real)0.5 * dt * f_rate[a][b];
            f[a][b] += dt * f_rate[a][b];
        }
    matrix_invert_or_identity(f_mid, f_mid_inv);
    matrix_product(f_rate, f_mid_inv, l);
    real divergence = l[0][0] + l[1][1] + l[2][2];
#ifdef SPH_PLANE_STRESS
    /* sigma_zz = 0 needs eps_zz rate = -nu/(1-nu) (eps_xx + eps_yy) (Hooke) */
    divergence *= (real)1 - materials[material[i]].plane_stress_nu;
#endif
    velocity_gradient[i] = fullt_store(l);
    density_rate[i] = -rho[i] * divergence;
    deformation_gradient[i] = fullt_store(f);
}

/* A = P C^T with P = J sigma F^-T, J = rho0 / rho (the density carries the
 * out-of-plane stretch in plane stress, so J is the volume ratio of the
 * slice). reads: rho, pressure, deviatoric_stress, deformation_gradient,
 * csph, material; writes: first_piola (A). */
__kernel void tl_first_piola(__global const real *restrict rho,
                             __global const real *restrict pressure,
                             __global const symt *restrict deviatoric_stress,
                             __global const fullt *restrict deformation_gradient,
                             __global const symt *restrict csph,
                             __global const int *restrict material,
                             __constant const struct sph_material *materials,
                             __global fullt *restrict first_piola, const int n)
{
    const int i = get_global_id(0);
    if (i >= n)
        return;
    real sigma[3][3], f[3][3], f_inv[3][3], f_inv_t[3][3], c_t[3][3], p[3][3], a[3][3];
    total_stress(pressure[i], deviatoric_stress[i], sigma);
    fullt_load(deformation_gradient[i], f);
    matrix_invert_or_identity(f, f_inv);
    symt_load(csph[i], c_t);
#pragma unroll
    for (int r = 0; r < 3; ++r)
#pragma unroll
        for (int q = 0; q < 3; ++q) {
            f_inv_t[r][q] = f_inv[q][r];
            if (r < q) {
                const real t = c_t[r][q];
                c_t[r][q] = c_t[q][r];
                c_t[q][r] = t;
            }
        }
    const real volume_ratio = materials[material[i]].density / rho[i];
    matrix_product(sigma, f_inv_t, p);
    matrix_product(p, c_t, a);
#pragma unroll
    for (int r = 0; r < 3; ++r)
#pragma unroll
        for (int q = 0; q < 3; ++q)
            a[r][q] *= volume_ratio;
    first_piola[i] = fullt_store(a);
}

/* Hourglass control (after Ganzenmueller 2015, eqs. 18-20): the pair
 * separation predicted by the mean deformation gradient of the two
 * particles, F_ij X_ji, is compared with the actual x_ji; the mismatch along
 * the pair (zero for every linear displacement field, so it adds no
 * stiffness to a homogeneous deformation) is pulled back by a pair force of
 * modulus alpha E V0_i V0_j W(X_ij) / X_ij^2 per metre of mismatch. Returns
 * that force over m_i (an acceleration). */
static inline vec tl_hourglass(vec xji, vec big_xji, real r0, real w0, real f_mean[3][3],
                               real coefficient, real volume_j)
{
    real predicted[3] = {0, 0, 0};
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a)
#pragma unroll
        for (int b = 0; b < SPH_DIM; ++b)
            predicted[a] += f_mean[a][b] * vec_get(big_xji, b);
    const real r = length(xji);
    if (r <= 0)
        return VEC_ZERO;
    const vec direction = xji / r;
    const vec mismatch = xji - vec_make(predicted[0], predicted[1], predicted[2]);
    return (coefficient * volume_j * w0 / (r0 * r0) * dot(mismatch, direction)) * direction;
}

/* tl_hourglass with the pair's mean deformation gradient (F_i + F_j) / 2. */
static inline vec tl_pair_hourglass(const real f_i[3][3], fullt f_j, vec xij, vec big_xij, real r0,
                                    real w0, real hourglass, real volume_j)
{
    real f_mean[3][3];
    fullt_load(f_j, f_mean);
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b)
            f_mean[a][b] = (real)0.5 * (f_mean[a][b] + f_i[a][b]);
    return tl_hourglass(-xij, -big_xij, r0, w0, f_mean, hourglass, volume_j);
}

/* Pass 2 of the total Lagrangian form: stress force, artificial viscosity
 * (on the current pair geometry, as in the updated form), hourglass control,
 * XSPH. reads: pos, pos0, vel, rho, mass, first_piola, deformation_gradient,
 * sound_speed, material, av_alpha (SPH_AV_SWITCH: the pair's alpha is the
 * mean of the particles', beta in the case's ratio to it, as in pass 2);
 * writes: acceleration, energy_rate, viscous_heating
 * (the viscosity's part of energy_rate), hourglass_power (W/kg: the work
 * the hourglass forces take out of the motion, -1/2 sum_j v_ij . a_hg,ij,
 * which is not heat and is kept apart for the energy ledger), xsph_velocity. */
__kernel void
tl_momentum(__global const vec *restrict pos, __global const vec *restrict pos0,
            __global const vec *restrict vel, __global const real *restrict rho,
            __global const real *restrict mass, __global const fullt *restrict first_piola,
            __global const fullt *restrict deformation_gradient,
            __global const real *restrict sound_speed, __global const int *restrict material,
            __global const int *restrict flags, __global const real *restrict av_alpha, GRID_ARGS,
            __constant const struct sph_material *materials,
            __constant const struct sph_run_params *run, __global vec *restrict acceleration,
            __global real *restrict energy_rate, __global real *restrict viscous_heating,
            __global real *restrict hourglass_power, __global vec *restrict xsph_velocity,
            const int n)
{
    const int i = get_global_id(0);
    if (i >= n || (flags[i] & SPH_FLAG_GHOST))
        return;
    const real h = run->h, inv_h = (real)1 / h, support2 = run->support * run->support;
    const vec big_xi = pos0[i], xi = pos[i], vi = vel[i];
    __constant const struct sph_material *mi = &materials[material[i]];
    /* hourglass stiffness alpha E / rho0_i, E = 9 K G / (3 K + G) */
    const real hourglass = run->hourglass * (real)9 * mi->bulk_modulus * mi->shear_modulus /
                           (((real)3 * mi->bulk_modulus + mi->shear_modulus) * mi->density);
    real a_i[3][3], f_i[3][3];
    fullt_load(first_piola[i], a_i);
    fullt_load(deformation_gradient[i], f_i);
    real acc[3] = {0, 0, 0};
    real de = 0, hourglass_rate = 0;
    vec xsph = VEC_ZERO, acc_extra = VEC_ZERO; /* viscosity, hourglass */
#ifdef SPH_AV_SWITCH
    const real beta_per_alpha = run->av_alpha > 0 ? run->av_beta / run->av_alpha : (real)0;
#endif
    FOR_EACH_NEIGHBOUR_WITHIN(i, j, SPH_GRID_SPLIT)
    {
        const vec big_xij = big_xi - pos0[j];
        const real r02 = dot(big_xij, big_xij);
        if (j != i && r02 < support2) {
            const real r0 = sqrt(r02);
            __constant const struct sph_material *mj = &materials[material[j]];
            const real volume_j = mass[j] / mj->density;
            const real dwdr_r = kernel_dwdr_over_r_q(r0 * inv_h, inv_h);
            real a_j[3][3], grad[3] = {0, 0, 0}, stress_force[3];
            fullt_load(first_piola[j], a_j);
#pragma unroll
            for (int a = 0; a < SPH_DIM; ++a)
                grad[a] = dwdr_r * vec_get(big_xij, a);
#pragma unroll
            for (int a = 0; a < SPH_DIM; ++a) {
                stress_force[a] = 0;
#pragma unroll
                for (int b = 0; b < SPH_DIM; ++b)
                    stress_force[a] += (a_i[a][b] + a_j[a][b]) * grad[b];
                acc[a] += volume_j * stress_force[a];
            }
            const vec xij = xi - pos[j], vij = vi - vel[j];
            const real r2 = dot(xij, xij);
            if (r2 < support2 && r2 > 0) {
                const real q = sqrt(r2) * inv_h, inv_rho_mean = (real)2 / (rho[i] + rho[j]);
#ifdef SPH_AV_SWITCH
                const real alpha_ij = (real)0.5 * (av_alpha[i] + av_alpha[j]);
                const real beta_ij = beta_per_alpha * alpha_ij;
#else
                (void)av_alpha;
                const real alpha_ij = run->av_alpha, beta_ij = run->av_beta;
#endif
                const real pi_ij = artificial_viscosity(
                    dot(vij, xij), r2, h, (real)0.5 * (sound_speed[i] + sound_speed[j]),
                    inv_rho_mean, alpha_ij, beta_ij);
                const vec visc = (-mass[j] * pi_ij * kernel_dwdr_over_r_q(q, inv_h)) * xij;
                acc_extra += visc;
                de -= (real)0.5 * dot(vij, visc);
#ifdef SPH_XSPH
                xsph -= (mass[j] * inv_rho_mean * kernel_w_q(q, inv_h)) * vij;
#endif
            }
            if (hourglass > 0) {
                const vec a_hg =
                    tl_pair_hourglass(f_i, deformation_gradient[j], xij, big_xij, r0,
                                      kernel_w_q(r0 * inv_h, inv_h), hourglass, volume_j);
                acc_extra += a_hg;
                hourglass_rate -= (real)0.5 * dot(vij, a_hg);
            }
        }
    }
    END_FOR_EACH_NEIGHBOUR
    const real inv_rho0 = (real)1 / mi->density;
    acceleration[i] = inv_rho0 * vec_make(acc[0], acc[1], acc[2]) + acc_extra;
    energy_rate[i] = de;
    viscous_heating[i] = de; /* no other artificial heating in this form */
    hourglass_power[i] = hourglass_rate;
    store_xsph(xsph_velocity, i, xsph, run);
}

#endif /* SPH_TOTAL_LAGRANGIAN */
