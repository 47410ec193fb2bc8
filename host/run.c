/* The time loop of `sph run`: step, watch health, write outputs, report. */
#include "profile.h"
#include "run.h"

#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "checkpoint.h"
#include "device.h"
#include "domain.h"
#include "output.h"
#include "run_parts.h"
#include "scene.h"
#include "solver.h"

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Everything the loop carries from step to step: the stepping state here,
 * each other concern in its own struct (host/run_parts.h). */
struct loop {
    const struct sph_case *c;
    const struct run_options *opt;
    struct solver *s;
    struct output *out;
    const struct sph_scene *scene;
    double t, dt, dt_cfl, dt_prev, dt_initial;
    long step;
    double next_history, next_snapshot, next_progress_wall, wall_start;
    double next_checkpoint;      /* simulated s; HUGE_VAL without output.checkpoint_interval */
    double next_checkpoint_wall; /* wall-clock s (wall_seconds) */
    long first_step;             /* where this process began: 0, or the checkpoint's */
    long raise_at_step;          /* SPH_RAISE_AT_STEP=N: SIGINT after step N (tests); else -1 */
    int raise_count;             /* SPH_RAISE_COUNT: how many SIGINTs then (default 1) */
    double first_t;
    double probe, window_sum, window_error_sum;
    long window_steps;
    struct energy_ledger energy;
    struct health_watch health;
    struct impact_metrics impact;
    struct ballistics_track ballistics;
    struct reduction red;
    double halo_particles, halo_bytes; /* over several processes, means over the ranks */
    char message[SPH_PATH_MAX + 512];
    const char *status;
};

static struct run_clock clock_of(const struct loop *L)
{
    return (struct run_clock){.t = L->t, .step = L->step, .quiet = L->opt->quiet};
}

/* the sphere's share of the model's energy, J (0 without a projectile) */
static double projectile_energy(const struct loop *L)
{
    return L->s->projectile.enabled ? L->ballistics.energy : 0.0;
}

static double total_energy(const struct loop *L)
{
    return ledger_total(&L->energy, &L->red, projectile_energy(L));
}

static void load_vector(const struct loop *L, double t, double f[3])
{
    const double scale = scene_load_scale(L->scene->load, t);
    for (int a = 0; a < 3; ++a)
        f[a] =
            L->scene->loaded_count ? scale * L->scene->load_force[a] / L->scene->loaded_count : 0.0;
}

static double probe_value(const struct loop *L)
{
    if (!L->c->has_probe)
        return 0.0;
    return L->red.probe_displacement[L->c->probe.quantity];
}

static void track_probe(struct loop *L)
{
    L->probe = probe_value(L);
    const struct case_reference *ref = &L->c->reference;
    if (!L->c->has_probe)
        return;
    const double w0 = ref->enabled ? ref->window[0] : 0.0;
    const double w1 = ref->enabled ? ref->window[1] : L->c->numerics.end_time;
    if (L->t >= w0 && L->t <= w1 * (1 + 1e-12)) {
        L->window_sum += L->probe;
        if (ref->enabled)
            L->window_error_sum += fabs(L->probe - ref->value) / fabs(ref->value);
        ++L->window_steps;
    }
}

/* The health indicators of this row against the case's thresholds; returns
 * non-zero to stop (health.stop). */
static int watch_health(struct loop *L, struct history_row *row)
{
    solver_health(L->s, &row->health);
    if (sph_profiler) /* the neighbour passes' pair count until the next row */
        sph_profiler->pairs_per_call = row->health.neighbours_mean * L->s->n_real;
    row->energy_error =
        L->energy.scale > 0 ? (total_energy(L) - L->energy.start) / L->energy.scale : 0.0;
    if (!health_watch_row(&L->health, L->c, &row->health, clock_of(L), L->message,
                          sizeof L->message))
        return 0;
    L->status = "unhealthy";
    return 1;
}

static int write_history(struct loop *L)
{
    if (L->s->projectile.enabled) {
        ballistics_track_row(&L->ballistics, L->s, L->c, &L->red, clock_of(L), L->out);
        L->energy.driver_work = L->ballistics.driver_work;
        ledger_watch(&L->energy, &L->red, projectile_energy(L));
    }
    struct history_row row = {.time = L->t,
                              .dt = L->dt,
                              .step = L->step,
                              .probe = L->probe,
                              .kinetic = L->red.kinetic,
                              .internal = L->red.internal,
                              .external_work = L->energy.external_work,
                              .max_speed = L->red.max_speed};
    memcpy(row.momentum, L->red.momentum, sizeof row.momentum);
    row.wall_work = L->energy.wall_work;
    row.viscous_work = L->energy.viscous_work;
    row.hourglass_work = L->energy.hourglass_work;
    row.total_energy = total_energy(L);
    ledger_take_wall_force(&L->energy, &L->red, row.wall_force);
    row.dx = L->c->numerics.dx;
    const int stop = watch_health(L, &row);
    output_history(L->out, &row);
    return stop;
}

