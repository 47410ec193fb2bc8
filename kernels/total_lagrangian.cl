/*
 * Total Lagrangian SPH (numerics.formulation: total_lagrangian) for solids
 * that stay whole: every derivative is taken in the reference configuration
 * (the initial one, or the one of the last numerics.reference_update),
 * over the neighbours a particle had there. Bonet & Lok
 * (1999) and Vidal, Bonet & Huerta (2007) give the formulation; Ganzenmueller
 * (2015, Comput. Methods Appl. Mech. Engrg. 286) the hourglass control.
 * Because neighbours and kernel gradients do not change between updates,
 * the method has no tensile instability (Belytschko et al. 2000) and needs
 * no artificial stress; the price is that it cannot follow fracture or
 * mixing, and each reference update brings back some of the updated form's
 * behaviour (docs/validation_taylor.md).
 * With SPH_PART_CONTACT (bodies of different bodies[].part) a particle's
 * reference neighbours are of its own part only, each part its own
 * continuum; the parts meet through contact_current.cl's contact, searched
 * on the current positions.
 *
 * The neighbour grid is built on the reference positions (the host sorts
 * again only at a reference update) and every pair test uses them.
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
 *                         L = dF/dt F_mid^-1, and with it, particle by
 *                         particle, the same constitutive update as the
 *                         updated form (material.cl) and A^(n+1) for the
 *                         next step's momentum
 * The stress force is the derivative of sum_i V0_i Psi(F_i) with respect to
 * x_i, hence antisymmetric in the pair (momentum is conserved exactly) and
 * work-conjugate to the deformation rate that the material update uses.
 */

#ifdef SPH_TOTAL_LAGRANGIAN
/* V0_j = m_j / rho0_j, rho0 the density of the reference (the material's
 * until a reference update) */
static inline real tl_reference_volume(__global const real *restrict mass,
                                       __global const real *restrict reference_density, int j)
{
    return mass[j] / reference_density[j];
}

/* A = P C^T with P = J sigma F^-T, J = rho0 / rho (the density carries the
 * out-of-plane stretch in plane stress, so J is the volume ratio of the
 * slice), of particle i's stress after its material update. */
static inline fullt tl_first_piola(real rho0_over_rho, real pressure, symt deviatoric_stress,
                                   real f[3][3], real c[3][3])
{
    real sigma[3][3], f_inv[3][3], f_inv_t[3][3], c_t[3][3], p[3][3], a[3][3];
    total_stress(pressure, deviatoric_stress, sigma);
    matrix_invert_or_identity(f, f_inv);
#pragma unroll
    for (int r = 0; r < 3; ++r)
#pragma unroll
        for (int q = 0; q < 3; ++q) {
            f_inv_t[r][q] = f_inv[q][r];
            c_t[r][q] = c[q][r];
        }
    matrix_product(sigma, f_inv_t, p);
    matrix_product(p, c_t, a);
#pragma unroll
    for (int r = 0; r < 3; ++r)
#pragma unroll
        for (int q = 0; q < 3; ++q)
            a[r][q] *= rho0_over_rho;
    return fullt_store(a);
}

/* C_i from the reference lattice, and A_i = P_i C_i^T with F_i = I (the
 * reference is the configuration of now: P = J sigma, J = rho0 / rho);
 * run before the first step and after every reference update
 * (tl_reference_reset), one particle per work-item (ghosts too, so that no
 * slot of the field is left unset; a ghost's C is reflected from its
 * owner's at every refresh).
 * reads: pos0, mass, reference_density, rho, pressure, deviatoric_stress,
 * flags (the parts); writes: csph (C_i), first_piola. */
