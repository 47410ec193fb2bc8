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
 * With SPH_PART_CONTACT a pair of different parts (bodies[].part) carries
 * neither stress, artificial stress nor XSPH, only the viscosity and the
 * contact pressure of part_contact below: the parts push on each other and
 * can part, where one continuum would hold them together (the rubber rings
 * of Gray, Monaghan & Swift 2001 weld and tear otherwise).
 *
 * reads: pos, vel, rho, mass, pressure, deviatoric_stress,
 *        artificial_stress, csph, sound_speed, velocity_gradient (limited),
 *        av_alpha (switch);
 * writes: acceleration, energy_rate, viscous_heating (the viscosity's part
 *         of energy_rate, for the work ledger), xsph_velocity.
 */

#if defined(SPH_GRADED) && defined(SPH_ARTIFICIAL_STRESS)
/* W(dx) (run->as_inv_w_dx) is the finest level's */
#error "graded lattices take no artificial stress (host/case.c)"
#endif

/* Monaghan's (2000) artificial-stress weight (W(r) / W(dx))^n of w = W(r) */
static inline realv artificial_stress_weight(realv w, __constant const struct sph_run_params *run)
{
    const realv f = w * run->as_inv_w_dx;
    realv fn = (realv)1;
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
static inline realv av_limiter(realv g_i, realv g_j, realv eta, real eta_crit)
{
    const realv sum = g_i + g_j, fold = (eta - eta_crit) * ((real)5 / eta_crit);
    const realv phi = SPH_SELECT((realv)0, (real)4 * g_i * g_j / (sum * sum), g_i * g_j > (real)0);
    return SPH_SELECT(phi, phi * exp(-fold * fold), eta < eta_crit);
}

/* v_i - v_j less the limited reconstruction from each side to the
 * midpoint: jump = v_ij - phi / 2 (L_i + L_j) x_ij; eta = r / h */
static inline void limited_jump(realv vij[3], realv xij[3], realv eta, const realv l_i[3][3],
                                __global const fullt *restrict velocity_gradient, int j,
                                __constant const struct sph_run_params *run, realv jump[3])
{
    real l_j[3][3];
    fullt_load(velocity_gradient[j], l_j);
    realv d[3], g_i = (realv)0, g_j = (realv)0;
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a) {
        realv d_i = (realv)0, d_j = (realv)0;
#pragma unroll
        for (int c = 0; c < SPH_DIM; ++c) {
            d_i += l_i[a][c] * xij[c];
            d_j += l_j[a][c] * xij[c];
        }
        g_i += xij[a] * d_i;
        g_j += xij[a] * d_j;
        d[a] = d_i + d_j;
    }
    const realv half_phi = (real)0.5 * av_limiter(g_i, g_j, eta, run->av_eta_crit);
#pragma unroll
    for (int a = 0; a < 3; ++a)
        jump[a] = a < SPH_DIM ? vij[a] - half_phi * d[a] : (realv)0;
}
#endif

/* Pi_ij of an approaching pair (Monaghan 1992 eq. 4.1), 0 for a receding
 * one: vr = v_ij . x_ij (or the limited jump's), r2 = |x_ij|^2. Shared
 * with the total Lagrangian form (total_lagrangian.cl). */
static inline realv artificial_viscosity(realv vr, realv r2, hreal h, realv c_mean,
                                         realv inv_rho_mean, realv alpha, realv beta)
{
    const realv mu = h * vr / (r2 + (real)0.01 * h * h);
    return SPH_SELECT((realv)0, (-alpha * c_mean * mu + beta * mu * mu) * inv_rho_mean,
                      vr < (real)0);
}

/* Pi_ij with the pair's coefficients: the case's alpha and beta, or with
 * SPH_AV_SWITCH the mean of the two particles' alpha (alpha_i the lanes'
 * own), beta in the case's ratio to it, beta_per_alpha (Morris & Monaghan
 * 1997 take 2). Shared with the total Lagrangian form. */
