/* The axisymmetric mass convention (kernels/common.cl, plane_mass): on a
 * uniform (r, z) lattice of spacing dx whose particles carry the ring mass
 * per radian m = rho0 r dx^2, the density the rings imply at particle i,
 * rho_i = sum_j m_j W_ij / r_i (the ring masses summed over the plane and
 * divided by the radius), equals rho0 within 1% away from the axis (r of at
 * least one support) for every kernel. Within a support of the axis the
 * summation is far off even with the mirror particles (cubic spline, h =
 * 1.2 dx: +44% at r = dx/2), the known weakness of summation density there;
 * the solver never sums density, it integrates the continuity equation with
 * the hoop rate v_r / r (kernels/pass1.cl). The plane lattice sum sum_j dx^2 W_ij is
 * divided out, so what is tested is the axisymmetric weighting, not the
 * lattice moment of the kernel (tests/test_smoothing.c bounds that).
 * Checked in double with the device's own smoothing kernels. */
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

/* sum_j dx^2 W_ij over a full plane lattice (the kernel's lattice moment). */
static double lattice_sum(int kernel, double h_over_dx)
{
    const double h = h_over_dx, support = sph_kernel_support_q(kernel) * h;
    const int reach = (int)ceil(support) + 1;
    double sum = 0;
    for (int a = -reach; a <= reach; ++a)
        for (int b = -reach; b <= reach; ++b) {
            const double d = sqrt((double)(a * a + b * b));
            if (d < support)
                sum += sph_kernel_value(kernel, 2, d, h);
        }
    return sum;
}

/* rho at the particle of column `column` (r = (column + 1/2) dx), z = 0. */
static double ring_density(int kernel, double h_over_dx, int column)
{
    const double dx = 1.0, h = h_over_dx * dx, rho0 = 1000.0;
    const double support = sph_kernel_support_q(kernel) * h;
    const double ri = (column + 0.5) * dx;
    const int reach = (int)ceil(support / dx) + 1;
    double sum = 0;
    for (int c = -reach - column - 1; c <= column + reach; ++c)
        for (int k = -reach; k <= reach; ++k) {
            const double r = (c + 0.5) * dx, z = k * dx;
            const double d = sqrt((r - ri) * (r - ri) + z * z);
            if (d >= support)
                continue;
            const double mass = rho0 * fabs(r) * dx * dx; /* mirrors (r < 0) carry their source's */
            const double w = sph_kernel_value(kernel, 2, d, h);
            sum += mass * w / ri;
        }
    return sum / rho0 / lattice_sum(kernel, h_over_dx);
}

static void density_away_from_the_axis(void **state)
{
    (void)state;
    for (int kernel = 0; kernel < SPH_KERNEL_COUNT; ++kernel)
        for (int column = 3; column < 40; ++column) {
            const double ratio = ring_density(kernel, 1.2, column);
            if (fabs(ratio - 1) > 0.01)
                fail_msg("kernel %d, r = %.1f dx: rho / rho0 = %.5f", kernel, column + 0.5, ratio);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(density_away_from_the_axis),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
