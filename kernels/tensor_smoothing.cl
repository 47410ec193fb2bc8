/*
 * A tensor smoothing length (numerics.smoothing: tensor; docs/design_asph.md):
 * each particle's kernel is an ellipsoid carried with the material, so that
 * a sheet squashed in one direction and stretched in the other two keeps
 * its in-plane neighbours (the 3-D Taylor face, docs/validation_taylor.md).
 *
 * State: the dimensionless metric G = h0^2 M per particle (smoothing_metric,
 * the identity on the lattice), with M = H^2 the metric of Owen, Villumsen,
 * Shapiro & Martel 1998 (ApJS 116:155): particle i's kernel is
 *   W_i(x) = det(H_i) w(|H_i x|),  grad W_i(x) = det(H_i) w'(eta)/eta M_i x,
 * eta = sqrt(x^T M_i x) = sqrt(y^T G_i y) with y = x / h0, and det(H_i) =
 * sqrt(det G_i) / h0^dim. Each side of a pair uses its own kernel (as
 * Spheral's solid SPH does), so the pair terms stay antisymmetric.
 *
 * With the CSPH correction the metric drops out of the corrected gradient:
 * with s_i = sqrt(det G_i) (dW/dr / r)(eta_i h0) the true gradient is
 * s_i G_i x, the moment is B_i = -(sum_j V_j s_i x x^T) G_i =: A_i G_i, and
 * the corrected gradient B_i^-T (s_i G_i x) = s_i A_i^-1 x. So pass 1 sums
 * A_i with the weights s_i (where it summed with dW/dr / r), stores
 * C_i = A_i^-1, and pass 2 takes C_i (s_i x) for i's stress and C_j (s_j x)
 * for j's: only the scalar weight of each side changes. A_i is close to
 * G_i^-1, not to I, so the eigenvalue floor of csph_correction is applied to
 * G^1/2 A G^1/2 (close to I) and mapped back (tensor_csph_correction).
 *
 * Evolution (integrate_drift): the ellipsoid is carried with the material,
 * M <- dF^-T M dF^-1 with dF = I + dt L (L pass 1's corrected velocity
 * gradient), which keeps |H x_ij| of every material pair constant (the
 * kinematic rate of Spheral's SmoothingScaleUtilities; det M follows
 * rho^2, so the kernel's volume follows the particle's). Each semi-axis is
 * then held within [h0 / TENSOR_AXIS_MAX, TENSOR_AXIS_MAX h0], which bounds
 * the anisotropy (TENSOR_AXIS_MAX^2 at most) and the search reach.
 */
#ifndef SPH_TENSOR_SMOOTHING_CL
#define SPH_TENSOR_SMOOTHING_CL

/* The longest semi-axis over h0 (include/sph_shared.h); the search reach
 * (host/step.c) is this times the isotropic support. */
#define TENSOR_AXIS_MAX SPH_TENSOR_AXIS_MAX

/* y^T G y for lanes of y and lanes of G (particle i's) */
static inline realv metric_norm2_lanes(const realv g[3][3], const realv y[3])
{
    realv sum = (realv)0;
#pragma unroll
    for (int a = 0; a < SPH_DIM; ++a) {
        realv row = (realv)0;
#pragma unroll
        for (int c = 0; c < SPH_DIM; ++c)
            row += g[a][c] * y[c];
        sum += y[a] * row;
    }
    return sum;
}

/* G broadcast to every lane (a neighbour's metric): the lanes' forms
 * below then serve it too */
static inline void metric_broadcast(const real g[3][3], realv out[3][3])
{
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int c = 0; c < 3; ++c)
            out[a][c] = (realv)g[a][c];
}

/* G x over the first SPH_DIM components, lanes of G and of x */
static inline void metric_times_lanes(const realv g[3][3], const realv x[3], realv out[3])
{
#pragma unroll
    for (int a = 0; a < 3; ++a) {
        out[a] = (realv)0;
#pragma unroll
        for (int c = 0; c < SPH_DIM; ++c)
            out[a] += a < SPH_DIM ? g[a][c] * x[c] : (realv)0;
    }
}