static inline realv pair_artificial_viscosity(realv vr, realv r2, hreal h, realv c_mean,
                                              realv inv_rho_mean, realv alpha_i,
                                              real beta_per_alpha, int j,
                                              __global const real *restrict av_alpha,
                                              __constant const struct sph_run_params *run)
{
#ifdef SPH_AV_SWITCH
    const realv alpha_ij = (real)0.5 * (alpha_i + av_alpha[j]), beta_ij = beta_per_alpha * alpha_ij;
#else
    (void)alpha_i;
    (void)beta_per_alpha;
    (void)j;
    (void)av_alpha;
    const real alpha_ij = run->av_alpha, beta_ij = run->av_beta;
#endif
    return artificial_viscosity(vr, r2, h, c_mean, inv_rho_mean, alpha_ij, beta_ij);
}

/* XSPH's store: eps times the sum, or zero without it */
static inline void store_xsph(__global vec *restrict xsph_velocity, int i, vec sum,
                              __constant const struct sph_run_params *run)
{
#ifdef SPH_XSPH
    xsph_velocity[i] = run->xsph_epsilon * sum;
#else
    (void)sum;
    (void)run;
    xsph_velocity[i] = VEC_ZERO;
#endif
}

/* What pass 2 holds of its own particles, one lane each: the stress as its
 * traction takes the kernel gradient, sigma_g = sigma C^T / rho (C the CSPH
 * correction, else I; 1 / rho_i carried once), so that t_i = sigma_g . g
 * costs one product per pair where C^T g and then sigma . (C^T g) cost two
 * (docs/performance.md, "Fewer products per pair"); and the fields each
 * option reads. */
struct pass2_lanes_i {
    realv x[3], v[3], rho, inv_rho, sigma_g[3][3], c;
#ifdef SPH_AXISYMMETRIC
    realv r, inv_r;    /* axis_radius of x and its reciprocal */
    realv hoop_stress; /* sigma_tt / rho */
#endif
#ifdef SPH_ARTIFICIAL_STRESS
    realv as[3][3];
#ifndef SPH_AS_LATTICE_WEIGHT
    realv x0[3];
#endif
#endif
#ifdef SPH_AV_LIMITED
    realv l[3][3];
#endif
#ifdef SPH_TENSOR_SMOOTHING
    realv metric[3][3], volume_factor; /* tensor_smoothing.cl */
#endif
    realv alpha;         /* SPH_AV_SWITCH: each lane's own alpha (else unused) */
    real beta_per_alpha; /* SPH_AV_SWITCH: the case's beta / alpha */
};

/* The neighbour's mass as the sums weigh it: m_j in the stress term of i
 * (common.cl plane_mass: m_j / r_j in the axisymmetric form), at_i = (the
 * mass the stress term of j takes, m_j / r_i) / m_j, and m_pair in the
 * artificial terms and their heating: in the axisymmetric form m_j / r_ij
 * with the pair's mean radius r_ij = (r_i + |r_j|) / 2, so that the force
 * ring i takes from ring j, m_i m_j / r_ij (...), is exactly minus the one
 * j takes from i and the axial momentum of target and projectile is
 * conserved to round-off (with m_j / r_j the pair forces differ by
 * O(dx / r), which near the axis is O(1)). Elsewhere m_pair = m_j and
 * at_i = 1 exactly.
 * at_radial is at_i for the radial row of the stress term with the ghost's
 * signed radius (ghosts beyond the axis have r_j < 0): the row sums r
 * sigma_rr and r sigma_rz, whose smooth continuations across the axis
 * (odd and even in r) are the ghost's r_j sigma_j, not |r_j| sigma_j. With
 * |r_j| the rings next to the axis take an O(1) radial force error: in the
 * homogeneous expansion of tests/check_homogeneous_flow.py the first
 * ring's hoop stress came out 24% off; with the sign, within 0.5%. The
 * axial row keeps |r_j|: its continuation would be odd too, but only the
 * mirror-symmetric |r_j| makes the axial forces of i on the ghost of k and
 * of k on the ghost of i cancel, which conserves the axial momentum. The
 * first ring's axial force keeps an error there (a plane wave along the
 * axis: behind the front the first ring moves at 12-13% of the impact
 * speed where the others are at rest; with the sign in the axial row too,
 * 2%, but the momentum of an axisymmetric shot then drifts by 1.1% at d/dx
 * 8: docs/results/penetration_session27/axis_plane_wave.yaml). */
