/* Equations of state, Johnson-Cook yield and the radial return, compiled
 * from kernels/material_models.cl in double precision, against values
 * computed by hand from the published forms (thesis eqs. 3.24-3.27, 3.32,
 * 3.33-3.34, 4.13-4.15; REFERENCES.md 2 and 3 for the material data). The
 * Mie-Gruneisen values were computed both from the expanded form used in the
 * code and from the Hugoniot form p_H (1 - Gamma0 mu / (2 (1 + mu))) +
 * Gamma0 rho0 e; they agree to 1e-15. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#define SPH_DOUBLE
#define CL_TARGET_OPENCL_VERSION 120
#include "sph_shared.h"
#include "../kernels/material_models.cl"

static void assert_relative(double got, double want, double tolerance)
{
    const double error = want == 0 ? fabs(got) : fabs(got - want) / fabs(want);
    if (error > tolerance)
        fail_msg("got %.12g, expected %.12g (relative error %.3g > %.3g)", got, want, error,
                 tolerance);
}

/* Iron of the 2-D Taylor bar (REFERENCES.md 2): rho0 7850, C 3630, S 1.8,
 * Gamma0 1.8. */
static struct sph_material iron(void)
{
    struct sph_material m = {0};
    m.density = 7850;
    m.eos_c0 = 3630;
    m.eos_s = 1.8;
    m.eos_gamma0 = 1.8;
    m.eos = SPH_EOS_MIE_GRUNEISEN;
    return m;
}

static void mie_gruneisen_compression(void **state)
{
    (void)state;
    const struct sph_material m = iron();
    assert_relative(pressure_eos(&m, 0.1, 0), 12343224438.799625, 1e-12);
    assert_relative(pressure_eos(&m, 0.1, 1e5), 13756224438.799625, 1e-12);
    assert_relative(pressure_eos(&m, 0, 0), 0, 0);
}

static void mie_gruneisen_tension(void **state)
{
    (void)state;
    const struct sph_material m = iron();
    assert_relative(pressure_eos(&m, -0.05, 0), -5171933250.0, 1e-12);
    assert_relative(pressure_eos(&m, -0.05, 1e5), -3758933250.0, 1e-12);
}

/* 10% gelatin (REFERENCES.md 3): rho0 1030, c0 1520, S 1.8, p0 = 0:
 * C1 = rho0 c0^2 = 2.379712e9 Pa, C2 = 2.6 C1, C3 = 3.52 C1. */
static void polynomial_eos(void **state)
{
    (void)state;
    struct sph_material m = {0};
    m.density = 1030;
    m.eos_c0 = 1520;
    m.eos_s = 1.8;
    m.eos = SPH_EOS_POLYNOMIAL;
    assert_relative(pressure_eos(&m, 0.1, 0), 308220298.24, 1e-12);
    assert_relative(pressure_eos(&m, -0.02, 0), -47594240.0, 1e-12);
}

/* 4340 steel (REFERENCES.md 2): A 792 MPa, B 510 MPa, n 0.26, C 0.014,
 * m 1.03, T_melt 1793 K, T_room 293 K, reference rate 1/s. */
static struct sph_material steel_4340(void)
{
    struct sph_material m = {0};
    m.yield_stress = 792e6;
    m.hardening_b = 510e6;
    m.hardening_n = 0.26;
    m.jc_rate_c = 0.014;
    m.jc_reference_rate = 1;
    m.jc_thermal_m = 1.03;
    m.melt_temperature = 1793;
    m.room_temperature = 293;
    m.shear_modulus = 89.2e9;
    m.strength = SPH_STRENGTH_JOHNSON_COOK;
    return m;
}

