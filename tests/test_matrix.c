/* The CSPH correction (kernels/matrix.cl), compiled on the host in double
 * precision, once per dimension (SPH_DIM 2 and 3: test_matrix_2d,
 * test_matrix_3d):
 * - on a regular lattice's interior, face, edge and corner, with every
 *   smoothing kernel at h/dx 1.0, 1.2, 1.5 and 2.0, it is the plain
 *   inverse to the bit: the eigenvalue floor touches no body's corner;
 * - a moment matrix with one eigenvalue below the floor that passes the
 *   determinant guard (the splashed SEBS particle's 0.056) is inverted with
 *   that eigenvalue raised to the floor, along its own eigenvector;
 * - continuous across the floor; the determinant guard still gives the
 *   identity;
 * - the Jacobi decomposition rebuilds the matrix it took apart. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#define SPH_DOUBLE
#define CL_TARGET_OPENCL_VERSION 120
#include "sph_shared.h"
#include "../kernels/smoothing.cl"
#include "../kernels/matrix.cl"

/* B = sum_j V_j x_ji (x) grad_i W_ij over a unit lattice (V_j = 1) cut to
 * the particles with x_a >= 0 for the first `cut_axes` axes: 0 interior,
 * 1 face, 2 edge, 3 corner (3-D). */
static void lattice_moment(int kernel, double h, int cut_axes, real b[3][3])
{
    const double support = sph_kernel_support_q(kernel) * h;
    const int reach = (int)ceil(support);
    for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q)
            b[p][q] = 0;
    for (int i = -reach; i <= reach; ++i)
        for (int j = -reach; j <= reach; ++j)
            for (int k = SPH_DIM == 3 ? -reach : 0; k <= (SPH_DIM == 3 ? reach : 0); ++k) {
                const double x[3] = {i, j, k};
                const double r = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
                int outside = 0;
                for (int a = 0; a < cut_axes; ++a)
                    outside |= x[a] < 0;
                if (r == 0 || r >= support || outside)
                    continue;
                /* x_ji = x, grad_i W_ij = dW/dr (x_i - x_j) / r = -dW/dr x / r */
                const double s = -sph_kernel_dwdr(kernel, SPH_DIM, r, h) / r;
                for (int p = 0; p < SPH_DIM; ++p)
                    for (int q = 0; q < SPH_DIM; ++q)
                        b[p][q] += s * x[p] * x[q];
            }
}

/* The smallest eigenvalue of a symmetric matrix (first SPH_DIM rows). */
static double smallest_eigenvalue(real b[3][3])
{
    real t[3][3], v[3][3];
    for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q)
            t[p][q] = p < SPH_DIM && q < SPH_DIM ? b[p][q] : 0;
    symmetric_eigen(t, v);
    double smallest = t[0][0];
    for (int k = 1; k < SPH_DIM; ++k)
        smallest = fmin(smallest, t[k][k]);
    return smallest;
}

/* Also prints the corner's smallest eigenvalue per kernel and h/dx (the
 * table docs/validation_penetration.md quotes, session 35), and Wendland
 * C2's face, edge and corner determinants at h = 1.2 dx (kernels/matrix.cl
 * quotes them). */
static void lattice_corners_untouched(void **state)
{
    (void)state;
    const double h_over_dx[] = {1.0, 1.2, 1.5, 2.0};
    for (int kernel = 0; kernel < SPH_KERNEL_COUNT; ++kernel) {
        print_message("kernel %d, corner's smallest eigenvalue at h/dx 1.0 / 1.2 / 1.5 / 2.0:",
                      kernel);
        for (int e = 0; e < 4; ++e)
            for (int cut = 0; cut <= SPH_DIM; ++cut) {
                real b[3][3], c[3][3], inverse[3][3];
                lattice_moment(kernel, h_over_dx[e], cut, b);
                if (cut == SPH_DIM)
                    print_message(" %.3f", smallest_eigenvalue(b));
                assert_true(matrix_invert_or_identity(b, inverse));
                csph_correction(b, c);
                for (int p = 0; p < 3; ++p)
                    for (int q = 0; q < 3; ++q)
                        if (c[p][q] != inverse[p][q])
                            fail_msg("kernel %d, h/dx %.1f, %d cut axes: C[%d][%d] %.17g, "
                                     "B^-1 %.17g",
                                     kernel, h_over_dx[e], cut, p, q, c[p][q], inverse[p][q]);
            }
        print_message("\n");
    }
    print_message("Wendland C2, h/dx 1.2: det B at the face / edge / corner:");
    for (int cut = 1; cut <= SPH_DIM; ++cut) {
        real b[3][3];
        lattice_moment(SPH_KERNEL_WENDLAND_C2, 1.2, cut, b);
        print_message(" %.4f", (double)(SPH_DIM == 2 ? determinant2(b) : determinant3(b)));
    }
    print_message("\n");
}

