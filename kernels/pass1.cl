/*
 * Pass 1: velocity gradient, density rate and (with SPH_CSPH) the kernel
 * gradient correction.
 *
 * L_i = sum_j V_j (v_j - v_i) (x) grad_i W_ij, V_j = m_j / rho_j. With CSPH
 * (thesis eqs. 3.10-3.11; Chen et al. 1999, Bonet & Lok 1999) the gradient is
 * corrected so that a linear velocity field is differentiated exactly:
 * B_i = sum_j V_j (x_j - x_i) (x) grad_i W_ij, corrected gradient C_i^T grad W
 * with C_i = B_i^-1 (guarded: kernels/matrix.cl csph_correction), hence
 * L_i <- L_i C_i (one pass suffices because L is linear in the gradient).
 * Density: continuity, drho_i/dt = -rho_i tr(L_i) (plus the out-of-plane
 * strain rate in plane stress).
 * Then each particle's material update (material.cl) with its L_i and
 * density rate, so neither is stored (64 + 4 B per particle in 3-D): it
 * writes only particle i's own state, none of what pass 1 reads of the
 * neighbours (integrate_drift writes the new density).
 *
 * With SPH_AV_LIMITED the (corrected) L_i is also stored, for pass 2's
 * reconstruction of the pair velocity jump (pass2.cl); with
 * SPH_TENSOR_SMOOTHING too, for integrate_drift's update of the metric.
 * With SPH_TENSOR_SMOOTHING each particle sums with its own ellipsoidal
 * kernel's weight and the CSPH correction is tensor_csph_correction's
 * (kernels/tensor_smoothing.cl).
 *
 * With SPH_SPHERE_WALL (projectile.boundary: integral) a particle near the
 * rigid sphere also gets the sphere's share of its sums (sphere_wall.cl).
 * With SPH_PART_CONTACT (bodies of different bodies[].part) a particle sums
 * over its own part only: each part is its own continuum, whose face
 * towards another part is a free surface (pass 2 adds the contact).
 *
 * reads: pos, vel_half, rho, mass, material, flags, energy_rate (and with
 * SPH_SPHERE_WALL projectile_state, deviatoric_stress, pressure);
 * writes: csph, velocity_gradient (SPH_AV_LIMITED); updates: the material
 * state (MATERIAL_STATE_ARGS, the switch viscosity's av_alpha with it).
 */

/* What pass 1 does with particle i's sums, lane by lane:
 * the CSPH correction C_i = B_i^-1 (symmetric, since grad W_ij is along
 * x_ij) applied to L_i, the density rate, and the material update. */
static inline void pass1_finish(
    int i, real grad_v[3][3], real moment[3][3], __global const real *restrict rho,
    __global const int *restrict material, __global const int *restrict flags,
    __constant const struct sph_material *materials, __constant const struct sph_run_params *run,
    __global symt *restrict csph, __global fullt *restrict velocity_gradient,
    __global const symt *restrict smoothing_metric, const real dt, __global const vec *restrict pos,
    __global const vec *restrict vel, MATERIAL_STATE_ARGS)
{
#ifndef SPH_CSPH
    (void)moment;
    (void)csph;
    (void)smoothing_metric;
#endif
#ifdef SPH_CSPH
    real c[3][3], corrected[3][3];
#ifdef SPH_TENSOR_SMOOTHING
    real metric[3][3];
    symt_load(smoothing_metric[i], metric);
    tensor_csph_correction(moment, metric, c);
#else
    (void)smoothing_metric;
    csph_correction(moment, c);
#endif
    matrix_product(grad_v, c, corrected);
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b)
            grad_v[a][b] = corrected[a][b];
    csph[i] = symt_store(c);
#endif
#if defined(SPH_AV_LIMITED) || defined(SPH_TENSOR_SMOOTHING)
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
    material_update_particle(i, grad_v, -rho[i] * divergence, dt, rho, material, flags, pos, vel,
                             materials, run, MATERIAL_STATE);
}

