/*
 * Pass 2: acceleration, the artificial part of the energy rate, and the XSPH
 * velocity.
 *
 * Momentum (thesis eq. 3.17; Gray, Monaghan & Swift 2001 eq. 28), with
 * sigma = -p I + S and the kernel gradient g = grad_i W_ij:
 *   dv_i/dt = sum_j m_j [ (sigma_i . g_i + sigma_j . g_j) / (rho_i rho_j)
 *                         + (f_ij^n (R_i + R_j) - Pi_ij I) . g ]
 * where g_i = g_j = g in plain SPH, and with CSPH g_i = C_i^T g,
 * g_j = C_j^T g (Bonet & Lok 1999). The pair terms stay antisymmetric, so
 * linear momentum is conserved, and the stress force is the work conjugate
 * of pass 1's velocity gradient L_i = sum_j V_j (v_j - v_i) (x) g_i: the
 * material update adds sigma_i : L_i / rho_i to the internal energy, which
 * balances the work of these forces exactly.
 * This pass adds the heating of the artificial terms,
 *   de_i/dt = -1/2 sum_j m_j (v_i - v_j) . (f^n (R_i + R_j) - Pi I) . g.
 * Pi_ij: Monaghan artificial viscosity (Monaghan 1992 eq. 4.1). With
 * SPH_AV_LIMITED (numerics.artificial_viscosity.scheme: limited) the
 * velocity jump in mu_ij is not v_i - v_j but the jump left between the two
 * particles' linear reconstructions to the pair's midpoint,
 *   v_i - v_j - phi_ij / 2 (L_i + L_j) . x_ij,
 * with L from pass 1 and a van Leer-type limiter phi_ij in [0, 1] of the
 * ratio of the two slopes along x_ij (Frontiere, Raskin & Owen 2017, J.
 * Comput. Phys. 332:160, sec. 2.3; Christensen 1990; as Spheral's limited
 * Monaghan-Gingold viscosity): in a smooth flow (shear, uniform
 * compression, rotation) the reconstructions meet and the viscosity
 * vanishes, at a shock the slopes disagree, phi -> 0 and the full pair jump
 * is damped. Pairs closer than a lattice spacing get the full jump back
 * (av_limiter), which keeps particles from interpenetrating. With
 * SPH_AV_SWITCH (scheme: switch) alpha is the pair mean of a per-particle
 * alpha that compression raises and that decays to alpha_min elsewhere
 * (pass1.cl, switch_alpha; Morris & Monaghan 1997), beta in proportion.
 * f_ij = W(r_ij) / W(dx): Monaghan (2000) artificial stress weight.
 * XSPH (Monaghan 1989): v^_i = v_i + eps sum_j m_j / rho_ij (v_j - v_i) W_ij.
 *
 * reads: pos, vel, rho, mass, pressure, deviatoric_stress,
 *        artificial_stress, csph, sound_speed, velocity_gradient (limited),
 *        av_alpha (switch);
 * writes: acceleration, energy_rate, viscous_heating (the viscosity's part
 *         of energy_rate, for the work ledger), xsph_velocity.
 */

/* sigma = S - p I */
static inline void total_stress(real p, symt dev, real out[3][3])
{
    symt_load(dev, out);
#pragma unroll
    for (int a = 0; a < 3; ++a)
        out[a][a] -= p;
}

/* out = m . v over the first SPH_DIM components */
static inline void matrix_times(real m[3][3], real v[3], real out[3])
{
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a) {
        out[a] = 0;
#pragma unroll
        for (int b = 0; b < SPH_DIM; ++b)
            out[a] += m[a][b] * v[b];
    }
}

/* out = m^T . v */
static inline void transpose_times(real m[3][3], real v[3], real out[3])
{
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a) {
        out[a] = 0;
#pragma unroll
        for (int b = 0; b < SPH_DIM; ++b)
            out[a] += m[b][a] * v[b];
    }
}

/* out = C^T v for the symmetric CSPH correction C (pass1.cl) */
static inline void symt_transpose_times(symt f, real v[3], real out[3])
{
    real m[3][3];
    symt_load(f, m);
    transpose_times(m, v, out);
}

/* out = (S - p I) . v */
static inline void stress_times(real p, symt dev, real v[3], real out[3])
{
    real m[3][3];
    total_stress(p, dev, m);
    matrix_times(m, v, out);
}

/* Monaghan's (2000) artificial-stress weight (W(r) / W(dx))^n */
static inline real artificial_stress_weight(real r, real h,
                                            __constant const struct sph_run_params *run)
{
    const real f = kernel_w(r, h) * run->as_inv_w_dx;
    real fn = 1;
    for (int k = 0; k < run->as_exponent; ++k)
        fn *= f;
    return fn;
}

#ifdef SPH_AV_LIMITED
/* The limiter of the reconstructed jump for the slopes g_i = x_ij . L_i .
 * x_ij, g_j likewise: 4 g_i g_j / (g_i + g_j)^2 (van Leer's, symmetric in
 * i and j; 0 where the slopes differ in sign), times a fade to zero for
 * pairs closer than eta_crit h, exp(-((eta - eta_crit) / (eta_crit / 5))^2)
 * (Frontiere et al. 2017's eta_crit and eta_fold). eta = r / h. */
