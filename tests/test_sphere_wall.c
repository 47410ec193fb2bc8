/* The sphere's wall integrals (kernels/sphere_wall.cl, compiled here in
 * double precision) against brute force: grad Phi and the first moment M of
 * the sphere's (disc's) volume, summed over a fine lattice of points inside
 * it, for particles inside, at and beyond the surface, every kernel, 2-D
 * and 3-D; and the whole-space limit A = B = 1, Phi' = 0. */
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
#include "../kernels/sphere_wall.cl"

/* Phi' (along n = +x), A and B by a midpoint sum over the lattice points
 * y of spacing dy inside the ball of radius R centred at the origin, for
 * x = (d, 0, 0). */
static struct sphere_wall_moments brute_force(int type, int dim, double d, double radius, double h,
                                              double dy)
{
    const double support = sph_kernel_support_q(type) * h;
    const int reach = (int)ceil(support / dy) + 1;
    const int rz = dim == 3 ? reach : 0;
    const double volume = pow(dy, dim);
    double dphi = 0, normal = 0, tangent = 0;
    for (int k = -rz; k <= rz; ++k)
        for (int j = -reach; j <= reach; ++j)
            for (int i = -reach; i <= reach; ++i) {
                const double y[3] = {d + (i + 0.5) * dy, (j + 0.5) * dy,
                                     dim == 3 ? (k + 0.5) * dy : 0.0};
                if (y[0] * y[0] + y[1] * y[1] + y[2] * y[2] >= radius * radius)
                    continue;
                const double rel[3] = {y[0] - d, y[1], y[2]}; /* y - x */
                const double r = sqrt(rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2]);
                if (r >= support || r < 1e-12)
                    continue;
                /* grad_x W(x - y) = W'(r) (x - y) / r */
                const double w1 = sph_kernel_dwdr(type, dim, r, h);
                dphi += volume * w1 * (-rel[0]) / r;
                normal += volume * rel[0] * w1 * (-rel[0]) / r;
                tangent += volume * rel[1] * w1 * (-rel[1]) / r;
            }
    struct sphere_wall_moments m = {dphi, normal, tangent};
    return m;
}

static void test_whole_space(void **state)
{
    (void)state;
    for (int type = 0; type < SPH_KERNEL_COUNT; ++type)
        for (int dim = 2; dim <= 3; ++dim) {
            const struct sphere_wall_moments m = sphere_wall_integrals(type, dim, 0.3, 10.0, 1.0);
            if (fabs(m.normal - 1) > 1e-4 || fabs(m.tangent - 1) > 1e-4 || fabs(m.dphi) > 1e-6)
                fail_msg("kernel %d, %d-D, inside: A %.6f, B %.6f, Phi' %.2e; expected 1, 1, 0",
                         type, dim, m.normal, m.tangent, m.dphi);
        }
}

/* the gradient scale is 1/h; A and B are of order 1: 1% of each */
static void test_against_brute_force(void **state)
{
    (void)state;
    const double h = 1.0, radius = 2.4; /* R / h of a d/dx 8 shot at h = 1.2 dx */
    const double offsets[] = {-0.4, 0.0, 0.5, 1.2};
    for (int type = 0; type < SPH_KERNEL_COUNT; ++type)
        for (int dim = 2; dim <= 3; ++dim)
            for (size_t k = 0; k < sizeof offsets / sizeof offsets[0]; ++k) {
                const double d = radius + offsets[k] * h;
                const struct sphere_wall_moments m = sphere_wall_integrals(type, dim, d, radius, h);
                const struct sphere_wall_moments b =
                    brute_force(type, dim, d, radius, h, dim == 2 ? 0.005 : 0.025);
                if (fabs(m.dphi - b.dphi) > 0.01 / h || fabs(m.normal - b.normal) > 0.01 ||
                    fabs(m.tangent - b.tangent) > 0.01)
                    fail_msg("kernel %d, %d-D, d = R %+.1f h: Phi' %.4f / A %.4f / B %.4f, brute "
                             "force %.4f / %.4f / %.4f",
                             type, dim, offsets[k], m.dphi, m.normal, m.tangent, b.dphi, b.normal,
                             b.tangent);
            }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_whole_space),
        cmocka_unit_test(test_against_brute_force),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