static int write_snapshot(struct loop *L)
{
    struct host_fields f;
    char error[512];
    struct snapshot_meta meta = {.time = L->t, .step = L->step};
    if (solver_read_fields(L->s, &f))
        return 0; /* out of host memory: recorded, the loop stops at its next check */
    if (L->s->projectile.enabled)
        solver_projectile_motion(L->s, meta.projectile_centre, meta.projectile_velocity);
    const int status = output_snapshot(L->out, &f, &meta, error, sizeof error);
    impact_measure(&L->impact, L->c, &f, L->health.damaged);
    host_fields_free(&f);
    /* rank 0 writes; every rank stops with it */
    if (dist_bcast_int(status) && dist_rank() != 0)
        return snprintf(L->message, sizeof L->message,
                        "at step %ld, t = %.6e s: rank 0 could not "
                        "write the snapshot",
                        L->step, L->t) > 0;
    if (status) {
        fprintf(stderr, "sph: %s\n", error);
        snprintf(L->message, sizeof L->message, "at step %ld, t = %.6e s: %s", L->step, L->t,
                 error);
        return status;
    }
    health_watch_integrity(&L->health, L->s, L->c, clock_of(L), L->message, sizeof L->message);
    if (L->health.stop)
        L->status = "unhealthy";
    return status;
}

/* "42 s", "12 min 05 s", "2 h 27 min": an ETA a person reads at a glance
 * ("?" before there is one; a collapsing time step's ETA stays in hours) */
static void format_duration(char *text, size_t size, double seconds)
{
    if (!(seconds >= 0) || !isfinite(seconds)) {
        snprintf(text, size, "?");
        return;
    }
    if (seconds >= 1e9) {
        snprintf(text, size, "%.3g h", seconds / 3600);
        return;
    }
    const long s = (long)(seconds + 0.5);
    if (s < 60)
        snprintf(text, size, "%ld s", s);
    else if (s < 3600)
        snprintf(text, size, "%ld min %02ld s", s / 60, s % 60);
    else
        snprintf(text, size, "%ld h %02ld min", s / 3600, (s % 3600) / 60);
}

static void progress(struct loop *L, int final)
{
    const double now = wall_seconds();
    if (!final && now < L->next_progress_wall)
        return;
    const double elapsed = now - L->wall_start, end = L->c->numerics.end_time;
    /* over this process's steps: a resumed run began at first_step */
    const double rate = elapsed > 0 ? (L->step - L->first_step) / elapsed : 0;
    const double eta = L->t > L->first_t ? elapsed * (end - L->t) / (L->t - L->first_t) : 0;
    if (L->opt->quiet)
        return;
    char eta_text[32];
    format_duration(eta_text, sizeof eta_text, eta);
    /* a large 3-D run takes about one step a second: two decimals there */
    const int rate_decimals = rate < 10 ? 2 : 0;
    const int tty = isatty(fileno(stderr));
    fprintf(stderr, "%s  t = %.4e s (%5.1f%%)  step %ld  %.*f steps/s  ETA %s%s", tty ? "\r" : "",
            L->t, 100 * L->t / end, L->step, rate_decimals, rate, eta_text,
            tty ? (final ? "   \n" : "   ") : "\n");
    L->next_progress_wall = now + (tty ? 0.5 : 10.0);
    fflush(stderr);
}

/* Returns 0 while the run is healthy; otherwise fills message/status. */
static int check_health(struct loop *L)
{
    if (L->red.bad_id >= 0) {
        const long id = L->red.bad_id;
        const double *x = &L->scene->position[3 * id];
        snprintf(L->message, sizeof L->message,
                 "unstable at step %ld, t = %.6e s: particle %ld (initially at %.6g, %.6g, %.6g m) "
                 "has a non-finite state or a speed above %.4g m/s (max speed %.4g m/s)",
                 L->step, L->t, id, x[0], x[1], x[2], (double)L->s->run.velocity_limit,
                 L->red.max_speed);
        L->status = "unstable";
        return 1;
    }
    if (L->dt_cfl < 1e-3 * L->dt_initial) {
        snprintf(L->message, sizeof L->message,
                 "unstable at step %ld, t = %.6e s: the time step collapsed to %.3e s (from "
                 "%.3e s): max signal speed %.4g m/s",
                 L->step, L->t, L->dt_cfl, L->dt_initial, L->red.max_signal);
        L->status = "unstable";
        return 1;
    }
    return 0;
}

static int one_step(struct loop *L)
{
    double load[3];
    load_vector(L, L->t, load); /* F(t^n): the kick of this step uses it */
    const double end = L->c->numerics.end_time;
    L->dt_cfl = solver_time_step(L->s, L->c->numerics.cfl, L->red.max_signal);
    L->dt = L->dt_cfl;
    if (L->t + L->dt > end)
        L->dt = fmax(end - L->t, 1e-30);
    char error[512];
    const long updates = L->s->reference_updates;
    if (solver_advance(L->s, L->dt, L->dt_prev, load, &L->red, error, sizeof error)) {
        snprintf(L->message, sizeof L->message, "unstable at step %ld, t = %.6e s: %s", L->step,
                 L->t, error);
        L->status = "unstable";
        return 1;
    }
    L->t += L->dt;
    L->dt_prev = L->dt;
    ++L->step;
    if (L->s->reference_updates > updates && !L->opt->quiet)
        fprintf(stderr,
                "%st = %.4e s, step %ld: largest Green strain %.4g reached numerics."
                "reference_update (%g): the configuration of now is the reference (update %ld)\n",
                isatty(fileno(stderr)) ? "\n" : "", L->t, L->step, L->red.max_distortion,
                L->s->reference_update, L->s->reference_updates);
    ledger_step(&L->energy, &L->red, L->dt, projectile_energy(L));
    if (!L->s->projectile.enabled) /* else at history rows, when its energy is read */
        ledger_watch(&L->energy, &L->red, 0.0);
    track_probe(L);
    return check_health(L);
}

