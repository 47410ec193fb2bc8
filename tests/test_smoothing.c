/* Smoothing kernels, compiled from kernels/smoothing.cl in double precision:
 * normalisation, zero gradient sum, first moment, and dW/dr against a
 * central difference of W, for all six kernels in 1-, 2- and 3-D. */
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

static const char *const names[SPH_KERNEL_COUNT] = {
    "cubic_spline", "gaussian", "quintic_spline", "wendland_c2", "double_cosine", "hyperbolic"};

/* Sums over a lattice of spacing dx around a point offset from a lattice
 * node: the discrete integral of W, of grad W, and of (x_j - x_i) grad W. */
struct sums {
    double integral;
    double gradient[3];
    double moment[3][3];
};

static struct sums lattice_sums(int type, int dim, double h, double dx, const double offset[3])
{
    struct sums s = {0};
    const double support = sph_kernel_support_q(type) * h;
    const int reach = (int)ceil(support / dx) + 1;
    const int rz = dim == 3 ? reach : 0, ry = dim >= 2 ? reach : 0;
    const double volume = pow(dx, dim);
    for (int k = -rz; k <= rz; ++k)
        for (int j = -ry; j <= ry; ++j)
            for (int i = -reach; i <= reach; ++i) {
                const double xj[3] = {i * dx, j * dx, k * dx};
                double xij[3], r2 = 0;
                for (int a = 0; a < 3; ++a) {
                    xij[a] = a < dim ? offset[a] - xj[a] : 0.0; /* x_i - x_j */
                    r2 += xij[a] * xij[a];
                }
                const double r = sqrt(r2);
                if (r >= support)
                    continue;
                s.integral += volume * sph_kernel_value(type, dim, r, h);
                if (r < 1e-12)
                    continue;
                const double dwdr = sph_kernel_dwdr(type, dim, r, h);
                for (int a = 0; a < dim; ++a) {
                    const double g = dwdr * xij[a] / r;
                    s.gradient[a] += volume * g;
                    for (int b = 0; b < dim; ++b)
                        s.moment[b][a] += volume * (-xij[b]) * g;
                }
            }
    return s;
}

static void check_kernel(int type, int dim)
{
    /* the hyperbolic kernel's gradient jumps at r = 0, so lattice sums of it
     * converge only as O(dx): fine lattices keep that error under 1e-3 */
    const double h = 1.0, dx = dim == 1 ? 0.002 : dim == 2 ? 0.01 : 0.04;
    const double offset[3] = {0.37 * dx, 0.61 * dx, 0.23 * dx};
    const struct sums s = lattice_sums(type, dim, h, dx, offset);
    if (fabs(s.integral - 1.0) > 1e-3)
        fail_msg("%s %d-D: integral %.6f, expected 1 within 1e-3", names[type], dim, s.integral);
    /* grad W scales as 1/h: compare the sums with that scale */
    for (int a = 0; a < dim; ++a) {
        if (fabs(s.gradient[a]) > 1e-3 / h)
            fail_msg("%s %d-D: gradient sum[%d] = %.3e, expected 0", names[type], dim, a,
                     s.gradient[a]);
        for (int b = 0; b < dim; ++b) {
            const double expected = a == b ? 1.0 : 0.0;
            if (fabs(s.moment[a][b] - expected) > 1e-3)
                fail_msg("%s %d-D: first moment [%d][%d] = %.6f, expected %.0f", names[type], dim,
                         a, b, s.moment[a][b], expected);
        }
    }
}

static void check_derivative(int type, int dim)
{
    const double h = 0.7, e = 1e-6;
    const double support = sph_kernel_support_q(type) * h;
    const double scale = sph_kernel_sigma(type, dim) * sph_inv_h_pow(h, dim) / h;
    for (int k = 1; k < 200; ++k) {
        const double r = support * k / 200.0;
        if (fabs(r / h - 1.0) < 1e-3 || fabs(r / h - 2.0) < 1e-3 || fabs(r - support) < 2 * e)
            continue; /* piecewise joints */
        const double fd =
            (sph_kernel_value(type, dim, r + e, h) - sph_kernel_value(type, dim, r - e, h)) /
            (2 * e);
        const double dw = sph_kernel_dwdr(type, dim, r, h);
        if (fabs(fd - dw) > 1e-5 * scale * 10)
            fail_msg("%s %d-D: dW/dr at r = %.3f h is %.6e, central difference %.6e", names[type],
                     dim, r / h, dw, fd);
    }
}

static void test_normalisation_and_moments(void **state)
{
    (void)state;
    for (int type = 0; type < SPH_KERNEL_COUNT; ++type)
        for (int dim = 1; dim <= 3; ++dim)
            check_kernel(type, dim);
}

static void test_derivative_matches_value(void **state)
{
    (void)state;
    for (int type = 0; type < SPH_KERNEL_COUNT; ++type)
        for (int dim = 1; dim <= 3; ++dim)
            check_derivative(type, dim);
}

static void test_compact_support(void **state)
{
    (void)state;
    for (int type = 0; type < SPH_KERNEL_COUNT; ++type) {
        const double q = sph_kernel_support_q(type);
        assert_true(sph_kernel_value(type, 3, q * 1.0001, 1.0) == 0.0);
        /* continuous at the cut */
        assert_true(fabs(sph_kernel_shape(type, q * 0.99999)) < 1e-7 * sph_kernel_shape(type, 0.0));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_normalisation_and_moments),
        cmocka_unit_test(test_derivative_matches_value),
        cmocka_unit_test(test_compact_support),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