#ifdef SPH_AXISYMMETRIC
#define PAIR_MASSES(I, j)                                                                          \
    const real r_j_ = axis_radius(pos[j].x, run), m_j = mass[j] / r_j_;                            \
    const realv m_pair = (real)2 * mass[j] / ((I).r + r_j_), at_i = r_j_ * (I).inv_r,              \
                at_radial = copysign(r_j_, pos[j].x) * (I).inv_r
#else
#define PAIR_MASSES(I, j)                                                                          \
    const real m_j = mass[j], m_pair = m_j, at_i = (real)1, at_radial = (real)1
#endif

/* The switch viscosity's per-lane alpha and the case's beta / alpha (zero
 * without SPH_AV_SWITCH, where pair_artificial_viscosity ignores them). */
static inline void switch_lanes(__global const real *restrict av_alpha, const struct lane_block *b,
                                int n, __constant const struct sph_run_params *run, realv *alpha,
                                real *beta_per_alpha)
{
#ifdef SPH_AV_SWITCH
    *alpha = gather_real(av_alpha, b, n);
    *beta_per_alpha = run->av_alpha > 0 ? run->av_beta / run->av_alpha : (real)0;
#else
    (void)av_alpha;
    (void)b;
    (void)n;
    (void)run;
    *alpha = (realv)0;
    *beta_per_alpha = 0;
#endif
}

static inline void pass2_gather(
    struct pass2_lanes_i *I, const struct lane_block *b, int n, __global const vec *restrict pos,
    __global const vec *restrict pos0, __global const vec *restrict vel,
    __global const real *restrict rho, __global const real *restrict pressure,
    __global const symt *restrict deviatoric_stress,
    __global const symt *restrict artificial_stress, __global const symt *restrict csph,
    __global const real *restrict sound_speed, __global const fullt *restrict velocity_gradient,
    __global const real *restrict av_alpha, __constant const struct sph_run_params *run)
{
    lane_positions(pos, b, n, I->x);
    gather_vec(vel, b, n, I->v);
    I->rho = SPH_SELECT((realv)1, gather_real(rho, b, n), b->live);
    I->inv_rho = (real)1 / I->rho;
    realv sigma[3][3];
    gather_symt(deviatoric_stress, b, n, sigma);
    const realv p = gather_real(pressure, b, n);
#pragma unroll
    for (int a = 0; a < 3; ++a) {
        sigma[a][a] -= p; /* total_stress, lane by lane */
#pragma unroll
        for (int c = 0; c < 3; ++c)
            sigma[a][c] *= I->inv_rho;
    }
#ifdef SPH_CSPH
    realv c_i[3][3];
    gather_symt(csph, b, n, c_i);
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int k = 0; k < 3; ++k) {
            I->sigma_g[a][k] = (realv)0;
#pragma unroll
            for (int c = 0; c < SPH_DIM; ++c)
                I->sigma_g[a][k] += sigma[a][c] * c_i[k][c];
        }
#else
    (void)csph;
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int k = 0; k < 3; ++k)
            I->sigma_g[a][k] = sigma[a][k];
#endif
    I->c = gather_real(sound_speed, b, n);
#ifdef SPH_AXISYMMETRIC
    I->r = fmax(fabs(I->x[0]), run->axis_radius); /* common.cl axis_radius */
    I->inv_r = (real)1 / I->r;
    I->hoop_stress = sigma[2][2];