/* sqrt(det G): det(H) h0^dim, the kernel's normalisation over the
 * isotropic one */
static inline real metric_volume_factor(real g[3][3])
{
#if SPH_DIM == 2
    return sqrt(fmax(determinant2(g), (real)0));
#else
    return sqrt(fmax(determinant3(g), (real)0));
#endif
}

/* The lanes' metrics and volume factors (a lane past n: zero, and it is
 * out of every candidate's reach, lanes.cl lane_positions) */
static inline void metric_lanes(__global const symt *restrict smoothing_metric,
                                const struct lane_block *b, int n, realv g[3][3],
                                realv *volume_factor)
{
    gather_symt(smoothing_metric, b, n, g);
    lanes_union f;
    for (int l = 0; l < SPH_LANES; ++l) {
        real t[3][3];
        tensor_lane(g, l, t);
        f.s[l] = metric_volume_factor(t);
    }
    *volume_factor = f.v;
}

/* eta = |H x| in units of h0 for the lanes' own metrics: x = x_ij,
 * inv_h = 1 / h0 */
static inline realv metric_eta_lanes(const realv g[3][3], const realv x[3], real inv_h)
{
    realv y[3];
#pragma unroll
    for (int a = 0; a < 3; ++a)
        y[a] = x[a] * inv_h;
    return sqrt(metric_norm2_lanes(g, y));
}

/* The symmetric matrix with eigenvectors v (columns) and eigenvalues
 * value[k] over the first SPH_DIM dimensions, the identity beyond */
static inline void metric_from_eigen(real v[3][3], const real value[3], real g[3][3])
{
    for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q) {
            real sum = 0;
            for (int k = 0; k < SPH_DIM; ++k)
                sum += v[p][k] * v[q][k] * value[k];
            g[p][q] = p < SPH_DIM && q < SPH_DIM ? sum : (real)(p == q);
        }
}

/* G^1/2 of a symmetric positive definite G (its eigenvalues floored at a
 * tiny positive value) */
static inline void metric_square_root(real g[3][3], real root[3][3])
{
    real t[3][3], v[3][3], value[3] = {1, 1, 1};
    for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q)
            t[p][q] = g[p][q];
    symmetric_eigen(t, v);
    for (int k = 0; k < SPH_DIM; ++k)
        value[k] = sqrt(fmax(t[k][k], (real)1e-12));
    metric_from_eigen(v, value, root);
}

/* C = A^-1 of pass 1's moment A (close to G^-1), with csph_correction's
 * guard applied to G^1/2 A G^1/2 (close to I): C = G^1/2 (G^1/2 A
 * G^1/2)^-1 G^1/2 */
static inline void tensor_csph_correction(real a[3][3], real g[3][3], real c[3][3])
{
    real root[3][3], t[3][3], n[3][3], cn[3][3];
    metric_square_root(g, root);
    matrix_product(root, a, t);
    matrix_product(t, root, n);
    csph_correction(n, cn);
    matrix_product(root, cn, t);
    matrix_product(t, root, c);
}

/* The metric carried one step with the material and its semi-axes held
 * within [1 / TENSOR_AXIS_MAX, TENSOR_AXIS_MAX] h0 (the header). l: the
 * corrected velocity gradient, dt: the step. Returns the longest semi-axis
 * over h0 (smoothing_reach: the lane lists' per-particle reach). */
static inline real metric_advance(real g[3][3], real l[3][3], real dt)
{
    real f[3][3], f_inv[3][3], t[3][3], moved[3][3];
    for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q)
            f[p][q] = (real)(p == q) + (p < SPH_DIM && q < SPH_DIM ? dt * l[p][q] : (real)0);
    matrix_invert_or_identity(f, f_inv);
    matrix_product(g, f_inv, t);
    for (int p = 0; p < 3; ++p) /* f_inv^T (g f_inv) */
        for (int q = 0; q < 3; ++q) {
            real sum = 0;
            for (int k = 0; k < 3; ++k)
                sum += f_inv[k][p] * t[k][q];
            moved[p][q] = sum;
        }
    real v[3][3], value[3] = {1, 1, 1};
    symmetric_eigen(moved, v);
    const real lo = (real)(1.0 / (TENSOR_AXIS_MAX * TENSOR_AXIS_MAX)),
               hi = (real)(TENSOR_AXIS_MAX * TENSOR_AXIS_MAX);
    real smallest = hi;
    for (int k = 0; k < SPH_DIM; ++k) {
        value[k] = clamp(moved[k][k], lo, hi);
        smallest = fmin(smallest, value[k]);
    }
    metric_from_eigen(v, value, g);
    return (real)1 / sqrt(smallest);
}

