/*
 * Equations of state and yield stresses, pointwise.
 *
 * Written in the common subset of C11 and OpenCL C (scalars only), like
 * smoothing.cl, so the unit tests compile this very file on the host and
 * check it against hand-computed values (tests/test_material.c). Every
 * function takes the material table entry (include/sph_shared.h) and SI
 * quantities: mu = rho / rho0 - 1 (compression), e specific internal energy
 * (J/kg), T temperature (K), strain rates in 1/s.
 */
#ifndef SPH_MATERIAL_MODELS_CL
#define SPH_MATERIAL_MODELS_CL

#if defined(__OPENCL_VERSION__) || defined(__OPENCL_C_VERSION__)
#define SPH_CONSTANT __constant const
#else
#define SPH_CONSTANT const
#endif

/* Linear EOS, p = K mu. */
static inline real pressure_linear(SPH_CONSTANT struct sph_material *m, real mu)
{
    return m->bulk_modulus * mu;
}

/* Mie-Gruneisen with the shock Hugoniot as reference curve (thesis eqs.
 * 3.24-3.27; the LS-DYNA *EOS_GRUNEISEN form with a = 0), assuming
 * Gamma rho = Gamma0 rho0:
 *   compression (mu > 0): p = rho0 C^2 mu (1 + (1 - Gamma0/2) mu)
 *                             / (1 - (S - 1) mu)^2 + Gamma0 rho0 e
 *   tension     (mu < 0): p = rho0 C^2 mu + Gamma0 rho0 e
 * which is p_H (1 - Gamma0 mu / (2 (1 + mu))) + Gamma0 rho0 e with the
 * Hugoniot pressure p_H = rho0 C^2 mu (1 + mu) / (1 - (S - 1) mu)^2. The
 * denominator vanishes at mu = 1 / (S - 1) (the Hugoniot's limiting
 * compression); it is held at that of 0.9 of it. */
static inline real pressure_mie_gruneisen(SPH_CONSTANT struct sph_material *m, real mu, real e)
{
    const real rho0 = m->density, c = m->eos_c0, gamma0 = m->eos_gamma0;
    const real energy_term = gamma0 * rho0 * e;
    if (mu <= 0)
        return rho0 * c * c * mu + energy_term;
    const real s1 = m->eos_s - (real)1;
    const real mu_limited = s1 > 0 ? fmin(mu, (real)0.9 / s1) : mu;
    const real denominator = (real)1 - s1 * mu_limited;
    return rho0 * c * c * mu * ((real)1 + ((real)1 - (real)0.5 * gamma0) * mu) /
               (denominator * denominator) +
           energy_term;
}

/* Polynomial Mie-Gruneisen (thesis eqs. 4.13-4.15, REFERENCES.md 3):
 * p = C0 + C1 mu + C2 mu^2 + C3 mu^3 (mu > 0), C0 + C1 mu (mu <= 0) with
 * C0 = p0, C1 = rho0 c0^2 - Gamma0 p0 / 2, C2 = (2S - 1) C1,
 * C3 = (S - 1)(3S - 1) C1. No energy term in this form. */
static inline real pressure_polynomial(SPH_CONSTANT struct sph_material *m, real mu)
{
    const real c1 = m->density * m->eos_c0 * m->eos_c0 - (real)0.5 * m->eos_gamma0 * m->eos_p0;
    if (mu <= 0)
        return m->eos_p0 + c1 * mu;
    const real s = m->eos_s;
    const real c2 = ((real)2 * s - (real)1) * c1;
    const real c3 = (s - (real)1) * ((real)3 * s - (real)1) * c1;
    return m->eos_p0 + mu * (c1 + mu * (c2 + mu * c3));
}

static inline real pressure_eos(SPH_CONSTANT struct sph_material *m, real mu, real e)
{
    if (m->eos == SPH_EOS_MIE_GRUNEISEN)
        return pressure_mie_gruneisen(m, mu, e);
    if (m->eos == SPH_EOS_POLYNOMIAL)
        return pressure_polynomial(m, mu);
    return pressure_linear(m, mu);
}

/* The longitudinal wave speed at the current state, m/s:
 * c^2 = (dp/drho at fixed e) + 4 G / (3 rho0), the slope by a central
 * difference over mu +- 1e-3; never below the reference speed at rho0. A
 * compressed Mie-Gruneisen or polynomial solid stiffens (at mu = 3 the
 * polynomial gelatin's c is five times c0), and the time step and the
 * artificial viscosity follow it (stored per particle by material.cl). */
