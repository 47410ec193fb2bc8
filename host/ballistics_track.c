/* What the run tracks of a projectile (host/run_parts.h): each history row
 * reads the sphere (host/ballistics.c), writes ballistics.csv and keeps the
 * extremes the summary reports; it says when the nose leaves a graded
 * body's fine region and when the sphere is through the target. */
#include <math.h>
#include <stdio.h>

#include "run_parts.h"
#include "scene.h"

void ballistics_track_start(struct ballistics_track *b)
{
    b->left_fine_time = -1;
    b->exit_time = -1;
}

/* Whether point x lies in a graded body but not in its finest level: where
 * the lattice does not refine with numerics.dx. */
static int in_coarse_shells(const struct sph_case *c, const double x[3])
{
    for (int b = 0; b < c->body_count; ++b) {
        const struct case_body *body = &c->bodies[b];
        if (!body->grading.enabled)
            continue;
        int in_body = 1;
        for (int a = 0; a < c->dimension; ++a)
            in_body &= x[a] >= body->box.min[a] && x[a] <= body->box.max[a];
        if (in_body && grading_level_at(c, body, x) > 0)
            return 1;
    }
    return 0;
}

/* Records the first time of an event (*when < 0 until then); returns
 * whether to say so now. */
static int first_time(double *when, struct run_clock at)
{
    if (*when >= 0)
        return 0;
    *when = at.t;
    return !at.quiet;
}

/* The first time the sphere's nose enters coarse shells: the depth from
 * then on is not refined by numerics.dx, so a convergence study must not
 * reach it (docs/shock_capturing.md, SEBS). */
static void watch_fine_region(struct ballistics_track *b, const struct projectile *proj,
                              const struct sph_case *c, const struct projectile_reading *p,
                              struct run_clock at)
{
    double nose[3];
    for (int a = 0; a < 3; ++a)
        nose[a] = p->position[a] + proj->radius * proj->axis[a];
    if (b->left_fine_time < 0 && in_coarse_shells(c, nose) && first_time(&b->left_fine_time, at))
        fprintf(stderr,
                "\nsph: at t = %.6e s the sphere's nose (%.4g m deep) left the graded lattice's "
                "fine region: from here on its depth does not refine with numerics.dx\n",
                at.t, p->penetration);
}

/* The first row with the whole sphere past the target's initial exit face
 * on its track: it perforated, and its speed from then on is the residual
 * velocity. */
static void watch_perforation(struct ballistics_track *b, const struct projectile_reading *p,
                              struct run_clock at)
{
    if (p->through && first_time(&b->exit_time, at))
        fprintf(stderr,
                "\nsph: at t = %.6e s the sphere is through the target (perforated) at "
                "%.6g m/s\n",
                at.t, p->speed_along_axis);
}

static void track_extremes(struct ballistics_track *b, const struct projectile *p,
                           const struct projectile_reading *r, double t)
{
    if (r->penetration > b->max_penetration) {
        b->max_penetration = r->penetration;
        b->time_of_max = t;
    }
    b->final_penetration = r->penetration;
    b->max_lateral = fmax(b->max_lateral, r->lateral_deflection);
    b->final_lateral = r->lateral_deflection;
    b->final_velocity = r->speed_along_axis;
    for (int k = 0; k < p->probe_count; ++k) {
        b->max_d1 = fmax(b->max_d1, r->cavity_d1[k]);
        b->max_d2 = fmax(b->max_d2, r->cavity_d2[k]);
    }
}

void ballistics_track_row(struct ballistics_track *b, struct solver *s, const struct sph_case *c,
                          const struct reduction *red, struct run_clock at, struct output *out)
{
    const struct projectile *p = &s->projectile;
    struct ballistics_row row = {.time = at.t};
    solver_projectile_read(s, &row.p);
    double speed2 = 0, target = 0;
    for (int a = 0; a < 3; ++a) {
        speed2 += row.p.velocity[a] * row.p.velocity[a];
        target += red->momentum[a] * p->axis[a];
    }
    row.projectile_kinetic = 0.5 * p->mass * speed2;
    /* under prescribed motion the force holding the sphere is external: its
     * impulse and work leave the balances closed */
    row.system_momentum = p->momentum_scale * target + p->mass * row.p.speed_along_axis -
                          row.p.driver_impulse_along_axis;
    /* the particle sums are the modelled part's (a quarter with two symmetry
     * planes), the sphere's figures the whole sphere's: the ledger takes
     * the sphere's share of the model */
    b->energy =
        (row.projectile_kinetic + row.p.contact_energy + row.p.dissipated) / p->momentum_scale;
    b->driver_work = row.p.driver_work / p->momentum_scale;
    if (at.step == 0)
        b->momentum0 = row.system_momentum;
    b->momentum_error =
        fmax(b->momentum_error, fabs(row.system_momentum - b->momentum0) / fabs(b->momentum0));
    track_extremes(b, p, &row.p, at.t);
    watch_perforation(b, &row.p, at);
    watch_fine_region(b, p, c, &row.p, at);
    output_ballistics(out, &row);
}

void ballistics_track_summary(const struct ballistics_track *b, struct run_summary *sum)
{
    sum->max_penetration_m = b->max_penetration;
    sum->time_of_max_penetration_s = b->time_of_max;
    sum->final_penetration_m = b->final_penetration;
    sum->final_projectile_velocity_m_per_s = b->final_velocity;
    sum->max_cavity_diameter_m = b->max_d1;
    sum->max_damaged_diameter_m = b->max_d2;
    sum->left_fine_region_time_s = b->left_fine_time;
    sum->max_lateral_deflection_m = b->max_lateral;
    sum->final_lateral_deflection_m = b->final_lateral;
    sum->exit_time_s = b->exit_time;
    sum->momentum_error = b->momentum_error;
}
