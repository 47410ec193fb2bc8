/* The run's energy ledger (host/run_parts.h): the powers the step's
 * reduction returns, integrated step by step, and the balance they close. */
#include <math.h>
#include <string.h>

#include "run_parts.h"

double ledger_total(const struct energy_ledger *e, const struct reduction *red, double projectile)
{
    return red->kinetic + red->internal - e->external_work - e->wall_work - e->driver_work +
           e->hourglass_work + projectile;
}

void ledger_step(struct energy_ledger *e, const struct reduction *red, double dt, double projectile)
{
    e->external_work += red->load_power * dt;   /* F(t^n) . v^(n+1/2) dt */
    e->wall_work += red->wall_power * dt;       /* f(x^n) . v^(n+1/2) dt, as the load */
    e->viscous_work += red->viscous_power * dt; /* the heating pass 2 gave the step */
    e->hourglass_work += red->hourglass_power * dt;
    for (int a = 0; a < 3; ++a)
        e->wall_impulse[a] += red->wall_force[a] * dt;
    e->impulse_since_row += dt;
    e->scale = fmax(e->scale, fmax(fabs(e->external_work) + fabs(e->driver_work),
                                   red->kinetic + fabs(red->internal) + projectile));
}

void ledger_watch(struct energy_ledger *e, const struct reduction *red, double projectile)
{
    e->excursion = fmax(e->excursion, fabs(ledger_total(e, red, projectile) - e->start));
}

void ledger_take_wall_force(struct energy_ledger *e, const struct reduction *red, double force[3])
{
    for (int a = 0; a < 3; ++a) {
        /* a held wall's force is not summed anywhere: along its normal the
         * particles' momentum change stands for it (with every other wall's
         * and any load's force along that normal: host/run_parts.h) */
        const double impulse =
            (e->held_axes >> a) & 1u ? e->row_momentum[a] - red->momentum[a] : -e->wall_impulse[a];
        force[a] = e->impulse_since_row > 0 ? impulse / e->impulse_since_row : 0.0;
        e->row_momentum[a] = red->momentum[a];
    }
    memset(e->wall_impulse, 0, sizeof e->wall_impulse);
    e->impulse_since_row = 0;
}

double ledger_drift(const struct energy_ledger *e)
{
    return e->scale > 0 ? e->excursion / e->scale : 0;
}