static inline real av_limiter(real g_i, real g_j, real eta, real eta_crit)
{
    const real sum = g_i + g_j, fold = (eta - eta_crit) / ((real)0.2 * eta_crit);
    const real phi = g_i * g_j > 0 ? (real)4 * g_i * g_j / (sum * sum) : (real)0;
    return eta < eta_crit ? phi * exp(-fold * fold) : phi;
}

/* v_i - v_j less the limited reconstruction from each side to the midpoint */
static inline vec limited_jump(vec vij, vec xij, real r, real h, real l_i[3][3],
                               __global const fullt *restrict velocity_gradient, int j,
                               __constant const struct sph_run_params *run)
{
    real l_j[3][3], x[3], d_i[3] = {0, 0, 0}, d_j[3] = {0, 0, 0};
    fullt_load(velocity_gradient[j], l_j);
#pragma unroll
    for (int a = 0; a < 3; ++a)
        x[a] = a < SPH_DIM ? vec_get(xij, a) : (real)0;
    matrix_times(l_i, x, d_i);
    matrix_times(l_j, x, d_j);
    real g_i = 0, g_j = 0;
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a) {
        g_i += x[a] * d_i[a];
        g_j += x[a] * d_j[a];
    }
    const real half_phi = (real)0.5 * av_limiter(g_i, g_j, r / h, run->av_eta_crit);
    return vij - half_phi * vec_make(d_i[0] + d_j[0], d_i[1] + d_j[1], d_i[2] + d_j[2]);
}
#endif

static inline real artificial_viscosity(vec vij, vec xij, real r2, real h, real c_mean,
                                        real rho_mean, real alpha, real beta)
{
    const real vr = dot(vij, xij);
    if (vr >= 0)
        return 0;
    const real mu = h * vr / (r2 + (real)0.01 * h * h);
    return (-alpha * c_mean * mu + beta * mu * mu) / rho_mean;
}

__kernel void pass2_momentum_energy(
    __global const vec *restrict pos, __global const vec *restrict pos0,
    __global const vec *restrict vel, __global const real *restrict rho,
    __global const real *restrict mass, __global const real *restrict pressure,
    __global const symt *restrict deviatoric_stress,
    __global const symt *restrict artificial_stress, __global const symt *restrict csph,
    __global const real *restrict sound_speed, __global const fullt *restrict velocity_gradient,
    __global const real *restrict av_alpha, __global const int *restrict flags, GRID_ARGS,
    __constant const struct sph_run_params *run, __global vec *restrict acceleration,
    __global real *restrict energy_rate, __global real *restrict viscous_heating,
    __global vec *restrict xsph_velocity, const int n)
{
    const int i = get_global_id(0);
    if (i >= n || (flags[i] & SPH_FLAG_GHOST))
        return;
    const real q2 = (run->support / run->h) * (run->support / run->h); /* (support / h)^2 */
    const vec xi = pos[i], vi = vel[i];
    const real rho_i = rho[i];
    const real c_i = sound_speed[i];
    real sigma_i[3][3]; /* sigma_i / rho_i */
    total_stress(pressure[i], deviatoric_stress[i], sigma_i);
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b)
            sigma_i[a][b] /= rho_i;
#ifdef SPH_ARTIFICIAL_STRESS
    real r_i[3][3];
    symt_load(artificial_stress[i], r_i);
#else
    (void)artificial_stress;
#endif
#ifdef SPH_CSPH
    real c_i_t[3][3];
    symt_load(csph[i], c_i_t);
#else
    (void)csph;
#endif
#ifdef SPH_AV_LIMITED
    real l_i[3][3];
    fullt_load(velocity_gradient[i], l_i);
#else
    (void)velocity_gradient;
#endif
#ifdef SPH_AV_SWITCH
    /* beta follows alpha in the case's ratio (Morris & Monaghan 1997: beta = 2 alpha) */
    const real alpha_i = av_alpha[i],
               beta_per_alpha = run->av_alpha > 0 ? run->av_beta / run->av_alpha : (real)0;
#else
    (void)av_alpha;
