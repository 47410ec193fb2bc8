/* The concerns of the run loop (host/run.c), each a small struct with its
 * own functions: the energy ledger (host/ledger.c), the health watch
 * (host/health_watch.c), the impact figures of a snapshot (host/impact.c)
 * and what the run tracks of a projectile (host/ballistics_track.c). The
 * loop owns one of each and calls them at steps, history rows, snapshots
 * and the end. */
#ifndef SPH_RUN_PARTS_H
#define SPH_RUN_PARTS_H

#include "output.h"
#include "solver.h"
#include "sph_case.h"

/* ---- energy ledger: E = K + U - W_loads - W_walls - W_driver + W_hourglass
 * (+ the sphere's share) and the work the artificial viscosity turned into heat */
struct energy_ledger {
    double external_work;  /* J: work of the loads, F(t^n) . v^(n+1/2) dt summed */
    double wall_work;      /* J: work the walls did on the particles */
    double viscous_work;   /* J: heat made by the artificial viscosity (in U) */
    double hourglass_work; /* J: work the hourglass forces took out of the motion */
    double driver_work;    /* J: work of the force holding a prescribed projectile's speed */
    double wall_impulse[3], impulse_since_row; /* N s and s since the last history row */
    double start;                              /* the total at t = 0, J */
    double scale;                              /* the largest energy so far, J */
    double excursion;                          /* the largest |E - E(0)| so far, J */
    double kinetic_start;   /* particles' and projectile's kinetic energy at t = 0, J */
    unsigned held_axes;     /* bit a: a held wall's normal lies along axis a */
    double row_momentum[3]; /* the particles' momentum at the last row, kg m/s */
};
/* the total; `projectile` is the sphere's share of the model's energy, J */
double ledger_total(const struct energy_ledger *e, const struct reduction *red, double projectile);
/* one step of length dt: the powers of the reduction integrated */
void ledger_step(struct energy_ledger *e, const struct reduction *red, double dt,
                 double projectile);
/* track |E - E(0)| (each step without a projectile, at rows with one, when
 * its energy is read) */
void ledger_watch(struct energy_ledger *e, const struct reduction *red, double projectile);
/* the mean force on the walls since the last row (the reaction: minus the
 * force on the particles), N; starts the next interval. A held wall (a
 * symmetry plane) has no contact force of its own: along its normal the
 * force is minus the particles' momentum change over the interval (every
 * wall's force along it, and a load's or a projectile's too) */
void ledger_take_wall_force(struct energy_ledger *e, const struct reduction *red, double force[3]);
/* drift over the run: excursion over the largest energy */
double ledger_drift(const struct energy_ledger *e);

/* ---- health: the case's thresholds against each row and snapshot */
struct health_watch {
    double min_pair_distance;             /* over dx, smallest so far */
    double max_clumped, max_swegle;       /* fractions, largest so far */
    double first_unhealthy_time;          /* s; < 0 while healthy */
    char reason[256];                     /* why, from the first crossing */
    int stop;                             /* a snapshot found a tear and health.stop asks to stop */
    int *initial_neighbours, *neighbours; /* per particle, by id */
    long baseline_updates;     /* total Lagrangian: the reference initial_neighbours counts on */
    char *damaged;             /* per particle (by id), from the last snapshot */
    double max_neighbour_loss; /* largest fraction that lost a third of its neighbours */
};
/* where and when, for the messages */
struct run_clock {
    double t;
    long step;
    int quiet;
};
/* count_now: the initial neighbour counts from the solver (not on resume:
 * health_watch_records gives them) */
int health_watch_open(struct health_watch *h, struct solver *s, int count_now);
struct checkpoint;
/* its records in a checkpoint, written (load 0) or read (load 1) */
void health_watch_records(struct health_watch *h, int n, struct checkpoint *k, int load);
void health_watch_close(struct health_watch *h);
/* a history row's indicators: returns non-zero (and writes `message`) when
 * the run must stop (health.stop) */
int health_watch_row(struct health_watch *h, const struct sph_case *c,
                     const struct health_reading *r, struct run_clock at, char *message,
                     size_t size);
/* a snapshot's neighbour counts: a tear; sets h->stop when health.stop */
void health_watch_integrity(struct health_watch *h, struct solver *s, const struct sph_case *c,
                            struct run_clock at, char *message, size_t size);
/* the energy threshold, checked once at the end against the run's drift */
void health_watch_energy(struct health_watch *h, const struct sph_case *c, double drift, double t);

/* ---- impact figures of a snapshot (Taylor bars, damage) */
struct impact_metrics {
    double final_length, footprint_radius;      /* m, against walls[0] */
    double max_plastic_strain, max_temperature; /* largest over the snapshots */
    double damaged_fraction;                    /* largest over the snapshots */
};
/* also marks damaged[p] for the health watch's tear test */
void impact_measure(struct impact_metrics *m, const struct sph_case *c, const struct host_fields *f,
                    char *damaged);

/* ---- what the run tracks of a projectile (ballistics.csv, summary) */
struct ballistics_track {
    double energy;      /* the sphere's share of the model's energy at the last row, J */
    double driver_work; /* the share of the work done holding a prescribed sphere, J */
    double momentum0;   /* sphere plus target along the axis at t = 0, kg m/s */
    double max_penetration, time_of_max, final_penetration, final_velocity;
    double max_d1, max_d2, momentum_error;
    double left_fine_time;             /* s: nose first in a graded body's coarse shells; < 0 */
    double max_lateral, final_lateral; /* centre's distance from the shot line, m */
    double exit_time;                  /* s: the sphere first through the target; < 0 */
};
void ballistics_track_start(struct ballistics_track *b);
/* reads the projectile, updates the extremes, writes the ballistics.csv row */
void ballistics_track_row(struct ballistics_track *b, struct solver *s, const struct sph_case *c,
                          const struct reduction *red, struct run_clock at, struct output *out);
void ballistics_track_summary(const struct ballistics_track *b, struct run_summary *sum);

#endif