static void finish_summary(struct loop *L, struct run_summary *sum)
{
    const double wall = wall_seconds() - L->wall_start;
    memset(sum, 0, sizeof *sum);
    sum->case_name = L->c->name;
    sum->device = L->s->dev->name;
    sum->status = L->status;
    sum->message = L->message;
    sum->precision = L->c->numerics.double_precision ? "double" : "float";
    sum->neighbour_loop = L->s->lanes > 1 ? "lanes" : "plain";
    sum->neighbour_lanes = L->s->lanes;
    sum->grid_sorts = L->s->sorts;
    if (L->s->lane_lists && L->s->n > 0) {
        sum->lane_list_candidates =
            (double)L->s->lane_list_entries / (double)solver_lane_blocks(L->s);
        sum->lane_list_bytes = (double)solver_lane_list_bytes(L->s) / L->s->n_real;
    }
    sum->particles = L->s->n_scene;
    sum->dimension = L->c->dimension;
    sum->steps = L->step;
    sum->end_time = L->t;
    sum->wall_time_s = wall;
    sum->steps_per_s = wall > 0 ? (L->step - L->first_step) / wall : 0;
    sum->bytes_per_particle = solver_bytes_per_particle(L->s);
    sum->processes = dist_size();
    sum->migrated_particles = L->s->domain.migrated;
    sum->rebalances = L->s->domain.rebalances;
    const long steps = L->step - L->first_step;
    sum->halo_particles = L->halo_particles;
    sum->halo_bytes_per_step = steps > 0 ? L->halo_bytes / steps : 0;
    sum->has_probe = L->c->has_probe;
    sum->probe_name = L->c->has_probe ? L->c->probe.name : "";
    sum->probe_final = L->probe;
    sum->probe_mean = L->window_steps ? L->window_sum / L->window_steps : NAN;
    sum->has_reference = L->c->reference.enabled;
    sum->reference = L->c->reference.value;
    sum->reference_error_final = fabs(L->probe - sum->reference) / fabs(sum->reference);
    sum->reference_e_av = L->window_steps ? L->window_error_sum / L->window_steps : NAN;
    sum->energy_drift = ledger_drift(&L->energy);
    sum->max_neighbour_loss_fraction = L->health.max_neighbour_loss;
    /* over the initial kinetic energy, or the largest energy of a run that
     * starts at rest */
    const struct energy_ledger *e = &L->energy;
    const double work_scale = e->kinetic_start > 0 ? e->kinetic_start : e->scale;
    sum->viscous_work_J = e->viscous_work;
    sum->hourglass_work_J = e->hourglass_work;
    sum->viscous_work_fraction = work_scale > 0 ? e->viscous_work / work_scale : 0;
    sum->hourglass_work_fraction = work_scale > 0 ? e->hourglass_work / work_scale : 0;
    sum->has_hourglass = L->s->total_lagrangian;
    sum->reference_updates = L->s->reference_updates;
    sum->has_wall = L->c->wall_count > 0;
    sum->final_length_m = L->impact.final_length;
    sum->footprint_radius_m = L->impact.footprint_radius;
    for (int m = 0; m < L->c->material_count; ++m)
        sum->has_plasticity |= L->c->materials[m].strength != SPH_STRENGTH_ELASTIC;
    sum->max_plastic_strain = L->impact.max_plastic_strain;
    sum->max_temperature_K = L->impact.max_temperature;
    sum->min_pair_distance_over_dx = L->health.min_pair_distance;
    sum->max_clumped_fraction = L->health.max_clumped;
    sum->max_swegle_fraction = L->health.max_swegle;
    if (!cl_failed()) /* a stopped device's last figures are not the run's */
        health_watch_energy(&L->health, L->c, sum->energy_drift, L->t);
    sum->first_unhealthy_time = L->health.first_unhealthy_time;
    sum->unhealthy_reason = L->health.reason;
    sum->has_projectile = L->s->projectile.enabled;
    ballistics_track_summary(&L->ballistics, sum);
    sum->damaged_fraction = L->impact.damaged_fraction;
}