__kernel void
tl_correction(__global const vec *restrict pos0, __global const real *restrict mass,
              __global const real *restrict reference_density, __global const real *restrict rho,
              __global const real *restrict pressure,
              __global const symt *restrict deviatoric_stress, __global const int *restrict flags,
              GRID_ARGS, __constant const struct sph_run_params *run, __global symt *restrict csph,
              __global fullt *restrict first_piola, const int n)
{
    const int i = get_global_id(0);
    if (i >= n)
        return;
    const real inv_h = (real)1 / run->h, support2 = run->support * run->support;
    const vec xi = pos0[i];
    real moment[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
#ifndef SPH_PART_CONTACT
    (void)flags;
#endif
    FOR_EACH_NEIGHBOUR_WITHIN(i, j, SPH_GRID_SPLIT)
    {
        const vec xij = xi - pos0[j];
        const real r2 = dot(xij, xij);
#ifdef SPH_PART_CONTACT
        if (SPH_PART_OF(flags[j]) != SPH_PART_OF(flags[i]))
            continue; /* another continuum */
#endif
        if (j != i && r2 < support2) {
            /* - V0_j X_ij (x) g_ij: the moment of X_j - X_i */
            const real s = -tl_reference_volume(mass, reference_density, j) *
                           lane_of(kernel_dwdr_over_r_q((realv)(sqrt(r2) * inv_h), inv_h), 0);
#pragma unroll
            for (int p = 0; p < SPH_DIM; ++p)
#pragma unroll
                for (int q = 0; q < SPH_DIM; ++q)
                    moment[p][q] += s * vec_get(xij, p) * vec_get(xij, q);
        }
    }
    END_FOR_EACH_NEIGHBOUR
    real c[3][3];
    csph_correction(moment, c);
    csph[i] = symt_store(c); /* symmetric: grad W_ij is along X_ij */
    real identity[3][3];
    matrix_identity(identity);
    first_piola[i] = tl_first_piola(reference_density[i] / rho[i], pressure[i],
                                    deviatoric_stress[i], identity, c);
}

/* numerics.reference_update: the configuration of now becomes the
 * reference (an updated reference configuration, as LAMMPS' SMD package's
 * total Lagrangian pair style offers for large strains): X := x, u := 0,
 * rho0 := rho, F := I, and the reference offset (X minus the initial
 * position) takes the displacement, so that the reported displacement
 * goes on from the initial position. The stress (Cauchy, integrated with
 * L) and every material variable carry over; the host then sorts, builds
 * the reference neighbours again and runs tl_correction.
 * updates: pos0, displacement, reference_offset, reference_density,
 * deformation_gradient; reads pos, rho. */
__kernel void tl_reference_reset(__global const vec *restrict pos, __global vec *restrict pos0,
                                 __global vec *restrict displacement,
                                 __global vec *restrict reference_offset,
                                 __global const real *restrict rho,
                                 __global real *restrict reference_density,
                                 __global fullt *restrict deformation_gradient, const int n)
{
    const int i = get_global_id(0);
    if (i >= n)
        return;
    reference_offset[i] += displacement[i];
    pos0[i] = pos[i];
    displacement[i] = (vec)0;
    reference_density[i] = rho[i];
    real identity[3][3];
    matrix_identity(identity);
    deformation_gradient[i] = fullt_store(identity);
}

/* x_j - x_i of a pair, as X_j - X_i + (u_j - u_i) from X_ij = X_i - X_j
 * and the displacements: the positions' own differences carry their
 * rounding, one unit in the last place of x (1e-9 m at 1 cm in single
 * precision), which is a strain of 4e-6 at a spacing of 0.25 mm (0.8 MPa
 * in steel); a body at rest then rang at 0.03 m/s and the hourglass
 * springs, stiffer than the material, pumped that noise into the
 * viscosity for ever (0.01 J in 16 us in a free 20 x 2 mm steel bar, none
 * in double precision). The displacement's rounding is that of u, not x;
 * tl_deformation takes F itself as I + grad_X u for the same reason. */
static inline realv tl_current_separation(realv big_xij, real u_j, realv u_i)
{
    return (u_j - u_i) - big_xij;
}

/* The reference pair of the lanes with candidate j: X_ij = X_i - X_j, its
 * square and q0 = |X_ij| / h, the lanes for which j is a reference
 * neighbour (within the support, of the lane's own part: own_part,
 * OWN_PART; not i itself; lanes that are not live sit at LANE_FAR) and
 * g_ij = grad_X W(|X_ij|) with respect to X_i, zero in the other lanes.
 * The mask of the reference pairs never changes, so every candidate's
 * test is the same as at t = 0. */
static inline maskv tl_reference_pair(realv big_xi[3], vec big_xj, maskv own_part, real support2,
                                      real inv_h, realv big_xij[3], realv *r02, realv *q0,
                                      realv grad[3])
{
    const maskv near = lane_pair(big_xi, big_xj, support2, big_xij, r02) & own_part;
    *q0 = sqrt(*r02) * inv_h;
    const realv dwdr_r = SPH_SELECT((realv)0, kernel_dwdr_over_r_q(*q0, inv_h), near);
#pragma unroll
    for (int a = 0; a < 3; ++a)
        grad[a] = dwdr_r * big_xij[a];
    return near;
}

/* The end of tl_deformation for one particle: F^(n+1) = I + (sum_u) C_i +
 * dt dF/dt with dF/dt = (sum_w) C_i, L = dF/dt F_mid^-1, the material
 * update with L (material.cl) and A^(n+1) for the next step's momentum.
 * It writes only particle i's own state, none of what tl_deformation
 * reads of the neighbours. */
static inline void tl_deformation_finish(
    int i, real sum_u[3][3], real sum_w[3][3], const real dt, __global const symt *restrict csph,
    __global real *restrict rho, __global const real *restrict reference_density,
    __global const int *restrict material, __global const int *restrict flags,
    __global const vec *restrict pos, __global const vec *restrict vel_half,
    __constant const struct sph_material *materials, __constant const struct sph_run_params *run,
    __global fullt *restrict deformation_gradient, __global fullt *restrict first_piola,
    MATERIAL_STATE_ARGS)
{
    real c[3][3], f[3][3], f_rate[3][3], f_mid[3][3], f_mid_inv[3][3], l[3][3];
    symt_load(csph[i], c);
    /* F = I + H, H = sum_j V0_j (u_j - u_i) (x) g_ij C_i: the same as
     * sum_j V0_j (x_j - x_i) (x) g_ij C_i where C_i inverts the reference
     * moment exactly, but I is exact where B C is I only to rounding (a
     * body at rest kept a strain of that rounding, 0.002 m/s in a free
     * steel bar), and where C_i fell back to I (matrix_invert_or_identity)
     * a body at rest keeps F = I instead of the uncorrected moment */
    matrix_product(sum_u, c, f);
    matrix_product(sum_w, c, f_rate);
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b) {
            f[a][b] += a == b ? (real)1 : (real)0;
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
    deformation_gradient[i] = fullt_store(f);
    const real rho_new =
        material_update_particle(i, l, -rho[i] * divergence, dt, rho, material, flags, pos,
                                 vel_half, materials, run, MATERIAL_STATE);
    rho[i] = rho_new;
    first_piola[i] =
        tl_first_piola(reference_density[i] / rho_new, pressure[i], deviatoric_stress[i], f, c);
}

/* F^n from the displacements u^n (F = I + grad_X u), and its rate from the
 * motion of this step,
 * w = v^(n+1/2) + v_xsph (the velocity integrate_drift moves particles
 * with), so that F^(n+1) = F^n + dt dF/dt is exactly the gradient of
 * x^(n+1). The material update gets L = dF/dt (F^n + dt/2 dF/dt)^-1, the
 * mid-step velocity gradient. One work-item per lane block
 * (kernels/lanes.cl); the blocks walk the reference grid.
 * reads: pos (the material update's), displacement, pos0, vel_half,
 * xsph_velocity, mass, reference_density, rho, material, flags, csph,
 * energy_rate; writes: deformation_gradient (F^(n+1)), rho, first_piola;
 * updates: the material state (MATERIAL_STATE_ARGS). */
__kernel void
tl_deformation(__global const vec *restrict pos, __global const vec *restrict displacement,
               __global const vec *restrict pos0, __global const vec *restrict vel_half,
               __global const vec *restrict xsph_velocity, __global const real *restrict mass,
               __global const real *restrict reference_density, __global real *restrict rho,
               __global const int *restrict material, __global const int *restrict flags,
               LANE_GRID_ARGS, __constant const struct sph_material *materials,
               __constant const struct sph_run_params *run, __global const symt *restrict csph,
               const real dt, __global fullt *restrict deformation_gradient,
               __global fullt *restrict first_piola, MATERIAL_STATE_ARGS, const int n)
{
    struct lane_block b;
    if (!lane_block_setup(&b, flags, sort_keys, grid_dims, n))
        return;
    LANE_PASS_CONSTANTS;
    realv big_xi[3], ui[3], wi[3], xsph_i[3];
    lane_positions(pos0, &b, n, big_xi);
    gather_vec(displacement, &b, n, ui);
    gather_vec(vel_half, &b, n, wi);
    gather_vec(xsph_velocity, &b, n, xsph_i);
#pragma unroll
    for (int a = 0; a < 3; ++a)
        wi[a] += xsph_i[a];
#ifdef SPH_PART_CONTACT
    const realv parts = lane_parts(flags, &b, n);
#endif
    realv sum_u[3][3], sum_w[3][3];
    tensor_zero_v(sum_u);
    tensor_zero_v(sum_w);
    FOR_EACH_LANE_NEIGHBOUR(b, j)
    {
        realv big_xij[3], r02, q0, grad[3];
        if (!lanes_any(tl_reference_pair(big_xi, pos0[j], OWN_PART(parts, j), support2, inv_h,
                                         big_xij, &r02, &q0, grad)))
            continue;
        const real volume = tl_reference_volume(mass, reference_density, j);
        const vec uj = displacement[j], wj = vel_half[j] + xsph_velocity[j];
        realv u[3], w[3];
#pragma unroll
        for (int a = 0; a < 3; ++a) {
            u[a] = a < SPH_DIM ? vec_get(uj, a) - ui[a] : (realv)0;
            w[a] = a < SPH_DIM ? vec_get(wj, a) - wi[a] : (realv)0;
        }
        outer_add(sum_u, volume, u, grad);
        outer_add(sum_w, volume, w, grad);
    }
    END_FOR_EACH_LANE_NEIGHBOUR(void) h;
    for (int l = 0; l < SPH_LANES; ++l) {
        if (!lane_live(&b, l))
            continue;
        real sx[3][3], sw[3][3];
        tensor_lane(sum_u, l, sx);
        tensor_lane(sum_w, l, sw);
        tl_deformation_finish(b.first + l, sx, sw, dt, csph, rho, reference_density, material,
                              flags, pos, vel_half, materials, run, deformation_gradient,
                              first_piola, MATERIAL_STATE);
    }
}

/* What tl_momentum holds of its own particles, one lane each. */
struct tl_lanes_i {
    realv x0[3], u[3], v[3], a[3][3], f[3][3], rho, c; /* u: displacement */
    realv hourglass;     /* the hourglass stiffness alpha E / rho0_i (tl_momentum) */
    realv alpha;         /* SPH_AV_SWITCH: each lane's own alpha (else unused) */
    real beta_per_alpha; /* SPH_AV_SWITCH: the case's beta / alpha */
};

static inline void tl_gather(
    struct tl_lanes_i *I, const struct lane_block *b, int n,
    __global const vec *restrict displacement, __global const vec *restrict pos0,
    __global const vec *restrict vel, __global const real *restrict rho,
    __global const real *restrict reference_density, __global const fullt *restrict first_piola,
    __global const fullt *restrict deformation_gradient, __global const real *restrict sound_speed,
    __global const int *restrict material, __global const real *restrict av_alpha,
    __constant const struct sph_material *materials, __constant const struct sph_run_params *run)
{
    lane_positions(pos0, b, n, I->x0);
    gather_vec(displacement, b, n, I->u);
    gather_vec(vel, b, n, I->v);
    gather_fullt(first_piola, b, n, I->a);
    gather_fullt(deformation_gradient, b, n, I->f);
    I->rho = SPH_SELECT((realv)1, gather_real(rho, b, n), b->live);
    I->c = gather_real(sound_speed, b, n);
    /* alpha E / rho0_i, E = 9 K G / (3 K + G), rho0 the reference's (so
     * that m_i times it times V0_j, the pair's force, is the same from
     * either side after a reference update) */
    lanes_union hourglass;
    for (int l = 0; l < SPH_LANES; ++l) {
        const int i = b->first + l < n ? b->first + l : b->first;
        __constant const struct sph_material *m = &materials[material[i]];
        hourglass.s[l] = run->hourglass * (real)9 * m->bulk_modulus * m->shear_modulus /
                         (((real)3 * m->bulk_modulus + m->shear_modulus) * reference_density[i]);
    }
    I->hourglass = hourglass.v;
    switch_lanes(av_alpha, b, n, run, &I->alpha, &I->beta_per_alpha);
}

/* Hourglass control (after Ganzenmueller 2015, eqs. 18-20): the pair
 * separation predicted by the mean deformation gradient of the two
 * particles, p_ij = F_ij X_ij with F_ij = (F_i + F_j) / 2, is compared with
 * the actual x_ij, and the whole mismatch p_ij - x_ij (zero for every
 * linear displacement field, so it adds no stiffness to a homogeneous
 * deformation) is pulled back by a pair force of alpha E V0_i V0_j W(X_ij) /
 * X_ij^2 per metre of mismatch: a linear spring between x_ij and p_ij.
 * Ganzenmueller's force keeps only the mismatch's component along x_ij and
 * acts along x_ij (a central force). That force, repulsive on a pair closer
 * than predicted, has a transverse stiffness of -|force| / |x_ij|, which
 * grows without bound as a pair comes together. After reference updates
 * the 3-D copper rod at 0.2 mm has pairs 0.1 dx apart on its face; with
 * the central force two of its particles oscillated about a fixed place
 * at up to 570 m/s, gathered a plastic strain of 50 and took 3.4% of the
 * energy, and with this spring they do not (that the transverse
 * stiffness drove them is the explanation, not measured pair by pair:
 * docs/validation_taylor.md, "The hourglass spring on the whole
 * mismatch"). The spring on the whole
 * mismatch has the stiffness alpha E V0 V0 W / X^2 in every direction
 * whatever |x_ij|; its pair forces are equal and opposite (momentum is
 * conserved) but not along x_ij, so it exerts a couple x_ij x f_ij, of
 * the order of the mismatch, on non-linear motion.
 * X_ij^2 is taken no smaller than the lattice spacing's square: on the
 * first lattice no pair is closer, but a reference taken by
 * numerics.reference_update from a body squashed threefold has pairs at
 * dx / 3, whose springs are nine times stiffer. With the central spring
 * that mattered (the 3-D 42CrMo4 bar at 0.4 mm: the springs fed 2-16% of
 * the impact energy into the motion at alpha 0.1-0.3, and blew up at
 * 0.01); with this spring it has not been shown to (without the floor the
 * same bar at alpha 0.01 / 0.1 / 0.3 and the copper rod at 0.2 mm close
 * their energy to 0.24% and 0.13%, as with it), so it stays as a bound on
 * a spring's stiffness, not as a measured necessity.
 * Adds that force over m_i (an acceleration) to acc and its power
 * -1/2 v_ij . a to power, in the lanes of `near`. */
static inline void tl_hourglass(const struct tl_lanes_i *I, fullt f_j_packed, const realv xij[3],
                                const realv big_xij[3], realv r02, realv w0, real volume_j,
                                real spacing2, const realv vij[3], maskv near, realv acc[3],
                                realv *power)
{
    real f_j[3][3];
    fullt_load(f_j_packed, f_j);
    const realv stiffness =
        SPH_SELECT((realv)0, I->hourglass * volume_j * w0 / fmax(r02, (realv)spacing2), near);
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a) {
        realv predicted = (realv)0;
#pragma unroll
        for (int c = 0; c < SPH_DIM; ++c)
            predicted += (real)0.5 * (I->f[a][c] + f_j[a][c]) * big_xij[c];
        /* a pair closer than predicted (predicted - x_ij along x_ij) pushes i away */
        const realv pull = stiffness * (predicted - xij[a]);
        acc[a] += pull;
        *power -= (real)0.5 * vij[a] * pull;
    }
}