/* An orthonormal frame turned off the axes (rotations about z, then x). */
static void frame(real q[3][3])
{
    const double a = 0.7, b = SPH_DIM == 3 ? 0.4 : 0.0;
    const double rz[3][3] = {{cos(a), -sin(a), 0}, {sin(a), cos(a), 0}, {0, 0, 1}};
    const double rx[3][3] = {{1, 0, 0}, {0, cos(b), -sin(b)}, {0, sin(b), cos(b)}};
    for (int p = 0; p < 3; ++p)
        for (int r = 0; r < 3; ++r) {
            q[p][r] = 0;
            for (int k = 0; k < 3; ++k)
                q[p][r] += rz[p][k] * rx[k][r];
        }
}

/* B = Q diag(lambda) Q^T in the first SPH_DIM dimensions. */
static void from_eigen(real q[3][3], const double *lambda, real b[3][3])
{
    for (int p = 0; p < 3; ++p)
        for (int r = 0; r < 3; ++r) {
            b[p][r] = 0;
            for (int k = 0; k < SPH_DIM; ++k)
                b[p][r] += q[p][k] * lambda[k] * q[r][k];
        }
}

static void small_eigenvalue_raised_to_floor(void **state)
{
    (void)state;
    /* det 0.028 (3-D) / 0.056 (2-D): passes the determinant guard */
    const double lambda[3] = {1.0, SPH_DIM == 3 ? 0.5 : 0.056, 0.056};
    real q[3][3], b[3][3], c[3][3];
    frame(q);
    from_eigen(q, lambda, b);
    real plain[3][3];
    assert_true(matrix_invert_or_identity(b, plain));
    csph_correction(b, c);
    for (int k = 0; k < SPH_DIM; ++k) {
        const double expected = 1.0 / fmax(lambda[k], 0.1);
        for (int p = 0; p < SPH_DIM; ++p) {
            double cq = 0;
            for (int r = 0; r < SPH_DIM; ++r)
                cq += c[p][r] * q[r][k];
            if (fabs(cq - expected * q[p][k]) > 1e-12)
                fail_msg("eigenvector %d, component %d: C q %.15g, expected %.15g", k, p, cq,
                         expected * q[p][k]);
        }
    }
    /* the plain inverse amplifies the small direction 1 / 0.056 = 17.9-fold */
    double amplification = 0;
    for (int p = 0; p < SPH_DIM; ++p)
        for (int r = 0; r < SPH_DIM; ++r)
            amplification += q[p][SPH_DIM - 1] * plain[p][r] * q[r][SPH_DIM - 1];
    assert_true(fabs(amplification - 1.0 / 0.056) < 1e-9);
    for (int p = 0; p < 3; ++p)
        for (int r = 0; r < 3; ++r)
            assert_true(fabs(c[p][r] - c[r][p]) < 1e-15);
}

static void continuous_across_floor(void **state)
{
    (void)state;
    real q[3][3], below[3][3], above[3][3], c_below[3][3], c_above[3][3];
    frame(q);
    const double just_below[3] = {1.0, 0.1 * (1 - 1e-9), 0.7};
    const double just_above[3] = {1.0, 0.1 * (1 + 1e-9), 0.7};
    from_eigen(q, just_below, below);
    from_eigen(q, just_above, above);
    assert_false(symmetric_eigenvalues_above(below, CSPH_EIGENVALUE_FLOOR));
    assert_true(symmetric_eigenvalues_above(above, CSPH_EIGENVALUE_FLOOR));
    csph_correction(below, c_below);
    csph_correction(above, c_above);
    for (int p = 0; p < 3; ++p)
        for (int r = 0; r < 3; ++r)
            if (fabs(c_below[p][r] - c_above[p][r]) > 1e-7)
                fail_msg("C[%d][%d] jumps from %.12g to %.12g at the floor", p, r, c_below[p][r],
                         c_above[p][r]);
}

static void determinant_guard_gives_identity(void **state)
{
    (void)state;
    real q[3][3], b[3][3], c[3][3];
    frame(q);
    const double lambda[3] = {1.0, 0.02, 0.02}; /* det 4e-4 (3-D) < 1/1024; 0.02 (2-D) < 1/32 */
    from_eigen(q, lambda, b);
    csph_correction(b, c);
    for (int p = 0; p < 3; ++p)
        for (int r = 0; r < 3; ++r)
            assert_true(c[p][r] == (p == r ? 1.0 : 0.0));
}

static void jacobi_rebuilds_matrix(void **state)
{
    (void)state;
    const real a[3][3] = {{2.0, -0.3, 0.7}, {-0.3, 0.5, 0.11}, {0.7, 0.11, -1.2}};
    real t[3][3], v[3][3];
    for (int p = 0; p < 3; ++p)
        for (int r = 0; r < 3; ++r)
            t[p][r] = a[p][r];
    symmetric_eigen(t, v);
    for (int p = 0; p < 3; ++p)
        for (int r = 0; r < 3; ++r) {
            double rebuilt = 0;
            for (int k = 0; k < 3; ++k)
                rebuilt += v[p][k] * t[k][k] * v[r][k];
            assert_true(fabs(rebuilt - a[p][r]) < 1e-13);
            if (p != r)
                assert_true(fabs(t[p][r]) < 1e-13);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(lattice_corners_untouched),
        cmocka_unit_test(small_eigenvalue_raised_to_floor),
        cmocka_unit_test(continuous_across_floor),
        cmocka_unit_test(determinant_guard_gives_identity),
        cmocka_unit_test(jacobi_rebuilds_matrix),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