static void print_summary_line(const struct run_summary *sum, const char *folder)
{
    printf("%s: %s", sum->case_name, sum->status);
    if (sum->max_neighbour_loss_fraction > 0)
        printf(" (not whole: %.2f%% of particles lost over a third of their neighbours)",
               100 * sum->max_neighbour_loss_fraction);
    if (sum->first_unhealthy_time >= 0)
        printf(" (unhealthy from t = %.4g s: %s)", sum->first_unhealthy_time,
               sum->unhealthy_reason);
    if (sum->has_probe) {
        printf(" | %s final %.4f mm", sum->probe_name, 1e3 * sum->probe_final);
        if (isnan(sum->probe_mean)) /* the run ended before the averaging window */
            printf(", no mean (window not reached)");
        else
            printf(", mean %.4f mm", 1e3 * sum->probe_mean);
        if (sum->has_reference) {
            printf(" vs reference %.4f mm: ", 1e3 * sum->reference);
            if (!isnan(sum->reference_e_av))
                printf("e_av %.2f%%, ", 100 * sum->reference_e_av);
            printf("final error %.2f%%", 100 * sum->reference_error_final);
        }
    }
    if (sum->has_projectile && sum->exit_time_s >= 0)
        printf(" | perforated at %.4g s, residual velocity %.4g m/s", sum->exit_time_s,
               sum->final_projectile_velocity_m_per_s);
    else if (sum->has_projectile)
        printf(" | P_max %.4g um at %.4g ns", 1e6 * sum->max_penetration_m,
               1e9 * sum->time_of_max_penetration_s);
    printf(" | %d particles, %ld steps, %.1f s wall, %.*f steps/s", sum->particles, sum->steps,
           sum->wall_time_s, sum->steps_per_s < 10 ? 2 : 0, sum->steps_per_s);
    if (dist_size() > 1)
        printf(", %d processes", dist_size());
    printf(" | %s\n", folder);
}

/* write_history or write_snapshot, timed apart when profiling: its host
 * time less the kernels it launches (the health indicators at each history
 * row), which the kernels' time holds (counted in both, the profile's "the
 * rest" came out negative). */
static int timed_output(struct loop *L, int (*write)(struct loop *))
{
    struct profiler *p = sph_profiler;
    double t0 = 0, device0 = 0;
    if (p) {
        profile_flush(p); /* the step's kernels end before the clock starts */
        t0 = profile_clock();
        device0 = profile_device_seconds(p);
    }
    const int result = write(L);
    if (p) {
        profile_flush(p);
        p->host_output_s += profile_clock() - t0 - (profile_device_seconds(p) - device0);
    }
    return result;
}

/* After an OpenCL failure (host/device.h) the run stops where it is: no
 * output is written from a device that no longer answers. */
static int device_failed(struct loop *L)
{
    if (!cl_failed())
        return 0;
    L->status = cl_failure_status();
    snprintf(L->message, sizeof L->message, "at step %ld, t = %.6e s: %s", L->step, L->t,
             cl_failure());
    if (dist_size() > 1) { /* the other ranks wait in a collective: end them all */
        fprintf(stderr, "sph: rank %d of %d stopped %s\n", dist_rank(), dist_size(), L->message);
        dist_abort(2);
    }
    return 1;
}

/* ---- checkpoints and interruption */

/* The loop's own records in a checkpoint: the stepping state and each
 * concern's plain struct (host/run_parts.h), written (load 0) or read
 * (load 1); the solver, the health watch and the outputs keep their own. */
static void loop_records(struct loop *L, struct checkpoint *k, int load)
{
    CHECKPOINT_RECORD(k, "loop.", L->t, load);
    CHECKPOINT_RECORD(k, "loop.", L->dt, load);
    CHECKPOINT_RECORD(k, "loop.", L->dt_cfl, load);
    CHECKPOINT_RECORD(k, "loop.", L->dt_prev, load);
    CHECKPOINT_RECORD(k, "loop.", L->dt_initial, load);
    CHECKPOINT_RECORD(k, "loop.", L->step, load);
    CHECKPOINT_RECORD(k, "loop.", L->next_history, load);
    CHECKPOINT_RECORD(k, "loop.", L->next_snapshot, load);
    CHECKPOINT_RECORD(k, "loop.", L->next_checkpoint, load);
    CHECKPOINT_RECORD(k, "loop.", L->probe, load);
    CHECKPOINT_RECORD(k, "loop.", L->window_sum, load);
    CHECKPOINT_RECORD(k, "loop.", L->window_error_sum, load);
    CHECKPOINT_RECORD(k, "loop.", L->window_steps, load);
    CHECKPOINT_RECORD(k, "loop.", L->energy, load);
    CHECKPOINT_RECORD(k, "loop.", L->impact, load);
    CHECKPOINT_RECORD(k, "loop.", L->ballistics, load);
    CHECKPOINT_RECORD(k, "loop.", L->red, load);
    health_watch_records(&L->health, L->s->n_scene, k, load);
}

/* Writes RUN_DIR/checkpoint.h5 (host/checkpoint.h), with the resolved case
 * text of the case in memory (sph resume compares the reloaded case's). A
 * failure is reported and the run goes on: the previous checkpoint stays. */
static int write_checkpoint(struct loop *L)
{
    struct checkpoint *k = CHECKED_CALLOC(1, sizeof *k, "the checkpoint");
    size_t length = 0;
    char *text = case_resolved_text(L->c, &length);
    int failed = !k || !text;
    if (!failed && checkpoint_begin(k, L->out->folder) == 0) {
        checkpoint_put(k, "case", text, length);
        solver_checkpoint_records(L->s, k, 0);
        loop_records(L, k, 0);
        output_checkpoint_save(L->out, k);
        if (cl_failed()) /* the device did not answer: the records are not the state */
            k->failed = 1, snprintf(k->error, sizeof k->error, "%s", cl_failure());
        failed = checkpoint_end(k); /* closes the file; removes it on a failure */
    } else if (!failed)
        failed = 1; /* checkpoint_begin's error is in k */
    if (failed && !cl_failed())
        fprintf(stderr, "sph: checkpoint not written at t = %.6e s: %s\n", L->t,
                !k      ? "out of host memory"
                : !text ? "the resolved case could not be formatted (out of host memory)"
                        : k->error);
    free(k);
    free(text);
    L->next_checkpoint_wall = wall_seconds() + L->c->output.checkpoint_wall_interval;
    return failed;
}