#else
    (void)run;
#endif
#ifdef SPH_ARTIFICIAL_STRESS
    gather_symt(artificial_stress, b, n, I->as);
#ifndef SPH_AS_LATTICE_WEIGHT
    gather_vec(pos0, b, n, I->x0);
#endif
#else
    (void)artificial_stress;
    (void)pos0;
#endif
#ifdef SPH_AV_LIMITED
    gather_fullt(velocity_gradient, b, n, I->l);
#else
    (void)velocity_gradient;
#endif
    switch_lanes(av_alpha, b, n, run, &I->alpha, &I->beta_per_alpha);
}

/* Pi_ij of the lanes with neighbour j, given vx = v_ij . x_ij: on the
 * pair velocity jump, or with SPH_AV_LIMITED on the jump between the two
 * reconstructions; alpha the case's, or with SPH_AV_SWITCH the pair mean of
 * the particles' (beta in the case's ratio to it). q = r / h. */
static inline realv pass2_viscosity(const struct pass2_lanes_i *I, realv vx, realv vij[3],
                                    realv xij[3], realv q, realv r2, hreal h, realv inv_rho_mean,
                                    int j, __global const real *restrict sound_speed,
                                    __global const fullt *restrict velocity_gradient,
                                    __global const real *restrict av_alpha,
                                    __constant const struct sph_run_params *run)
{
#ifdef SPH_AV_LIMITED
    realv jump[3];
    limited_jump(vij, xij, q, I->l, velocity_gradient, j, run, jump);
    const realv vr = jump[0] * xij[0] + jump[1] * xij[1] + jump[2] * xij[2];
    (void)vx;
#else
    const realv vr = vx;
    (void)vij;
    (void)q;
    (void)velocity_gradient;
#endif
    return pair_artificial_viscosity(vr, r2, h, (real)0.5 * (I->c + sound_speed[j]), inv_rho_mean,
                                     I->alpha, I->beta_per_alpha, j, av_alpha, run);
}

/* The kernel gradient g = grad_i W_ij, and as j's stress sees it: g_j =
 * C_j^T g with CSPH (Bonet & Lok 1999), else g (i's C_i^T is in sigma_g). */
static inline void pass2_gradients(realv dwdr_r, realv xij[3], __global const symt *restrict csph,
                                   int j, realv grad[3], realv g_j[3])
{
#pragma unroll
    for (int a = 0; a < 3; ++a)
        grad[a] = a < SPH_DIM ? dwdr_r * xij[a] : (realv)0;
#ifdef SPH_CSPH
    real c_j[3][3];
    symt_load(csph[j], c_j);
#pragma unroll
    for (int a = 0; a < 3; ++a) {
        g_j[a] = (realv)0;
#pragma unroll
        for (int c = 0; c < SPH_DIM; ++c)
            g_j[a] += c_j[c][a] * grad[c];
    }
#else
    (void)csph;
    (void)j;
#pragma unroll
    for (int a = 0; a < 3; ++a)
        g_j[a] = grad[a];
#endif
}

#ifdef SPH_ARTIFICIAL_STRESS
/* Monaghan's (2000) term f^n (R_i + R_j) . g added to `extra`, and its
 * heating -1/2 m v_ij . (f^n (R_i + R_j) . g) to `de`; w = W(r_ij). f^n by
 * default less the same weight at the pair's initial distance: zero for the
 * undeformed lattice and for pairs that separate, so the term acts against
 * clumping only and adds no traction at free surfaces
 * (SPH_AS_LATTICE_WEIGHT keeps Monaghan's original). */
