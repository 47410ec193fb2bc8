/*
 * The rigid sphere as a boundary of the target's sums
 * (projectile.boundary: integral, -DSPH_SPHERE_WALL; an experiment beside
 * the penalty contact of projectile.cl, which stays as a backstop).
 *
 * A target particle near the sphere has part of its kernel support inside
 * the sphere, where there are no particles: its sums lack that part.
 * Here the sphere's volume Omega is taken as continuous matter whose
 * contribution to particle i's sums is an integral over Omega, known in
 * closed form up to one radial quadrature (a semi-analytic wall in the
 * sense of Kulasegaram et al. 2004, IJNME 61:2421, and Ferrand et al.
 * 2013, IJNMF 71:446, for a sphere instead of a plane):
 *
 *   grad Phi = int_Omega grad_x W(x - y) dy = Phi'(d) n,
 *   M        = int_Omega (y - x) (x) grad_x W(x - y) dy
 *            = A n (x) n + B (I - n (x) n),
 *
 * with d the distance of x from the sphere's centre and n the outward
 * unit vector there. Over shells of radius r about x the fraction of the
 * shell inside Omega is a cap about -n of half-angle theta_0, cos theta_0
 * = c(r) = (d^2 + r^2 - R^2) / (2 d r) (clamped to [-1, 1]):
 *   3-D: Phi' = pi int r^2 W' (1 - c^2) dr,
 *        A = -(2 pi / 3) int r^3 W' (1 - c^3) dr,
 *        B = -pi int r^3 W' ((1 - c) - (1 - c^3) / 3) dr;
 *   2-D (the disc; also the axisymmetric meridian plane, where a
 *   particle's volume is its area, plane_mass / rho):
 *        Phi' = 2 int r W' sin theta_0 dr,
 *        A = -int r^2 W' (theta_0 + c sin theta_0) dr,
 *        B = -int r^2 W' (theta_0 - c sin theta_0) dr.
 * Over the whole space (c = -1) A = B = 1 and Phi' = 0: the kernel's
 * normalisation (tests/test_sphere_wall.c checks these, and the integrals
 * against brute-force sums).
 *
 * What the sums get (free slip, unilateral):
 *   pass 1: the CSPH moment matrix gets M, and the velocity gradient the
 *   mirror image's motion, 2 ((V - v_i).n) Phi' n (x) n: the image of
 *   particle i in the sphere's tangent plane moves with i's tangential
 *   velocity and mirrors its normal velocity about the sphere's, as the
 *   images at a symmetry plane do (kernels/ghost.cl), so a particle
 *   closing on the sphere is compressed by its own approach;
 *   projectile_contact: the force (sigma_i + sigma_w) . C_i grad Phi / rho_i
 *   with sigma_w the particle's stress mirrored in the sphere's tangent
 *   plane (no shear traction: free slip), and minus it on the sphere.
 *   With both mirrored the pair conserves energy as the pairs with
 *   symmetry-plane images do: the force's work on i relative to the
 *   sphere equals the stress work of the velocity-gradient term (each is
 *   2 sigma_nn Phi' (v_i - V).n / rho_i with C = I); what is left (from C
 *   and from the two terms' half-step offset) is counted as dissipated.
 * Only while in contact: the normal stress n.sigma_i.n compressive, or the
 * particle closing on the sphere; a particle in tension or separating sees
 * a free surface, as without the sphere.
 */

/* The wall's normal velocity in pass 1, as a multiple of the approach:
 * 2 the mirror image's (the default: energy-conserving), 1 the sphere's
 * own (the wall moving rigidly, as Adami et al. 2012's continuity term has
 * it; it leaves 6-18% of the impact energy unaccounted for in the gel
 * shots, docs/validation_penetration.md). -DSPH_SPHERE_WALL_IMAGE=1 in
 * SPH_BUILD_OPTIONS for comparisons. */
#ifndef SPH_SPHERE_WALL_IMAGE
#define SPH_SPHERE_WALL_IMAGE 2
#endif

#if defined(SPH_SPHERE_WALL) || !defined(__OPENCL_VERSION__)
/* (the integrals compile on the host too: tests/test_sphere_wall.c) */

/* The integrals above for a particle at distance d from the centre of a
 * sphere (disc in 2-D) of radius R, with smoothing length h, for smoothing
 * kernel `type` in `dim` dimensions (compile-time constants on the device). */
struct sphere_wall_moments {
    real dphi, normal, tangent; /* Phi' (1/m), A, B */
};

/* the integrands at shell radius r */
static inline void sphere_wall_integrand(int type, int dim, real r, real d, real radius, real h,
                                         real out[3])
{
    const real c =
        fmin(fmax((d * d + r * r - radius * radius) / ((real)2 * d * r), (real)-1), (real)1);
    const real w1 = sph_kernel_dwdr(type, dim, r, h);
    if (dim == 3) {
        out[0] = (real)SPH_PI * r * r * w1 * ((real)1 - c * c);
        out[1] = -((real)2 * (real)SPH_PI / (real)3) * r * r * r * w1 * ((real)1 - c * c * c);
        out[2] = -(real)SPH_PI * r * r * r * w1 * (((real)1 - c) - ((real)1 - c * c * c) / (real)3);
    } else {
        const real theta = acos(c), s = sqrt(fmax((real)1 - c * c, (real)0));
        out[0] = (real)2 * r * w1 * s;
        out[1] = -r * r * w1 * (theta + c * s);
        out[2] = -r * r * w1 * (theta - c * s);
    }
}