/* Whether this rank's checkpoint is due. Over several processes every rank
 * writes its file at the same step: the simulated-time trigger is the same
 * everywhere, the wall-clock one is taken when any rank's is due (the
 * loop's agreement, below). */
static int checkpoint_due(const struct loop *L)
{
    const struct case_output *o = &L->c->output;
    return L->t >= L->next_checkpoint * (1 - 1e-9) ||
           (o->checkpoint_wall_interval > 0 && wall_seconds() >= L->next_checkpoint_wall);
}

static void next_checkpoint_time(struct loop *L)
{
    while (L->next_checkpoint <= L->t * (1 + 1e-9))
        L->next_checkpoint += L->c->output.checkpoint_interval;
}

/* SIGINT / SIGTERM: the loop finishes its step, writes a checkpoint, a
 * snapshot and summary.json, and exits 128 + the signal; a second signal
 * ends the process at once. */
static volatile sig_atomic_t interrupt_signal;

static void on_interrupt(int signal_number)
{
    if (interrupt_signal) {
        signal(signal_number, SIG_DFL);
        raise(signal_number);
        return;
    }
    interrupt_signal = signal_number;
}

/* Installs the handler (on) or puts back what was there; a signal the
 * parent ignores (a background job of a script) stays ignored. */
static void catch_interrupts(int on)
{
    static struct sigaction previous[2];
    const int signals[2] = {SIGINT, SIGTERM};
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = on_interrupt;
    action.sa_flags = SA_RESTART; /* the device's and HDF5's calls go on */
    sigemptyset(&action.sa_mask);
    if (on)
        interrupt_signal = 0;
    for (int k = 0; k < 2; ++k) {
        if (!on) {
            sigaction(signals[k], &previous[k], NULL);
            continue;
        }
        sigaction(signals[k], NULL, &previous[k]);
        if (previous[k].sa_handler != SIG_IGN)
            sigaction(signals[k], &action, NULL);
    }
}

static int stop_interrupted(struct loop *L)
{
    const int sig = interrupt_signal ? interrupt_signal : SIGINT; /* another rank's */
    const int saved = !dist_any(write_checkpoint(L) != 0);        /* every rank's file */
    timed_output(L, write_snapshot);
    L->status = "interrupted";
    snprintf(L->message, sizeof L->message, "interrupted by %s at step %ld, t = %.6e s; %s%s",
             sig == SIGINT ? "SIGINT" : "SIGTERM", L->step, L->t,
             saved ? "resume with: sph resume "
                   : "no checkpoint could be written now (an earlier one, if any, is still "
                     "there for sph resume) ",
             L->out->folder);
    return 128 + sig;
}

static int time_loop(struct loop *L)
{
    const struct case_output *o = &L->c->output;
    while (L->t < L->c->numerics.end_time * (1 - 1e-12)) {
        if (device_failed(L))
            return 2;
        const struct reduction before = L->red;
        const double t_before = L->t;
        const long step_before = L->step;
        const double probe_before = L->probe;
        const int stopped = one_step(L);
        if (device_failed(L)) { /* the summary keeps the last state the device gave */
            L->red = before, L->t = t_before, L->step = step_before, L->probe = probe_before;
            return 2;
        }
        if (stopped) {
            timed_output(L, write_history);
            timed_output(L, write_snapshot);
            return 3;
        }
        if (L->t >= L->next_history * (1 - 1e-9)) {
            L->next_history += o->history_interval;
            if (timed_output(L, write_history)) { /* unhealthy, and health.stop asks to stop */
                timed_output(L, write_snapshot);
                return 3;
            }
        }
        if (L->t >= L->next_snapshot * (1 - 1e-9)) {
            if (timed_output(L, write_snapshot)) { /* the message says what failed */
                L->status = "output_error";
                return 1;
            }
            L->next_snapshot += o->snapshot_interval;
            if (L->health.stop)
                return 3;
        }
        for (int k = 0; L->step == L->raise_at_step && k < L->raise_count; ++k)
            raise(SIGINT); /* SPH_RAISE_AT_STEP: tests' Ctrl-C, pressed twice or more */
        /* the loop's flags in one collective: every rank stops, or writes
         * its checkpoint, at the same step */
        double agreed[2] = {interrupt_signal != 0, checkpoint_due(L)};
        dist_max(agreed, 2);
        if (agreed[0])
            return stop_interrupted(L);
        if (agreed[1]) {
            next_checkpoint_time(L);
            write_checkpoint(L);
        }
        progress(L, 0);
    }
    if (device_failed(L))
        return 2;
    if (L->out->snapshot_times[L->out->snapshot_count - 1] < L->t)
        timed_output(L, write_snapshot);
    return device_failed(L) ? 2 : 0;
}

/* The per-kernel table on stdout and profile.json in the run folder.
 * Returns non-zero when the file could not be written. */