#endif
    real acc[3] = {0, 0, 0};
    real de_viscous = 0, de_stress = 0; /* the two artificial heatings */
    vec xsph = VEC_ZERO;
    FOR_EACH_NEIGHBOUR(i, j)
    {
        const vec xij = xi - pos[j];
        const real r2 = dot(xij, xij);
        const real h = PAIR_H(i, j);
        if (r2 > 0 && r2 < q2 * h * h) { /* excludes i, and a coincident pair (grad W = 0) */
            const real r = sqrt(r2);
            const vec vij = vi - vel[j];
            /* axisymmetric: sigma_i weighed by m_j / r_j, sigma_j by m_j / r_i,
             * the artificial terms by m_j / r_ij (common.cl, pair_mass) */
            const real rho_j = rho[j], m_j = plane_mass(mass[j], pos[j], run);
            const real m_pair = pair_mass(mass[j], xi, pos[j], run);
#ifdef SPH_AXISYMMETRIC
            const real m_j_at_i = mass[j] / axis_radius(xi.x, run);
#else
            const real m_j_at_i = m_j;
#endif
            const real rho_mean = (real)0.5 * (rho_i + rho_j);
#ifdef SPH_AV_LIMITED
            const vec jump = limited_jump(vij, xij, r, h, l_i, velocity_gradient, j, run);
#else
            const vec jump = vij;
#endif
#ifdef SPH_AV_SWITCH
            const real alpha_ij = (real)0.5 * (alpha_i + av_alpha[j]),
                       beta_ij = alpha_ij * beta_per_alpha;
#else
            const real alpha_ij = run->av_alpha, beta_ij = run->av_beta;
#endif
            const real pi_ij = artificial_viscosity(
                jump, xij, r2, h, (real)0.5 * (c_i + sound_speed[j]), rho_mean, alpha_ij, beta_ij);
            const real dwdr_r = kernel_dwdr(r, h) / r;
            /* the viscosity's heating, -1/2 m_j v_ij . (-Pi g): its share of de */
            de_viscous += (real)0.5 * m_pair * pi_ij * dwdr_r * dot(vij, xij);
            real grad[3] = {0, 0, 0}, g_i[3], g_j[3];
#pragma unroll
            for (int a = 0; a < SPH_DIM; ++a)
                grad[a] = dwdr_r * vec_get(xij, a);
#ifdef SPH_CSPH
            transpose_times(c_i_t, grad, g_i);
            symt_transpose_times(csph[j], grad, g_j);
#else
#pragma unroll
            for (int a = 0; a < 3; ++a)
                g_i[a] = g_j[a] = grad[a];
#endif
            /* (sigma_i . g_i + sigma_j . g_j) / (rho_i rho_j) and the
             * artificial terms (f^n (R_i + R_j) - Pi I) . g */
            real t_i[3], t_j[3], extra[3];
            matrix_times(sigma_i, g_i, t_i);
            stress_times(pressure[j], deviatoric_stress[j], g_j, t_j);
#pragma unroll
            for (int a = 0; a < SPH_DIM; ++a)
                extra[a] = -pi_ij * grad[a];
#ifdef SPH_ARTIFICIAL_STRESS
            {
                /* Monaghan's weight (W(r) / W(dx))^n; by default less the same
                 * weight at the pair's initial distance: zero for the
                 * undeformed lattice and for pairs that separate, so the term
                 * acts against clumping only and adds no traction at free
                 * surfaces (weight: lattice keeps Monaghan's original) */
                real fn = artificial_stress_weight(r, h, run);
#ifndef SPH_AS_LATTICE_WEIGHT
                fn =
                    fmax(fn - artificial_stress_weight(length(pos0[i] - pos0[j]), h, run), (real)0);
#endif
                if (fn > 0) {
                    real r_j[3][3], rg[3];
                    symt_load(artificial_stress[j], r_j);
#pragma unroll
                    for (int a = 0; a < SPH_DIM; ++a)
#pragma unroll
                        for (int b = 0; b < SPH_DIM; ++b)
                            r_j[a][b] += r_i[a][b];
                    matrix_times(r_j, grad, rg);
#pragma unroll
                    for (int a = 0; a < SPH_DIM; ++a) {
                        extra[a] += fn * rg[a];
                        de_stress -= (real)0.5 * m_pair * fn * vec_get(vij, a) * rg[a];
                    }
                }
            }
#endif
#pragma unroll
            for (int a = 0; a < SPH_DIM; ++a) /* sigma_i already carries 1 / rho_i */
                acc[a] += (m_j * t_i[a] + m_j_at_i * t_j[a] / rho_i) / rho_j + m_pair * extra[a];
#ifdef SPH_XSPH
            xsph -= (m_j / rho_mean * kernel_w(r, h)) * vij;
#endif
        }
    }
    END_FOR_EACH_NEIGHBOUR
#ifdef SPH_AXISYMMETRIC
    /* The pair sum above is the symmetric SPH form of (1 / eta) div(r sigma)
     * with eta = rho r the ring mass per radian and unit area
     * (sum_j m_j W_ij = eta_i): (sigma_i / r_j + sigma_j / r_i) m_j /
     * (rho_i rho_j) . grad W. Since div sigma in (r, z) is
     * (1 / r) div(r sigma) - sigma_tt / r e_r, only the hoop stress is left
     * as a body force, and it is radial: the axial pair forces cancel
     * exactly, so the axial momentum of target and projectile is conserved
     * (the form with sigma_rr / r and sigma_rz / r source terms of Petschek
     * & Libersky 1993 does not conserve it near the axis). sigma_i holds
     * sigma / rho_i. */
    acc[0] -= sigma_i[2][2] / axis_radius(xi.x, run);
#endif
    acceleration[i] = vec_make(acc[0], acc[1], acc[2]);
    energy_rate[i] = de_viscous + de_stress;
    viscous_heating[i] = de_viscous;
#ifdef SPH_XSPH
    xsph_velocity[i] = run->xsph_epsilon * xsph;
#else
    xsph_velocity[i] = VEC_ZERO;
#endif
}