/* What it reads and writes: the header above. One work-item per lane block
 * (kernels/lanes.cl). */
__kernel void pass1_velocity_gradient(
    __global const vec *restrict pos, __global const vec *restrict vel_half,
    __global const real *restrict rho, __global const real *restrict mass,
    __global const int *restrict material, __global const int *restrict flags, LANE_GRID_ARGS,
    __constant const struct sph_material *materials, __constant const struct sph_run_params *run,
    __global symt *restrict csph, __global fullt *restrict velocity_gradient,
    __global const symt *restrict smoothing_metric, const real dt, MATERIAL_STATE_ARGS,
#ifdef SPH_SPHERE_WALL
    __global const real *restrict projectile_state,
#endif
    const int n)
{
    struct lane_block b;
    if (!lane_block_setup(&b, flags, sort_keys, grid_dims, n))
        return;
    LANE_PASS_CONSTANTS;
    realv xi[3], vi[3];
    lane_positions(pos, &b, n, xi);
    gather_vec(vel_half, &b, n, vi);
    realv grad_v[3][3], moment[3][3];
    tensor_zero_v(grad_v);
    tensor_zero_v(moment);
#ifdef SPH_TENSOR_SMOOTHING
    realv metric_i[3][3], volume_factor_i;
    metric_lanes(smoothing_metric, &b, n, metric_i, &volume_factor_i);
#endif
#ifdef SPH_PART_CONTACT
    const realv parts = lane_parts(flags, &b, n);
#endif
    FOR_EACH_LANE_NEIGHBOUR(b, j)
    {
        realv xij[3], r2;
        LANE_PAIR_SUPPORT(b, j);
#ifdef SPH_PART_CONTACT
        const maskv near = lane_pair(xi, pos[j], support2, xij, &r2) & SAME_PART(parts, j);
#else
        const maskv near = lane_pair(xi, pos[j], support2, xij, &r2);
#endif
        if (!lanes_any(near))
            continue;
        LANE_PAIR_INV_H;
        const real volume = plane_mass(mass[j], pos[j], run) / rho[j];
#ifdef SPH_TENSOR_SMOOTHING
        /* i's own ellipsoid: the weight s_i of tensor_smoothing.cl's header */
        const realv dwdr_r = SPH_SELECT(
            (realv)0,
            volume_factor_i * kernel_dwdr_over_r_q(metric_eta_lanes(metric_i, xij, inv_h), inv_h),
            near);
#else
        /* grad_i W_ij = dW/dr x_ij / r; zero for lanes out of reach */
        const realv dwdr_r =
            SPH_SELECT((realv)0, kernel_dwdr_over_r_q(sqrt(r2) * inv_h, inv_h), near);
#endif
        /* V_j grad W = s x_ij: the gradient's scale taken once per pair */
        const realv s = volume * dwdr_r;
        const vec vj = vel_half[j];
        realv vji[3];
#pragma unroll
        for (int a = 0; a < 3; ++a)
            vji[a] = a < SPH_DIM ? vec_get(vj, a) - vi[a] : (realv)0;
        outer_add(grad_v, s, vji, xij);
#ifdef SPH_CSPH
        moment_add(moment, -s, xij);
#endif
    }
    END_FOR_EACH_LANE_NEIGHBOUR
#ifdef SPH_CSPH
    moment_mirror(moment);
#endif
    for (int l = 0; l < SPH_LANES; ++l) {
        if (!lane_live(&b, l))
            continue;
        real gv[3][3], m[3][3];
        tensor_lane(grad_v, l, gv);
        tensor_lane(moment, l, m);
#ifdef SPH_SPHERE_WALL
        sphere_wall_pass1(b.first + l, gv, m, pos, vel_half, flags, deviatoric_stress, pressure,
                          projectile_state, run);
#endif
        pass1_finish(b.first + l, gv, m, rho, material, flags, materials, run, csph,
                     velocity_gradient, smoothing_metric, dt, pos, vel_half, MATERIAL_STATE);
    }
}