static inline void pass2_artificial_stress(const struct pass2_lanes_i *I, realv w, hreal inv_h,
                                           realv grad[3], realv vij[3], realv m_pair, int j,
                                           __global const vec *restrict pos0,
                                           __global const symt *restrict artificial_stress,
                                           __constant const struct sph_run_params *run,
                                           realv extra[3], realv *de)
{
    realv fn = artificial_stress_weight(w, run);
#ifndef SPH_AS_LATTICE_WEIGHT
    const vec x0_j = pos0[j];
    realv d0[3];
#pragma unroll
    for (int a = 0; a < 3; ++a)
        d0[a] = a < SPH_DIM ? I->x0[a] - vec_get(x0_j, a) : (realv)0;
    const realv r0 = sqrt(d0[0] * d0[0] + d0[1] * d0[1] + d0[2] * d0[2]);
    fn = fmax(fn - artificial_stress_weight(kernel_w_q(r0 * inv_h, inv_h), run), (realv)0);
#else
    (void)pos0;
    (void)inv_h;
#endif
    real r_j[3][3];
    symt_load(artificial_stress[j], r_j);
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a) {
        realv rg = (realv)0;
#pragma unroll
        for (int c = 0; c < SPH_DIM; ++c)
            rg += (r_j[a][c] + I->as[a][c]) * grad[c];
        extra[a] += fn * rg;
        *de -= (real)0.5 * m_pair * fn * vij[a] * rg;
    }
}
#endif

#ifdef SPH_PART_CONTACT
/* The contact of two parts. For the lanes of another part than j's
 * (`other`, within the support) the stress tractions are dropped and,
 * where the pair is closer than d, the pair's lattice spacing (h dx / h0),
 * a contact pressure acts instead, in the form of the SPH pressure term:
 *   dv_i/dt += m_j 2 p_c / (rho_i rho_j) (-grad W_ij),
 *   p_c = K_ij (1 - r / d) / (2 d^(dim+1) |W'(d)|),
 *   K_ij = (rho_i c_i^2 + rho_j c_j^2) / 2.
 * Two lattices pressed together face to face touch pair by pair, each
 * particle the one opposite it, so the face carries the pressure
 * 2 p_c d^(dim+1) |W'(d)| for the overlap 1 - r / d: the division makes
 * that K times the overlap, a face as stiff as the material whatever the
 * kernel and h / dx (without it 0.53 K in 2-D and 0.33 K in 3-D for
 * Wendland C2 at h = 1.2 dx, and far less for wider kernels, whose
 * gradient at d is small: the rings' Gaussian and quintic runs at h =
 * 2 dx then pressed pairs within dx / 2). The force is antisymmetric
 * (momentum is kept), and its work goes to and comes back from the
 * internal energy, de_i = 1/2 m_j 2 p_c / (rho_i rho_j) v_ij . grad W, as
 * the artificial stress' does, so the energy balance closes. It is added
 * to `extra` as the viscosity's Pi is, with the viscosity's gradient (the
 * mean of the two kernels' with a tensor smoothing length). The viscosity
 * itself acts between parts only where they touch (pass 2 drops it for
 * overlap 0), so that two parts a gap apart do not brake each other.
 * Its limit (docs/validation_contact.md): the kernel's gradient vanishes
 * at r = 0, so the pair force peaks near d / 3 and a pair pushed closer
 * collapses; two elastic steel spheres pressed at Hertz's 28 GPa (a tenth
 * of rho c^2) lose their energy balance in such events at 50 particles a
 * radius. */
/* 2 d^(dim+1) |W'(d)| = 2 d^(dim+2) |(dW/dr) / r| at d = dx h / h0: a
 * number of the kernel and dx / h alone, the same for every pair (graded
 * or not), so each work-item takes it once */
static inline realv part_contact_face(__constant const struct sph_run_params *run)
{
    const real d = run->h * run->av_eta_crit;
    real d_power = d * d * d * d; /* d^(dim+2) */
#if SPH_DIM == 3
    d_power *= d;
#endif
    return (real)-2 * d_power *
           kernel_dwdr_over_r_q((realv)run->av_eta_crit, (hreal)((real)1 / run->h));
}