static int report_profile(struct profiler *p, struct sph_device *dev, long steps,
                          const char *folder)
{
    profile_flush(p);
    struct device_ceilings ceilings = {0, 0};
    char error[256];
    const int have_ceilings = device_ceilings(dev, &ceilings, error, sizeof error) == 0;
    if (!have_ceilings)
        fprintf(stderr, "sph: no device ceilings: %s\n", error);
    printf("profile over %ld steps on %s (ceilings: %.1f GB/s copy, %.1f GFLOP/s FMA)\n", steps,
           dev->name, ceilings.bandwidth_gb_s, ceilings.gflop_s);
    profile_print(p, have_ceilings ? &ceilings : NULL, steps, stdout);
    char path[SPH_PATH_MAX + 32], temporary[SPH_PATH_MAX + 48];
    snprintf(path, sizeof path, "%s/profile.json", folder);
    FILE *f = output_file_begin(path, temporary, sizeof temporary);
    if (!f) {
        fprintf(stderr, "sph: cannot write %s\n", path);
        return 1;
    }
    fprintf(f,
            "{\n  \"device\": \"%s\",\n  \"steps\": %ld,\n  \"wall_s\": %.6g,\n"
            "  \"output_s\": %.6g,\n  \"device_s\": %.6g,\n  \"ceiling_gb_per_s\": %.6g,\n"
            "  \"ceiling_gflop_per_s\": %.6g,\n  \"kernels\": ",
            dev->name, steps, p->wall_s, p->host_output_s, profile_device_seconds(p),
            ceilings.bandwidth_gb_s, ceilings.gflop_s);
    profile_write_json(p, steps, f);
    fprintf(f, "\n}\n");
    return output_file_commit(f, temporary, path);
}

static void default_folder(const struct sph_case *c, char *folder, size_t size)
{
    const time_t now = time(NULL);
    struct tm tm;
    localtime_r(&now, &tm);
    char stamp[32];
    strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
    snprintf(folder, size, "runs/%s-%s", c->name, stamp);
}

static int start(struct loop *L, char *error, size_t size)
{
    if (solver_sort(L->s, error, size))
        return 1;
    solver_prime(L->s);
    const double zero[3] = {0, 0, 0};
    solver_reduce(L->s, zero, &L->red);
    L->dt_initial = solver_time_step(L->s, L->c->numerics.cfl, L->red.max_signal);
    L->dt = L->dt_cfl = L->dt_initial;
    L->energy.start = total_energy(L);
    ballistics_track_start(&L->ballistics);
    if (health_watch_open(&L->health, L->s, 1))
        return snprintf(error, size, "out of host memory for %d particles", L->s->n_scene) > 0;
    if (L->s->projectile.enabled && output_ballistics_open(L->out, &L->s->projectile, error, size))
        return 1;
    track_probe(L);
    write_history(L);
    L->energy.start = total_energy(L); /* now with the projectile's energy read */
    L->energy.kinetic_start = L->red.kinetic + projectile_energy(L);
    L->energy.excursion = 0;
    L->next_history = L->c->output.history_interval;
    L->next_snapshot = L->c->output.snapshot_interval;
    L->next_checkpoint =
        L->c->output.checkpoint_interval > 0 ? L->c->output.checkpoint_interval : HUGE_VAL;
    if (cl_failed())
        return snprintf(error, size, "%s", cl_failure()) > 0;
    if (write_snapshot(L)) {
        snprintf(error, size, "cannot write the first snapshot into %.900s", L->out->folder);
        L->status = "output_error";
        return 1;
    }
    return 0;
}

/* `sph resume`: the checkpoint must belong to the case reloaded from the
 * folder's case.resolved.yaml (an edit that changes the case is refused). */
static int same_case(const struct sph_case *c, struct checkpoint *k, char *error, size_t size)
{
    size_t length = 0;
    char *text = case_resolved_text(c, &length);
    const size_t saved = checkpoint_size(k, "case");
    char *copy = text ? CHECKED_CALLOC(saved + 1, 1, "the checkpoint's case") : NULL;
    if (copy)
        checkpoint_get(k, "case", copy, saved);
    const int same = copy && !k->failed && saved == length && memcmp(text, copy, length) == 0;
    free(text);
    free(copy);
    if (!same)
        return snprintf(error, size,
                        "%s is not the case %s was written with (edited since?); restore it, or "
                        "start a new run",
                        c->path, k->path) > 0;
    return 0;
}

/* The state of the checkpoint instead of start()'s: the solver's buffers,
 * the health watch and the loop's records. */
static int resume_state(struct loop *L, struct checkpoint *k, char *error, size_t size)
{
    solver_checkpoint_records(L->s, k, 1);
    if (health_watch_open(&L->health, L->s, 0))
        return snprintf(error, size, "out of host memory for %d particles", L->s->n_scene) > 0;
    loop_records(L, k, 1);
    if (k->failed)
        return snprintf(error, size, "%s", k->error) > 0;
    if (cl_failed())
        return snprintf(error, size, "%s", cl_failure()) > 0;
    if (!L->opt->quiet)
        fprintf(stderr, "sph: resuming at step %ld, t = %.6e s\n", L->step, L->t);
    return 0;
}

/* Over several processes (collective, once every rank has loaded its
 * file): a rank whose last checkpoint could not be written kept an older
 * one, and the files do not make one state. */