/* The artificial viscosity on the current pair geometry, as in the updated
 * form: adds -m_j Pi_ij grad W(x_ij) to acc, its heating to de and the
 * XSPH sum, in the lanes whose pair is within the support now. */
static inline void
tl_viscosity(const struct tl_lanes_i *I, const realv xij[3], const realv vij[3], real support2,
             real h, real inv_h, int j, __global const real *restrict mass,
             __global const real *restrict rho, __global const real *restrict sound_speed,
             __global const real *restrict av_alpha, __constant const struct sph_run_params *run,
             maskv reference, realv acc[3], realv *de, realv xsph[3])
{
    const realv r2 = xij[0] * xij[0] + xij[1] * xij[1] + xij[2] * xij[2];
    const maskv near = reference & (r2 < support2) & (r2 > (real)0);
    if (!lanes_any(near))
        return;
    const realv q = sqrt(r2) * inv_h, inv_rho_mean = (real)2 / (I->rho + rho[j]);
    const realv vx = vij[0] * xij[0] + vij[1] * xij[1] + vij[2] * xij[2];
    const realv pi_ij =
        pair_artificial_viscosity(vx, r2, h, (real)0.5 * (I->c + sound_speed[j]), inv_rho_mean,
                                  I->alpha, I->beta_per_alpha, j, av_alpha, run);
    const realv s = SPH_SELECT((realv)0, -mass[j] * pi_ij * kernel_dwdr_over_r_q(q, inv_h), near);
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a)
        acc[a] += s * xij[a];
    *de -= (real)0.5 * s * vx;