/* h0 / (the shortest semi-axis) = sqrt(largest eigenvalue of G), at least
 * 1: the time step's signal speed is scaled by it (reduce.cl). Without a
 * second eigen-decomposition: the drift's longest semi-axis a (over h0,
 * smoothing_reach) gives the smallest eigenvalue 1 / a^2, so the other
 * two are the roots of x^2 - (tr G - 1 / a^2) x + det G a^2 (in 2-D the
 * other one is tr G - 1 / a^2). */
static inline real metric_shortest_axis_factor(real g[3][3], real longest_axis)
{
    const real smallest = (real)1 / (longest_axis * longest_axis);
#if SPH_DIM == 2
    const real largest = g[0][0] + g[1][1] - smallest;
#else
    const real sum = g[0][0] + g[1][1] + g[2][2] - smallest,
               product = determinant3(g) * longest_axis * longest_axis;
    const real largest = (real)0.5 * (sum + sqrt(fmax(sum * sum - (real)4 * product, (real)0)));
#endif
    return sqrt(fmax(largest, (real)1));
}

/* What pass 2 takes of a pair with two ellipsoids (the header): */
struct tensor_pair {
    realv s_i, s_j;         /* each side's gradient weight: grad W_i = s_i G_i x */
    realv h;                /* the pair's length along x: the mean of r / eta_i and r / eta_j */
    realv mean_gradient[3]; /* (grad W_i + grad W_j) / 2, uncorrected: the viscosity's */
    realv w;                /* (W_i + W_j) / 2: XSPH's */
};

/* for the lanes' metrics g_i and volume factors against neighbour j at
 * x = x_ij (r2 = |x|^2); lanes not `near` get zero weights and h0 */
static inline void tensor_pair_weights(struct tensor_pair *p, const realv g_i[3][3],
                                       realv volume_factor_i,
                                       __global const symt *restrict smoothing_metric, int j,
                                       const realv x[3], realv r2, real inv_h, real h0, maskv near)
{
    real g_j[3][3];
    symt_load(smoothing_metric[j], g_j);
    const real volume_factor_j = metric_volume_factor(g_j);
    realv g_jv[3][3];
    metric_broadcast(g_j, g_jv);
    const realv eta_i = metric_eta_lanes(g_i, x, inv_h), eta_j = metric_eta_lanes(g_jv, x, inv_h);
    p->s_i = SPH_SELECT((realv)0, volume_factor_i * kernel_dwdr_over_r_q(eta_i, inv_h), near);
    p->s_j = SPH_SELECT((realv)0, volume_factor_j * kernel_dwdr_over_r_q(eta_j, inv_h), near);
    const realv tiny = (realv)1e-6, r = sqrt(r2);
    p->h = SPH_SELECT((realv)h0,
                      (real)0.5 * r * ((real)1 / fmax(eta_i, tiny) + (real)1 / fmax(eta_j, tiny)),
                      near);
    realv gx_i[3], gx_j[3];
    metric_times_lanes(g_i, x, gx_i);
    metric_times_lanes(g_jv, x, gx_j);
#pragma unroll
    for (int a = 0; a < 3; ++a)
        p->mean_gradient[a] = (real)0.5 * (p->s_i * gx_i[a] + p->s_j * gx_j[a]);
    p->w = SPH_SELECT((realv)0,
                      (real)0.5 * (volume_factor_i * kernel_w_q(eta_i, inv_h) +
                                   volume_factor_j * kernel_w_q(eta_j, inv_h)),
                      near);
}

#endif /* SPH_TENSOR_SMOOTHING_CL */