/* overlap 1 - r / d of a pair, d = h dx / h0 its lattice spacing */
static inline realv part_overlap(realv r2, hreal h, __constant const struct sph_run_params *run)
{
    return fmax((realv)1 - sqrt(r2) / (h * run->av_eta_crit), (realv)0);
}

/* The contact's pair term 2 p_c / (rho_i rho_j) for the overlap 1 - r / d
 * (zero apart) and `face`, part_contact_face. Shared with the total
 * Lagrangian form's contact (kernels/contact_current.cl). */
static inline realv part_contact_term(realv rho_i, realv c_i, realv inv_rho_i, real rho_j, real c_j,
                                      realv overlap, realv face)
{
    const realv stiffness = (real)0.5 * (rho_i * c_i * c_i + rho_j * c_j * c_j);
    return (real)2 * stiffness * overlap * inv_rho_i / (rho_j * face);
}

static inline void part_contact(const struct pass2_lanes_i *I, maskv other, realv overlap,
                                realv face, real rho_j, real c_j, const realv av_grad[3],
                                const realv vij[3], realv m_pair, realv t_i[3], realv t_j[3],
                                realv extra[3], realv *de)
{
    const realv pi_c = SPH_SELECT(
        (realv)0, part_contact_term(I->rho, I->c, I->inv_rho, rho_j, c_j, overlap, face), other);
    realv power = (realv)0;
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a) {
        t_i[a] = SPH_SELECT(t_i[a], (realv)0, other);
        t_j[a] = SPH_SELECT(t_j[a], (realv)0, other);
        extra[a] -= pi_c * av_grad[a];
        power += av_grad[a] * vij[a];
    }
    *de += (real)0.5 * m_pair * pi_c * power;
}
#endif

/* The pair's stress tractions t_i = (sigma_i / rho_i) . C_i^T g =
 * sigma_g . g and t_j = sigma_j . g_j (the 1 / rho_i of t_j and 1 / rho_j
 * of both are applied by the caller), sigma = S - p I. */
static inline void pass2_tractions(const struct pass2_lanes_i *I, real pressure_j, symt dev_j,
                                   const realv grad[3], const realv g_j[3], realv t_i[3],
                                   realv t_j[3])
{
    real sigma_j[3][3];
    total_stress(pressure_j, dev_j, sigma_j);
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a) {
        t_i[a] = t_j[a] = (realv)0;
#pragma unroll
        for (int c = 0; c < SPH_DIM; ++c) {
            t_i[a] += I->sigma_g[a][c] * grad[c];
            t_j[a] += sigma_j[a][c] * g_j[c];
        }
    }
}

/* Each live lane's sums to its particle's acceleration, energy rate (both
 * artificial heatings), viscous heating and XSPH velocity. */
static inline void
pass2_store(const struct lane_block *b, const realv acc[3], const realv xsph[3], realv de_viscous,
            realv de_stress, __global vec *restrict acceleration,
            __global real *restrict energy_rate, __global real *restrict viscous_heating,
            __global vec *restrict xsph_velocity, __constant const struct sph_run_params *run)
{
    for (int l = 0; l < SPH_LANES; ++l) {
        if (!lane_live(b, l))
            continue;
        const int i = b->first + l;
        acceleration[i] = vec_make(lane_of(acc[0], l), lane_of(acc[1], l), lane_of(acc[2], l));
        energy_rate[i] = lane_of(de_viscous + de_stress, l);
        viscous_heating[i] = lane_of(de_viscous, l);
        store_xsph(xsph_velocity, i,
                   vec_make(lane_of(xsph[0], l), lane_of(xsph[1], l), lane_of(xsph[2], l)), run);
    }
}