static inline real sound_speed_current(SPH_CONSTANT struct sph_material *m, real rho, real e)
{
    const real mu = rho / m->density - (real)1, step = (real)1e-3;
    const real slope = (pressure_eos(m, mu + step, e) - pressure_eos(m, mu - step, e)) /
                       ((real)2 * step * m->density);
    const real c2 = slope + (real)4 * m->shear_modulus / ((real)3 * m->density);
    return fmax(m->sound_speed, sqrt(fmax(c2, (real)0)));
}

/* Johnson-Cook yield stress (thesis eq. 3.32; Johnson & Cook 1983):
 *   sigma_y = (A + B eps_p^n) (1 + C ln(rate*)) (1 - T*^m)
 * with rate* = max(rate / rate0, 1) (no softening below the reference
 * rate) and T* = (T - T_room) / (T_melt - T_room) clamped to [0, 1], so
 * sigma_y = 0 at and above the melting point. */
static inline real yield_stress_johnson_cook(SPH_CONSTANT struct sph_material *m,
                                             real plastic_strain, real strain_rate,
                                             real temperature)
{
    const real hardening =
        m->yield_stress +
        (plastic_strain > 0 ? m->hardening_b * pow(plastic_strain, m->hardening_n) : (real)0);
    const real rate_ratio = strain_rate / m->jc_reference_rate;
    const real rate_factor = rate_ratio > 1 ? (real)1 + m->jc_rate_c * log(rate_ratio) : (real)1;
    real thermal = 1;
    if (m->jc_thermal_m > 0 && m->melt_temperature > m->room_temperature) {
        real t_star =
            (temperature - m->room_temperature) / (m->melt_temperature - m->room_temperature);
        t_star = fmin(fmax(t_star, (real)0), (real)1);
        thermal = (real)1 - pow(t_star, m->jc_thermal_m);
    }
    return hardening * rate_factor * thermal;
}

/* Current yield stress of any strength model (elastic: none, returned as
 * -1). */
static inline real yield_stress_of(SPH_CONSTANT struct sph_material *m, real plastic_strain,
                                   real strain_rate, real temperature)
{
    if (m->strength == SPH_STRENGTH_PERFECTLY_PLASTIC)
        return m->yield_stress;
    if (m->strength == SPH_STRENGTH_JOHNSON_COOK)
        return yield_stress_johnson_cook(m, plastic_strain, strain_rate, temperature);
    return -1;
}

/* A value the current yield stress cannot fall below, from the
 * temperature alone (Pa; -1 where there is none): a trial stress at or
 * under it is elastic without the Johnson-Cook powers and logarithm, which
 * most of a body at any time is. Johnson-Cook with B >= 0 and C >= 0 at or
 * below T_room: A, since the hardening and rate factors are then >= 1 (in
 * rounded arithmetic too: a sum of non-negatives and a product by a factor
 * >= 1 round monotonically) and the thermal factor is 1. */
static inline real yield_stress_floor(SPH_CONSTANT struct sph_material *m, real temperature)
{
    if (m->strength == SPH_STRENGTH_PERFECTLY_PLASTIC)
        return m->yield_stress;
    if (m->strength == SPH_STRENGTH_JOHNSON_COOK && m->hardening_b >= 0 && m->jc_rate_c >= 0 &&
        temperature <= m->room_temperature)
        return m->yield_stress;
    return -1;
}

/* von Mises equivalent stress sqrt(3 J2), J2 = s:s / 2, of a deviatoric
 * stress s (3x3, row-major), Pa. */
static inline real von_mises_equivalent(const real s[9])
{
    real j2 = 0;
    for (int k = 0; k < 9; ++k)
        j2 += (real)0.5 * s[k] * s[k];
    return sqrt((real)3 * j2);
}

/* von Mises radial return (thesis eqs. 3.33-3.34; Wilkins 1964): the
 * deviatoric stress s (3x3, row-major) is scaled by min(1, sigma_y /
 * sqrt(3 J2)). Returns the equivalent plastic strain increment
 * (sqrt(3 J2) - sigma_y) / (3 G), 0 when elastic. */
static inline real radial_return(real s[9], real yield_stress, real shear_modulus)
{
    const real equivalent = von_mises_equivalent(s);
    if (yield_stress < 0 || equivalent <= yield_stress)
        return 0;
    const real f = yield_stress / equivalent;
    for (int k = 0; k < 9; ++k)
        s[k] *= f;
    return (equivalent - yield_stress) / ((real)3 * shear_modulus);
}

#endif /* SPH_MATERIAL_MODELS_CL */
