/* The health watch (host/run_parts.h): the case's thresholds (case_health)
 * against each history row's indicators and each snapshot's neighbour
 * counts. The first crossing is recorded and, with health.stop, stops the
 * run; the energy threshold is checked once at the end, against the run's
 * largest energy (early rows of a loaded run have almost no energy to
 * compare with). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "checkpoint.h"
#include "run_parts.h"

int health_watch_open(struct health_watch *h, struct solver *s, int count_now)
{
    h->min_pair_distance = HUGE_VAL;
    h->first_unhealthy_time = -1;
    h->initial_neighbours = CHECKED_CALLOC((size_t)s->n_scene + 1, sizeof(int), "neighbour counts");
    h->neighbours = CHECKED_CALLOC((size_t)s->n_scene + 1, sizeof(int), "neighbour counts");
    h->damaged = CHECKED_CALLOC((size_t)s->n_scene + 1, 1, "damage marks");
    if (!h->initial_neighbours || !h->neighbours || !h->damaged)
        return 1;
    h->baseline_updates = -1; /* a resumed run counts its reference's at the first snapshot */
    if (count_now) {
        solver_neighbour_counts(s, h->initial_neighbours, 1);
        h->baseline_updates = s->reference_updates;
    }
    return 0;
}

void health_watch_records(struct health_watch *h, int n, struct checkpoint *k, int load)
{
    CHECKPOINT_RECORD(k, "health.", h->min_pair_distance, load);
    CHECKPOINT_RECORD(k, "health.", h->max_clumped, load);
    CHECKPOINT_RECORD(k, "health.", h->max_swegle, load);
    CHECKPOINT_RECORD(k, "health.", h->first_unhealthy_time, load);
    CHECKPOINT_RECORD(k, "health.", h->reason, load);
    CHECKPOINT_RECORD(k, "health.", h->stop, load);
    CHECKPOINT_RECORD(k, "health.", h->max_neighbour_loss, load);
    /* the neighbours array is scratch */
    checkpoint_record(k, "health.initial_neighbours", h->initial_neighbours,
                      sizeof(int) * (size_t)n, load);
    checkpoint_record(k, "health.damaged", h->damaged, (size_t)n, load);
}

void health_watch_close(struct health_watch *h)
{
    free(h->initial_neighbours);
    free(h->neighbours);
    free(h->damaged);
    h->initial_neighbours = h->neighbours = NULL;
    h->damaged = NULL;
}

/* Records the first crossing; returns non-zero when health.stop asks to stop. */
static int unhealthy(struct health_watch *h, const struct sph_case *c, struct run_clock at,
                     char *message, size_t size)
{
    h->first_unhealthy_time = at.t;
    if (!at.quiet)
        fprintf(stderr, "\nsph: unhealthy at t = %.6e s, step %ld: %s\n", at.t, at.step, h->reason);
    if (!c->health.stop)
        return 0;
    snprintf(message, size, "stopped unhealthy at step %ld, t = %.6e s: %s", at.step, at.t,
             h->reason);
    return 1;
}

int health_watch_row(struct health_watch *h, const struct sph_case *c,
                     const struct health_reading *r, struct run_clock at, char *message,
                     size_t size)
{
    const struct case_health *limit = &c->health;
    const double dx = c->numerics.dx;
    h->min_pair_distance = fmin(h->min_pair_distance, r->min_pair_distance / dx);
    h->max_clumped = fmax(h->max_clumped, r->clumped_fraction);
    h->max_swegle = fmax(h->max_swegle, r->swegle_fraction);
    if (h->first_unhealthy_time >= 0)
        return 0;
    if (r->min_pair_distance < limit->min_pair_distance * dx)
        snprintf(h->reason, sizeof h->reason, "smallest pair distance %.3g dx below %.3g dx",
                 r->min_pair_distance / dx, limit->min_pair_distance);
    else if (r->clumped_fraction > limit->clumped_fraction)
        snprintf(h->reason, sizeof h->reason, "%.3g%% of particles clumped (%s), above %.3g%%",
                 100 * r->clumped_fraction,
                 c->numerics.total_lagrangian
                     ? "a neighbour closer than half the separation their deformation gives "
                       "the pair"
                     : "a neighbour closer than dx/2",
                 100 * limit->clumped_fraction);
    else
        return 0;
    return unhealthy(h, c, at, message, size);
}

void health_watch_integrity(struct health_watch *h, struct solver *s, const struct sph_case *c,
                            struct run_clock at, char *message, size_t size)
{
    /* the total Lagrangian form measures a loss against the reference of
     * now: after a reference update, the neighbours it was taken with (the
     * set does not change until the next, so counting them at a later
     * snapshot gives the same) */
    if (s->total_lagrangian && h->baseline_updates != s->reference_updates) {
        solver_neighbour_counts(s, h->initial_neighbours, 1);
        h->baseline_updates = s->reference_updates;
    }
    solver_neighbour_counts(s, h->neighbours, 0);
    if (cl_failed()) /* the counts were not read: the run is unwinding */
        return;
    int lost = 0;
    for (int p = 0; p < s->n_scene; ++p) /* failed material may separate */
        lost += 3 * h->neighbours[p] < 2 * h->initial_neighbours[p] && !h->damaged[p];
    const double fraction = (double)lost / s->n_scene;
    h->max_neighbour_loss = fmax(h->max_neighbour_loss, fraction);
    if (lost == 0 || h->first_unhealthy_time >= 0)
        return;
    /* a tear is seen at snapshot times only (it needs the neighbour counts) */
    snprintf(h->reason, sizeof h->reason,
             "torn: %.3g%% of particles lost a third of their initial neighbours (seen at the "
             "snapshot at step %ld)",
             100 * fraction, at.step);
    h->stop = unhealthy(h, c, at, message, size);
}

void health_watch_energy(struct health_watch *h, const struct sph_case *c, double drift, double t)
{
    if (h->first_unhealthy_time >= 0 || c->numerics.damping != 0 ||
        !(drift > c->health.energy_error))
        return;
    h->first_unhealthy_time = t;
    snprintf(h->reason, sizeof h->reason, "energy drift %.3g above %.3g over the run", drift,
             c->health.energy_error);
}