static int same_step_everywhere(struct loop *L, char *error, size_t size)
{
    double step[2] = {(double)L->step, -(double)L->step};
    dist_min(step, 2);
    if (step[0] == -step[1])
        return 0;
    return snprintf(error, size,
                    "the ranks' checkpoints in %s are from different steps (%.0f to %.0f); the "
                    "run cannot go on from them",
                    L->out->folder, step[0], -step[1]) > 0;
}

/* What a run holds; close_run releases it in reverse order (every release
 * accepts what was never made: the struct starts zeroed). */
struct run_resources {
    struct sph_case *c;
    struct sph_scene scene;
    struct sph_device dev;
    struct solver s;
    struct output out;
    char folder[SPH_PATH_MAX];
};

static void close_run(struct run_resources *r)
{
    output_close(&r->out);
    solver_release(&r->s);
    device_close(&r->dev);
    scene_free(&r->scene);
    free(r->c);
}

/* Case, scene, device and program, and the run folder's name. Returns 0,
 * or the exit status (1 bad input, 2 device) with the reason in `error`. */
static int open_run(const struct run_options *opt, struct run_resources *r, char *error,
                    size_t size)
{
    r->c = calloc(1, sizeof *r->c);
    if (!r->c)
        return snprintf(error, size, "out of host memory") > 0;
    struct sph_case *c = r->c;
    double points = 0;
    if (case_load(opt->case_path, opt->set_count, opt->sets, c, error, size) ||
        scene_estimate(c, &points, error, size))
        return 1;
    points /= dist_size(); /* each rank holds its share */
    /* the ranks' halos follow the reference positions in this form: a part
     * that comes near another over a rank's boundary would not be seen */
    if (dist_size() > 1 && c->numerics.total_lagrangian && case_has_part_contact(c))
        return snprintf(error, size,
                        "%s: bodies of different parts (bodies[].part) in the total Lagrangian "
                        "form run on one process (their contact is not carried between ranks)",
                        opt->case_path) > 0;
    /* an update re-sorts every rank's reference; the ranks' boxes and
     * halos are not re-cut for it */
    if (dist_size() > 1 && c->numerics.reference_update > 0)
        return snprintf(error, size,
                        "%s: numerics.reference_update runs on one process (the ranks' reference "
                        "boxes are not re-cut at an update); set it to 0 or run without mpirun",
                        opt->case_path) > 0;
    if (device_open(opt->device, opt->profile, &r->dev, error, size))
        return 2;
    /* before the scene is built: a case the device cannot hold is refused
     * in milliseconds, not after minutes and gigabytes of host memory. The
     * estimate counts lattice points: the particles of uniform and box-graded
     * bodies to within a few per cent (solver_create checks the exact need
     * with the ghosts); a track-graded body's tube is counted by its bounding
     * box, far more than it holds, so such cases wait for the exact check */
    solver_choose_lane_lists(c, points, (double)r->dev.global_memory, opt->quiet);
    const double bytes = points * (double)solver_case_bytes_per_particle(c);
    if (!scene_has_track(c) && bytes > (double)r->dev.global_memory) {
        solver_memory_error(c, &r->dev, bytes, solver_case_bytes_per_particle(c), points, 1, error,
                            size);
        return 2;
    }
    if (scene_build(c, &r->scene, error, size) || projectile_check_scene(c, &r->scene, error, size))
        return 1;
    solver_choose_loop(c, &r->dev);
    char options[512];
    solver_build_options(c, options, sizeof options);
    if (c->numerics.double_precision && !r->dev.has_double)
        return 2 * (snprintf(error, size, "%s has no double precision; use precision: float",
                             r->dev.name) > 0);
    if (device_build(&r->dev, device_source_dir(), options, error, size))
        return 2;
    if (opt->out_dir)
        snprintf(r->folder, sizeof r->folder, "%s", opt->out_dir);
    else
        default_folder(c, r->folder, sizeof r->folder);
    return 0;
}

static void say_what_runs(const struct run_options *opt, const struct run_resources *r)
{
    const struct sph_case *c = r->c;
    if (opt->quiet)
        return;
    case_note_welding(c, stderr);
    fprintf(stderr, "sph: %s: %d particles (%d-D), %s kernel, h = %.3g m, on %s%s; writing %s\n",
            c->name, r->scene.count, c->dimension, case_kernel_name(c->numerics.kernel),
            (double)r->s.run.h, r->dev.name, r->dev.from_cache ? " (cached program)" : "",
            r->folder);
}

/* The time loop, the profile, summary.json and the summary line. Returns
 * the exit status. */
static int run_and_report(struct loop *L, struct run_resources *r)
{
    struct profiler *profile =
        L->opt->profile ? CHECKED_CALLOC(1, sizeof *profile, "the profiler") : NULL;
    sph_profiler = profile;
    const double loop_start = profile_clock();
    int code = time_loop(L);
    solver_domain_figures(L->s, &L->halo_particles, &L->halo_bytes); /* every rank is here */
    if (profile)
        profile->wall_s = profile_clock() - loop_start;
    sph_profiler = NULL;
    if (profile && dist_rank() == 0 &&
        report_profile(profile, &r->dev, L->step - L->first_step, r->folder) && code == 0)
        code = 1;
    free(profile);
    progress(L, 1);
    struct run_summary sum;
    finish_summary(L, &sum);
    if (output_summary(&r->out, &sum) != 0) {
        fprintf(stderr, "sph: cannot write %s/summary.json\n", r->folder);
        if (code == 0)
            code = 1;
    }
    if (dist_rank() != 0) /* rank 0 speaks for the job */
        return code;
    if (code == 3)
        fprintf(stderr, "sph: %s; the last state is in %s\n", L->message, r->folder);
    if (code == 2)
        fprintf(stderr, "sph: stopped %s; what was written before is in %s\n", L->message,
                r->folder);
    if (code > 128)
        fprintf(stderr, "sph: %s\n", L->message);
    print_summary_line(&sum, r->folder);
    return code;
}