/* Gauss-Legendre, 8 points on [a, b], added to sum */
static inline void sphere_wall_quadrature(int type, int dim, real a, real b, real d, real radius,
                                          real h, real sum[3])
{
    if (b <= a)
        return;
    const real x[4] = {(real)0.1834346424956498, (real)0.5255324099163290, (real)0.7966664774136267,
                       (real)0.9602898564975363};
    const real w[4] = {(real)0.3626837833783620, (real)0.3137066458778873, (real)0.2223810344533745,
                       (real)0.1012285362903763};
    const real mid = (real)0.5 * (a + b), half_width = (real)0.5 * (b - a);
    for (int k = 0; k < 4; ++k)
        for (int side = -1; side <= 1; side += 2) {
            real f[3];
            sphere_wall_integrand(type, dim, mid + side * half_width * x[k], d, radius, h, f);
            for (int q = 0; q < 3; ++q)
                sum[q] += half_width * w[k] * f[q];
        }
}

static inline struct sphere_wall_moments sphere_wall_integrals(int type, int dim, real d,
                                                               real radius, real h)
{
    const real support = sph_kernel_support_q(type) * h;
    real sum[3] = {0, 0, 0};
    const real lo = fmax(d - radius, (real)0), hi = fmin(d + radius, support);
    /* pieces between the kinks of the integrand: r = R - d (the shells
     * wholly inside the sphere end there, for a centre inside it) and the
     * piecewise kernels' joints at r = h and 2 h */
    real cut[5] = {lo, fmin(fmax(radius - d, lo), hi), fmin(fmax(h, lo), hi),
                   fmin(fmax((real)2 * h, lo), hi), hi};
    for (int a = 1; a < 4; ++a) /* sort the three inner cuts */
        for (int b = a + 1; b < 4; ++b)
            if (cut[b] < cut[a]) {
                const real t = cut[a];
                cut[a] = cut[b];
                cut[b] = t;
            }
    for (int piece = 0; piece < 4; ++piece)
        sphere_wall_quadrature(type, dim, cut[piece], cut[piece + 1], d, radius, h, sum);
    struct sphere_wall_moments m = {sum[0], sum[1], sum[2]};
    return m;
}
#endif

#ifdef SPH_SPHERE_WALL

/* The sphere's centre, velocity (slots of kernels/projectile.cl's state)
 * and particle i's outward normal and distance from the centre. */
static inline real sphere_wall_geometry(__global const real *restrict state, vec x, real n[3],
                                        real sphere_v[3])
{
    real d2 = 0, rel[3];
    for (int a = 0; a < 3; ++a) {
        rel[a] = a < SPH_DIM ? vec_get(x, a) - state[SPH_PROJ_X + a] : (real)0;
        sphere_v[a] = a < SPH_DIM ? state[SPH_PROJ_V + a] : (real)0;
        d2 += rel[a] * rel[a];
    }
    const real d = sqrt(d2);
    for (int a = 0; a < 3; ++a)
        n[a] = d > 0 ? rel[a] / d : (real)0;
    return d;
}

/* What both wall terms need of particle i: its distance d from the
 * sphere's centre, the outward normal n, the sphere's velocity, the
 * closing speed (V - v_i).n, its stress sigma = s - p I and n.sigma.n, and
 * whether it is in contact: within its support of the surface, and
 * pressed (n.sigma.n < 0) or closing. */
struct sphere_wall_particle {
    real d, n[3], sphere_v[3], closing, sigma[3][3], normal_stress, h;
    int contact;
};

static inline struct sphere_wall_particle
sphere_wall_particle(int i, __global const vec *restrict pos, __global const vec *restrict vel,
                     __global const int *restrict flags,
                     __global const symt *restrict deviatoric_stress,
                     __global const real *restrict pressure, __global const real *restrict state,
                     __constant const struct sph_run_params *run)
{
    struct sphere_wall_particle p;
    p.d = sphere_wall_geometry(state, pos[i], p.n, p.sphere_v);
    p.h = run->h * spacing_scale(flags[i]);
    p.closing = 0;
    p.normal_stress = 0;
    p.contact = 0;
    /* most particles are out of reach: no stress read for them */
    if (!(p.d > 0 && p.d < run->sphere_radius + sph_kernel_support_q(SPH_KERNEL) * p.h))
        return p;
    const vec v = vel[i];
    for (int a = 0; a < SPH_DIM; ++a)
        p.closing += (p.sphere_v[a] - vec_get(v, a)) * p.n[a];
    symt_load(deviatoric_stress[i], p.sigma);
    for (int a = 0; a < 3; ++a)
        p.sigma[a][a] -= pressure[i];
    for (int a = 0; a < SPH_DIM; ++a)
        for (int b = 0; b < SPH_DIM; ++b)
            p.normal_stress += p.n[a] * p.sigma[a][b] * p.n[b];
    p.contact = p.normal_stress < 0 || p.closing > 0;
    return p;
}