/* What it reads and writes: the header above. One work-item per lane block
 * (kernels/lanes.cl). With SPH_AXISYMMETRIC the pair sum is the symmetric
 * SPH form of (1 / eta) div(r sigma) with eta = rho r the ring mass per
 * radian and unit area (sum_j m_j W_ij = eta_i): (sigma_i / r_j + sigma_j /
 * r_i) m_j / (rho_i rho_j) . grad W. Since div sigma in (r, z) is (1 / r)
 * div(r sigma) - sigma_tt / r e_r, only the hoop stress is left as a body
 * force, and it is radial: the axial pair forces cancel exactly, so the
 * axial momentum of target and projectile is conserved (the form with
 * sigma_rr / r and sigma_rz / r source terms of Petschek & Libersky 1993
 * does not conserve it near the axis). */
__kernel void pass2_momentum_energy(
    __global const vec *restrict pos, __global const vec *restrict pos0,
    __global const vec *restrict vel, __global const real *restrict rho,
    __global const real *restrict mass, __global const real *restrict pressure,
    __global const symt *restrict deviatoric_stress,
    __global const symt *restrict artificial_stress, __global const symt *restrict csph,
    __global const real *restrict sound_speed, __global const fullt *restrict velocity_gradient,
    __global const real *restrict av_alpha, __global const symt *restrict smoothing_metric,
    __global const int *restrict flags, LANE_GRID_ARGS, __constant const struct sph_run_params *run,
    __global vec *restrict acceleration, __global real *restrict energy_rate,
    __global real *restrict viscous_heating, __global vec *restrict xsph_velocity, const int n)
{
    struct lane_block b;
    if (!lane_block_setup(&b, flags, sort_keys, grid_dims, n))
        return;
    LANE_PASS_CONSTANTS;
    struct pass2_lanes_i I;
    pass2_gather(&I, &b, n, pos, pos0, vel, rho, pressure, deviatoric_stress, artificial_stress,
                 csph, sound_speed, velocity_gradient, av_alpha, run);
#ifdef SPH_TENSOR_SMOOTHING
    metric_lanes(smoothing_metric, &b, n, I.metric, &I.volume_factor);
#else
    (void)smoothing_metric;
#endif
    realv acc[3] = {(realv)0, (realv)0, (realv)0}, xsph[3] = {(realv)0, (realv)0, (realv)0};
    realv de_viscous = (realv)0, de_stress = (realv)0; /* the two artificial heatings */
#ifdef SPH_PART_CONTACT
    const realv parts = lane_parts(flags, &b, n), contact_face = part_contact_face(run);
#endif
    FOR_EACH_LANE_NEIGHBOUR(b, j)
    {
        realv xij[3], r2;
        LANE_PAIR_SUPPORT(b, j);
        const maskv near = lane_pair(I.x, pos[j], support2, xij, &r2);
        if (!lanes_any(near))
            continue;
#ifdef SPH_PART_CONTACT
        const maskv same = SAME_PART(parts, j);
#endif
        LANE_PAIR_INV_H;
        const realv q = sqrt(r2) * inv_h;
#ifdef SPH_TENSOR_SMOOTHING
        struct tensor_pair tp;
        tensor_pair_weights(&tp, I.metric, I.volume_factor, smoothing_metric, j, xij, r2, inv_h, h,
                            near);
        const hreal h_pair = tp.h;
#else
        const hreal h_pair = h;
#endif
        const vec vj = vel[j];
        realv vij[3];
#pragma unroll
        for (int a = 0; a < 3; ++a)
            vij[a] = a < SPH_DIM ? I.v[a] - vec_get(vj, a) : (realv)0;
        const realv vx = vij[0] * xij[0] + vij[1] * xij[1] + vij[2] * xij[2];
        PAIR_MASSES(I, j);
        const real rho_j = rho[j], m_over_rho_j = m_j / rho_j;
        const realv inv_rho_mean = (real)2 / (I.rho + rho_j);
#ifdef SPH_PART_CONTACT
        const maskv other = near & !same;
        const realv overlap = part_overlap(r2, h_pair, run);
        const realv pi_ij =
            SPH_SELECT(pass2_viscosity(&I, vx, vij, xij, q, r2, h_pair, inv_rho_mean, j,
                                       sound_speed, velocity_gradient, av_alpha, run),
                       (realv)0, other & (overlap <= (real)0));
#else
        const realv pi_ij = pass2_viscosity(&I, vx, vij, xij, q, r2, h_pair, inv_rho_mean, j,
                                            sound_speed, velocity_gradient, av_alpha, run);
#endif
        realv grad[3], g_j[3];
#ifdef SPH_TENSOR_SMOOTHING
        /* i's traction takes i's weight, j's j's (C_j in pass2_gradients);
         * the viscosity the pair's mean gradient */
        pass2_gradients(tp.s_j, xij, csph, j, grad, g_j);
#pragma unroll
        for (int a = 0; a < 3; ++a)
            grad[a] = tp.s_i * xij[a];
        const realv *av_grad = tp.mean_gradient;
        de_viscous += (real)0.5 * m_pair * pi_ij *
                      (av_grad[0] * vij[0] + av_grad[1] * vij[1] + av_grad[2] * vij[2]);
#else
        const realv dwdr_r = SPH_SELECT((realv)0, kernel_dwdr_over_r_q(q, inv_h), near);
        pass2_gradients(dwdr_r, xij, csph, j, grad, g_j);
        const realv *av_grad = grad;
        /* the viscosity's heating, -1/2 m v_ij . (-Pi g): its share of de */
        de_viscous += (real)0.5 * m_pair * pi_ij * dwdr_r * vx;
#endif
        /* (sigma_i . g_i + sigma_j . g_j) / (rho_i rho_j) and the
         * artificial terms (f^n (R_i + R_j) - Pi I) . g */
        realv t_i[3], t_j[3], extra[3];
        pass2_tractions(&I, pressure[j], deviatoric_stress[j], grad, g_j, t_i, t_j);
#pragma unroll
        for (int a = 0; a < SPH_DIM; ++a)
            extra[a] = -pi_ij * av_grad[a];
#ifdef SPH_PART_CONTACT
        part_contact(&I, other, overlap, contact_face, rho_j, sound_speed[j], av_grad, vij, m_pair,
                     t_i, t_j, extra, &de_stress);
#endif
#if defined(SPH_TENSOR_SMOOTHING) && defined(SPH_XSPH)
        realv w = tp.w; /* the mean of the two kernels' W */
#elif defined(SPH_ARTIFICIAL_STRESS) || defined(SPH_XSPH)
        realv w = kernel_w_q(q, inv_h); /* W(r_ij) */
#endif
#if defined(SPH_PART_CONTACT) && (defined(SPH_ARTIFICIAL_STRESS) || defined(SPH_XSPH))
        w = SPH_SELECT((realv)0, w, same); /* no artificial stress, no XSPH between parts */
#endif
#ifdef SPH_ARTIFICIAL_STRESS
        pass2_artificial_stress(&I, w, inv_h, grad, vij, m_pair, j, pos0, artificial_stress, run,
                                extra, &de_stress);
#endif
#pragma unroll
        for (int a = 0; a < SPH_DIM; ++a)
            acc[a] += m_over_rho_j * (t_i[a] + t_j[a] * I.inv_rho * (a == 0 ? at_radial : at_i)) +
                      m_pair * extra[a];
#ifdef SPH_XSPH
        const realv w_near = SPH_SELECT((realv)0, w, near);
#pragma unroll
        for (int a = 0; a < SPH_DIM; ++a)
            xsph[a] -= (m_j * inv_rho_mean * w_near) * vij[a];
#endif
    }
    END_FOR_EACH_LANE_NEIGHBOUR
#ifdef SPH_AXISYMMETRIC
    acc[0] -= I.hoop_stress * I.inv_r; /* the hoop stress' body force: see the header */
#endif
    pass2_store(&b, acc, xsph, de_viscous, de_stress, acceleration, energy_rate, viscous_heating,
                xsph_velocity, run);
}