/* A failure before the first step, once the folder exists: a device
 * failure still leaves a summary.json that says why. */
static int report_start_failure(struct loop *L, struct run_resources *r, const char *error)
{
    fprintf(stderr, "sph: %s\n", error);
    const int device = cl_failed();
    if (!r->out.history || (!device && strcmp(L->status, "output_error") != 0))
        return 1;
    if (device)
        L->status = cl_failure_status();
    snprintf(L->message, sizeof L->message, "before the first step: %s",
             device ? cl_failure() : error);
    struct run_summary sum;
    finish_summary(L, &sum);
    output_summary(&r->out, &sum);
    return device ? 2 : 1;
}

/* The run folder's outputs and the loop's first state: new (start) or from
 * the checkpoint `k` (resume). Returns 0, or the exit status. */
static int open_and_start(struct loop *L, struct run_resources *r, struct checkpoint *k,
                          char *error, size_t size)
{
    const int particles = r->scene.count;
    /* the folder before the solver: a case the device cannot hold (its
     * buffers) still leaves a summary.json that says so */
    if (k ? output_resume(&r->out, r->folder, r->c, particles, k, error, size)
          : output_open(&r->out, r->folder, r->c, particles, error, size)) {
        fprintf(stderr, "sph: %s\n", error);
        return 1;
    }
    /* every rank learns whether any could not make its solver */
    if (dist_agree(solver_create(&r->s, &r->dev, r->c, &r->scene, error, size), error, size)) {
        const int code = report_start_failure(L, r, error);
        return code == 1 ? 2 : code; /* a solver that cannot be made is the device's */
    }
    say_what_runs(L->opt, r);
    /* resumed: the CSV files are cut back only once the whole checkpoint
     * has loaded, so a refused resume leaves the folder as it was */
    if (k ? dist_agree(resume_state(L, k, error, size), error, size) ||
                same_step_everywhere(L, error, size) ||
                output_resume_files(&r->out, r->c->projectile.enabled, error, size)
          : start(L, error, size))
        return report_start_failure(L, r, error);
    return -1; /* ready to run */
}

int run_case(const struct run_options *opt)
{
    char error[SPH_ERROR_MAX] = "";
    struct run_resources *r = calloc(1, sizeof *r);
    struct checkpoint *k = opt->resume ? calloc(1, sizeof *k) : NULL;
    if (!r || (opt->resume && !k)) {
        fprintf(stderr, "sph: out of host memory\n");
        free(r);
        return 1;
    }
    /* sph resume RUN_DIR: the folder's resolved case, as it was */
    char resolved[SPH_PATH_MAX + 32];
    struct run_options options = *opt;
    if (opt->resume) {
        snprintf(resolved, sizeof resolved, "%s/case.resolved.yaml", opt->out_dir);
        options.case_path = resolved;
        options.set_count = 0;
    }
    int code = k && checkpoint_open(k, opt->out_dir)
                   ? snprintf(error, sizeof error, "%s", k->error) > 0
                   : open_run(&options, r, error, sizeof error);
    if (!code && k)
        code = same_case(r->c, k, error, sizeof error);
    /* over several processes every rank stops if any could not open the
     * run, with the first failing rank's message and the worst status */
    double worst = code;
    dist_max(&worst, 1);
    if (dist_agree(code != 0, error, sizeof error))
        code = (int)worst;
    if (code) {
        if (dist_rank() == 0)
            fprintf(stderr, "sph: %s\n", error);
        if (k)
            checkpoint_close(k);
        close_run(r);
        free(r), free(k);
        return code;
    }
    struct loop L = {.c = r->c,
                     .opt = opt,
                     .s = &r->s,
                     .out = &r->out,
                     .scene = &r->scene,
                     .status = "completed",
                     .wall_start = wall_seconds(),
                     .health = {.first_unhealthy_time = -1, .min_pair_distance = HUGE_VAL},
                     .ballistics = {.left_fine_time = -1, .exit_time = -1}};
    L.next_checkpoint_wall = L.wall_start + r->c->output.checkpoint_wall_interval;
    L.energy.held_axes = case_held_wall_axes(r->c);
    code = open_and_start(&L, r, k, error, sizeof error);
    if (k)
        checkpoint_close(k);
    if (code < 0) {
        L.first_step = L.step, L.first_t = L.t;
        const char *raise_at = getenv("SPH_RAISE_AT_STEP");
        L.raise_at_step = raise_at ? atol(raise_at) : -1;
        const char *raise_count = getenv("SPH_RAISE_COUNT");
        L.raise_count = raise_count ? atoi(raise_count) : 1;
        catch_interrupts(1);
        code = run_and_report(&L, r);
        catch_interrupts(0);
    }
    health_watch_close(&L.health);
    close_run(r);
    free(r), free(k);
    return code;
}