#ifdef SPH_XSPH
    const realv w = SPH_SELECT((realv)0, mass[j] * inv_rho_mean * kernel_w_q(q, inv_h), near);
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a)
        xsph[a] -= w * vij[a];
#else
    (void)xsph;
    (void)run;
#endif
}

/* Each live lane's sums to its particle's acceleration, energy rate,
 * hourglass power and XSPH velocity. */
static inline void
tl_momentum_store(const struct lane_block *b, const realv acc[3], const realv acc_extra[3],
                  realv de, realv hourglass_rate, const realv xsph[3],
                  __global const real *restrict reference_density,
                  __constant const struct sph_run_params *run, __global vec *restrict acceleration,
                  __global real *restrict energy_rate, __global real *restrict viscous_heating,
                  __global real *restrict hourglass_power, __global vec *restrict xsph_velocity)
{
    for (int l = 0; l < SPH_LANES; ++l) {
        if (!lane_live(b, l))
            continue;
        const int i = b->first + l;
        const real inv_rho0 = (real)1 / reference_density[i];
        acceleration[i] =
            inv_rho0 * vec_make(lane_of(acc[0], l), lane_of(acc[1], l), lane_of(acc[2], l)) +
            vec_make(lane_of(acc_extra[0], l), lane_of(acc_extra[1], l), lane_of(acc_extra[2], l));
        energy_rate[i] = lane_of(de, l);
        viscous_heating[i] = lane_of(de, l); /* no other artificial heating in this form */
        hourglass_power[i] = lane_of(hourglass_rate, l);
        store_xsph(xsph_velocity, i,
                   vec_make(lane_of(xsph[0], l), lane_of(xsph[1], l), lane_of(xsph[2], l)), run);
    }
}