/* Pass 1's wall terms for particle i (above): the moment matrix's M and the
 * velocity gradient's wall motion, before the CSPH inverse. */
static inline void sphere_wall_pass1(
    int i, real grad_v[3][3], real moment[3][3], __global const vec *restrict pos,
    __global const vec *restrict vel, __global const int *restrict flags,
    __global const symt *restrict deviatoric_stress, __global const real *restrict pressure,
    __global const real *restrict projectile_state, __constant const struct sph_run_params *run)
{
    const struct sphere_wall_particle p = sphere_wall_particle(
        i, pos, vel, flags, deviatoric_stress, pressure, projectile_state, run);
    if (!p.contact)
        return;
    const struct sphere_wall_moments m =
        sphere_wall_integrals(SPH_KERNEL, SPH_DIM, p.d, run->sphere_radius, p.h);
    for (int a = 0; a < SPH_DIM; ++a)
        for (int b = 0; b < SPH_DIM; ++b) {
            const real nn = p.n[a] * p.n[b];
            moment[a][b] += m.normal * nn + m.tangent * ((a == b ? (real)1 : (real)0) - nn);
            grad_v[a][b] += (real)SPH_SPHERE_WALL_IMAGE * p.closing * m.dphi * nn;
        }
}

/* The wall's force on particle i per unit mass, and the power the pair
 * (i, wall) does not conserve (the wall has no internal energy to take its
 * share of the stress work: *defect, W/kg, counted as dissipated); 0 out of
 * contact. */
static inline vec
sphere_wall_acceleration(int i, __global const vec *restrict pos, __global const vec *restrict vel,
                         __global const int *restrict flags,
                         __global const symt *restrict deviatoric_stress,
                         __global const real *restrict pressure, __global const real *restrict rho,
                         __global const symt *restrict csph, __global const real *restrict state,
                         __constant const struct sph_run_params *run, real *defect)
{
    *defect = 0;
    const struct sphere_wall_particle p =
        sphere_wall_particle(i, pos, vel, flags, deviatoric_stress, pressure, state, run);
    if (!p.contact)
        return VEC_ZERO;
    const struct sphere_wall_moments m =
        sphere_wall_integrals(SPH_KERNEL, SPH_DIM, p.d, run->sphere_radius, p.h);
    const real *n = p.n;
    const real normal_stress = p.normal_stress, closing = p.closing;
    const vec v = vel[i];
    real c[3][3];
#ifdef SPH_CSPH
    symt_load(csph[i], c);
#else
    (void)csph;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            c[a][b] = a == b ? (real)1 : (real)0;
#endif
    const real(*s)[3] = p.sigma;
    /* w = C grad Phi, sigma_n = sigma . n */
    real w[3] = {0, 0, 0}, sigma_n[3] = {0, 0, 0};
    for (int a = 0; a < SPH_DIM; ++a)
        for (int b = 0; b < SPH_DIM; ++b) {
            w[a] += c[a][b] * m.dphi * n[b];
            sigma_n[a] += s[a][b] * n[b];
        }
    real n_w = 0, sn_w = 0;
    for (int a = 0; a < SPH_DIM; ++a) {
        n_w += n[a] * w[a];
        sn_w += sigma_n[a] * w[a];
    }
    const real inv_rho = (real)1 / rho[i];
    /* never a pull: a particle closing on the sphere in tension is
     * compressed by pass 1's term but gets no force; its stress work
     * through that term is all the pair's defect */
    if (normal_stress >= 0) {
        *defect = (real)SPH_SPHERE_WALL_IMAGE * inv_rho * closing * sn_w;
        return VEC_ZERO;
    }
    /* (sigma + M sigma M) w, M = I - 2 n n: sigma + M sigma M =
     * 2 sigma - 2 n (x) (sigma n) - 2 (sigma n) (x) n + 4 sigma_nn n (x) n */
    real acc[3] = {0, 0, 0};
    for (int a = 0; a < SPH_DIM; ++a) {
        real sw = 0;
        for (int b = 0; b < SPH_DIM; ++b)
            sw += s[a][b] * w[b];
        acc[a] = inv_rho * ((real)2 * sw - (real)2 * n[a] * sn_w - (real)2 * sigma_n[a] * n_w +
                            (real)4 * normal_stress * n[a] * n_w);
    }
    /* the power into the particle's motion, its stress work through pass
     * 1's wall term (closing n (x) w), and the sphere's: their sum is
     * what the pair creates (the ledger counts minus it as dissipated) */
    real relative_power = 0;
    for (int a = 0; a < SPH_DIM; ++a)
        relative_power += acc[a] * (vec_get(v, a) - p.sphere_v[a]);
    *defect = relative_power + (real)SPH_SPHERE_WALL_IMAGE * inv_rho * closing * sn_w;
    return vec_make(acc[0], acc[1], acc[2]);
}

#endif