static void johnson_cook_yield(void **state)
{
    (void)state;
    const struct sph_material m = steel_4340();
    assert_relative(yield_stress_of(&m, 0, 1, 293), 792e6, 1e-14);
    assert_relative(yield_stress_of(&m, 0.1, 1000, 293), 1175963146.4497244, 1e-12);
    /* half-way to melting: 1 - 0.5^1.03 */
    assert_relative(yield_stress_of(&m, 0.2, 1, 793), 763927754.8956532, 1e-12);
    /* below the reference rate the rate term stays 1 */
    assert_relative(yield_stress_of(&m, 0.2, 0.5, 293), 1127612381.818713, 1e-12);
    /* at and above the melting point the material carries no shear */
    assert_relative(yield_stress_of(&m, 0.1, 1000, 1793), 0, 0);
    assert_relative(yield_stress_of(&m, 0.1, 1000, 2500), 0, 0);
}

/* The floor the material update tests trial stresses against before it
 * evaluates Johnson-Cook (kernels/material.cl, plastic_correction): never
 * above the yield stress over random plastic strains, rates and
 * temperatures up to T_room (where it is A), none above T_room, none when B
 * or C is negative (the factors could then fall below 1), and the yield
 * stress itself for a perfectly plastic material. */
static void yield_stress_floor_never_exceeds_the_yield_stress(void **state)
{
    (void)state;
    srand(11);
    struct sph_material m = steel_4340();
    for (int trial = 0; trial < 10000; ++trial) {
        const double strain = trial % 7 == 0 ? 0 : 5.0 * rand() / RAND_MAX;
        const double rate = pow(10, -3 + 11.0 * rand() / RAND_MAX);
        const double temperature = 93 + 200.0 * rand() / RAND_MAX;
        const double floor = yield_stress_floor(&m, temperature);
        assert_relative(floor, 792e6, 0);
        assert_true(floor <= yield_stress_of(&m, strain, rate, temperature));
    }
    assert_relative(yield_stress_floor(&m, 293.5), -1, 0);
    m.jc_rate_c = -0.01;
    assert_relative(yield_stress_floor(&m, 293), -1, 0);
    m.jc_rate_c = 0.014;
    m.hardening_b = -1e6;
    assert_relative(yield_stress_floor(&m, 293), -1, 0);
    struct sph_material plastic = {0};
    plastic.strength = SPH_STRENGTH_PERFECTLY_PLASTIC;
    plastic.yield_stress = 25e6;
    assert_relative(yield_stress_floor(&plastic, 1000), 25e6, 0);
    plastic.strength = SPH_STRENGTH_ELASTIC;
    assert_relative(yield_stress_floor(&plastic, 293), -1, 0);
}

/* Random symmetric deviatoric tensors: after the return sqrt(3 J2) equals
 * the yield stress within 1e-6 where the trial exceeded it, and no state is
 * ever pushed up; the increment is (trial - yield) / 3G. */
static void radial_return_lands_on_the_surface(void **state)
{
    (void)state;
    srand(7);
    const double yield = 600e6, shear = 80e9;
    for (int trial = 0; trial < 10000; ++trial) {
        double s[9];
        for (int a = 0; a < 3; ++a)
            for (int b = a; b < 3; ++b)
                s[3 * a + b] = s[3 * b + a] = 1.2e9 * ((double)rand() / RAND_MAX - 0.5);
        const double mean = (s[0] + s[4] + s[8]) / 3;
        s[0] -= mean, s[4] -= mean, s[8] -= mean;
        const double before = von_mises_equivalent(s);
        const double increment = radial_return(s, yield, shear);
        const double after = von_mises_equivalent(s);
        assert_true(after <= before * (1 + 1e-12));
        if (before > yield) {
            assert_relative(after, yield, 1e-6);
            assert_relative(increment, (before - yield) / (3 * shear), 1e-9);
        } else {
            assert_relative(after, before, 0);
            assert_relative(increment, 0, 0);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(mie_gruneisen_compression),
        cmocka_unit_test(mie_gruneisen_tension),
        cmocka_unit_test(polynomial_eos),
        cmocka_unit_test(johnson_cook_yield),
        cmocka_unit_test(yield_stress_floor_never_exceeds_the_yield_stress),
        cmocka_unit_test(radial_return_lands_on_the_surface),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