/* Pass 2 of the total Lagrangian form: stress force, artificial viscosity
 * (on the current pair geometry, as in the updated form), hourglass control,
 * XSPH. One work-item per lane block (kernels/lanes.cl).
 * reads: displacement, pos0, vel, rho, mass, reference_density, first_piola,
 * deformation_gradient,
 * sound_speed, material, av_alpha (SPH_AV_SWITCH: the pair's alpha is the
 * mean of the particles', beta in the case's ratio to it, as in pass 2);
 * writes: acceleration, energy_rate, viscous_heating
 * (the viscosity's part of energy_rate), hourglass_power (W/kg: the work
 * the hourglass forces take out of the motion, -1/2 sum_j v_ij . a_hg,ij,
 * which is not heat and is kept apart for the energy ledger), xsph_velocity. */
__kernel void tl_momentum(
    __global const vec *restrict displacement, __global const vec *restrict pos0,
    __global const vec *restrict vel, __global const real *restrict rho,
    __global const real *restrict mass, __global const real *restrict reference_density,
    __global const fullt *restrict first_piola, __global const fullt *restrict deformation_gradient,
    __global const real *restrict sound_speed, __global const int *restrict material,
    __global const int *restrict flags, __global const real *restrict av_alpha, LANE_GRID_ARGS,
    __constant const struct sph_material *materials, __constant const struct sph_run_params *run,
    __global vec *restrict acceleration, __global real *restrict energy_rate,
    __global real *restrict viscous_heating, __global real *restrict hourglass_power,
    __global vec *restrict xsph_velocity, const int n)
{
    struct lane_block b;
    if (!lane_block_setup(&b, flags, sort_keys, grid_dims, n))
        return;
    LANE_PASS_CONSTANTS;
    struct tl_lanes_i I;
    tl_gather(&I, &b, n, displacement, pos0, vel, rho, reference_density, first_piola,
              deformation_gradient, sound_speed, material, av_alpha, materials, run);
    realv acc[3] = {(realv)0, (realv)0, (realv)0};       /* the stress force times rho0_i */
    realv acc_extra[3] = {(realv)0, (realv)0, (realv)0}; /* viscosity, hourglass */
    realv xsph[3] = {(realv)0, (realv)0, (realv)0};
    realv de = (realv)0, hourglass_rate = (realv)0;
    const real spacing = run->h * run->av_eta_crit, spacing2 = spacing * spacing; /* dx^2 */
#ifdef SPH_PART_CONTACT
    const realv parts = lane_parts(flags, &b, n);
#endif
    FOR_EACH_LANE_NEIGHBOUR(b, j)
    {
        realv big_xij[3], r02, q0, grad[3];
        const maskv reference = tl_reference_pair(I.x0, pos0[j], OWN_PART(parts, j), support2,
                                                  inv_h, big_xij, &r02, &q0, grad);
        if (!lanes_any(reference))
            continue;
        const real volume_j = tl_reference_volume(mass, reference_density, j);
        real a_j[3][3];
        fullt_load(first_piola[j], a_j);
        /* V0_j (A_i + A_j) g_ij */
#pragma unroll
        for (int a = 0; a < SPH_DIM; ++a) {
            realv stress_force = (realv)0;
#pragma unroll
            for (int c = 0; c < SPH_DIM; ++c)
                stress_force += (I.a[a][c] + a_j[a][c]) * grad[c];
            acc[a] += volume_j * stress_force;
        }
        const vec uj = displacement[j], vj = vel[j];
        realv xij[3], vij[3];
#pragma unroll
        for (int a = 0; a < 3; ++a) {
            xij[a] =
                a < SPH_DIM ? -tl_current_separation(big_xij[a], vec_get(uj, a), I.u[a]) : (realv)0;
            vij[a] = a < SPH_DIM ? I.v[a] - vec_get(vj, a) : (realv)0;
        }
        tl_viscosity(&I, xij, vij, support2, h, inv_h, j, mass, rho, sound_speed, av_alpha, run,
                     reference, acc_extra, &de, xsph);
        if (run->hourglass > 0)
            tl_hourglass(&I, deformation_gradient[j], xij, big_xij, r02, kernel_w_q(q0, inv_h),
                         volume_j, spacing2, vij, reference, acc_extra, &hourglass_rate);
    }
    END_FOR_EACH_LANE_NEIGHBOUR
    tl_momentum_store(&b, acc, acc_extra, de, hourglass_rate, xsph, reference_density, run,
                      acceleration, energy_rate, viscous_heating, hourglass_power, xsph_velocity);
}

#endif /* SPH_TOTAL_LAGRANGIAN */
