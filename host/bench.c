/* `sph bench`: a fixed suite of scenes at several sizes, each stepped a fixed
 * number of times after a warm-up with every launch timed (profile.h); the
 * median over repeats gives particle-steps and pair interactions per second.
 * No output is written during the steps: this is the cost of the step. */
#include "bench.h"
#include "cpu_steal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "device.h"
#include "output.h"
#include "profile.h"
#include "scene.h"
#include "solver.h"

#define MAX_SCENE_SETS 6

/* TIER_NAMED: run only when --only names it (too long for any suite run) */
enum suite_tier { TIER_QUICK = 1, TIER_STANDARD = 2, TIER_LARGE = 4, TIER_NAMED = 8 };

/* The suite. The 3-D Taylor bar (a quarter with two symmetry planes) runs at
 * h = 1.2 dx, about 55 neighbours, as the peers' benchmark does; the other
 * scenes run their case files' numerics. Particle counts are those of the
 * spacing given (ghosts of the symmetry planes come on top). */
static const struct bench_scene {
    const char *name;
    const char *case_file; /* relative to the source folder */
    const char *sets[MAX_SCENE_SETS];
    int tiers;
} suite[] = {
    {"taylor3d-10k",
     "cases/taylor_3d_4340.yaml",
     {"numerics.dx=3.5e-4", "numerics.h_over_dx=1.2"},
     TIER_QUICK},
    {"taylor3d-50k",
     "cases/taylor_3d_4340.yaml",
     {"numerics.dx=2.05e-4", "numerics.h_over_dx=1.2"},
     TIER_STANDARD},
    {"taylor3d-200k",
     "cases/taylor_3d_4340.yaml",
     {"numerics.dx=1.29e-4", "numerics.h_over_dx=1.2"},
     TIER_STANDARD},
    {"taylor3d-1m",
     "cases/taylor_3d_4340.yaml",
     {"numerics.dx=7.55e-5", "numerics.h_over_dx=1.2"},
     TIER_LARGE},
    /* at d/dx 10, the spacing the suite has always measured it at */
    {"gelatin-axi",
     "cases/gelatin_silica.yaml",
     {"numerics.dx=0.738e-6"},
     TIER_QUICK | TIER_STANDARD},
    /* the 3-D penetration users run: a graded quarter target with a rigid
     * sphere */
    {"gelatin3d-120k", "cases/gelatin_silica_3d.yaml", {NULL}, TIER_STANDARD},
    {"gelatin3d-1m", "cases/gelatin_silica_3d.yaml", {"numerics.dx=0.35e-6"}, TIER_LARGE},
    {"gelatin3d-10m", "cases/gelatin_silica_3d.yaml", {"numerics.dx=0.159e-6"}, TIER_NAMED},
    {"beam2d-1k", "cases/beam_2d.yaml", {NULL}, TIER_QUICK},
    {"beam2d-16k", "cases/beam_2d.yaml", {"numerics.dx=0.25e-3"}, TIER_STANDARD},
};

struct scene_result {
    const char *name;
    int dimension, particles, ghosts, slots; /* slots: allocated (ghosts and room) */
    double neighbours_mean;
    long steps;
    int repeats;
    double seconds_per_step[BENCH_MAX_REPEATS];
    double median_s;
    size_t bytes_per_slot;
    double device_bytes;    /* every buffer's size over the real particles */
    double lane_list_bytes; /* the lane lists' as allocated (measured) */
    double steal_fraction;  /* CPU steal over the timed steps (NAN: unknown) */
    struct solver_memory memory;
    struct profiler profile;
};

static int ascending(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(const double *v, int count)
{
    double sorted[BENCH_MAX_REPEATS];
    memcpy(sorted, v, sizeof(double) * (size_t)count);
    qsort(sorted, (size_t)count, sizeof sorted[0], ascending);
    return count % 2 ? sorted[count / 2] : 0.5 * (sorted[count / 2 - 1] + sorted[count / 2]);
}

/* One step as `sph run` takes it, without loads or output: re-sort when
 * needed, the time step from the last reduction, step, reduce. */
static int bench_step(struct solver *s, double cfl, struct reduction *red, double *dt_prev,
                      char *error, size_t error_size)
{
    const double no_load[3] = {0, 0, 0};
    const double dt = solver_time_step(s, cfl, red->max_signal);
    if (solver_advance(s, dt, *dt_prev, no_load, red, error, error_size))
        return 1;
    *dt_prev = dt;
    if (!(red->max_signal > 0) || !isfinite(red->max_signal) || red->bad_id >= 0) {
        snprintf(error, error_size, "the scene went unstable during the benchmark");
        return 1;
    }
    return 0;
}

static int step_scene(struct solver *s, const struct sph_case *c, const struct bench_options *o,
                      struct scene_result *r, char *error, size_t error_size)
{
    struct reduction red;
    const double no_load[3] = {0, 0, 0};
    double dt_prev = 0;
    if (solver_sort(s, error, error_size))
        return 1;
    solver_prime(s);
    solver_reduce(s, no_load, &red);
    dt_prev = solver_time_step(s, c->numerics.cfl, red.max_signal);
    for (int k = 0; k < o->warmup; ++k)
        if (bench_step(s, c->numerics.cfl, &red, &dt_prev, error, error_size))
            return 1;
    struct health_reading health;
    solver_health(s, &health);
    r->neighbours_mean = health.neighbours_mean;
    CL_CHECK(clFinish(s->dev->queue));
    memset(&r->profile, 0, sizeof r->profile);
    r->profile.pairs_per_call = health.neighbours_mean * s->n_real;
    sph_profiler = &r->profile;
    const struct cpu_times cpu_before = cpu_times_now();
    for (int rep = 0; rep < o->repeats; ++rep) {
        const double t0 = profile_clock();
        for (int k = 0; k < o->steps; ++k)
            if (bench_step(s, c->numerics.cfl, &red, &dt_prev, error, error_size)) {
                sph_profiler = NULL;
                return 1;
            }
        CL_CHECK(clFinish(s->dev->queue));
        const double wall = profile_clock() - t0;
        r->seconds_per_step[rep] = wall / o->steps;
        r->profile.wall_s += wall;
    }
    sph_profiler = NULL;
    const struct cpu_times cpu_after = cpu_times_now();
    r->steal_fraction = cpu_steal_fraction(&cpu_before, &cpu_after);
    profile_flush(&r->profile);
    r->steps = (long)o->steps * o->repeats;
    r->repeats = o->repeats;
    r->median_s = median(r->seconds_per_step, o->repeats);
    return 0;
}

static int run_scene(struct sph_device *dev, const struct bench_scene *b,
                     const struct bench_options *o, struct scene_result *r, char *error,
                     size_t error_size)
{
    char path[2048];
    snprintf(path, sizeof path, "%s/%s", device_source_dir(), b->case_file);
    char *sets[MAX_SCENE_SETS + CASE_MAX_SETS];
    int set_count = 0;
    while (set_count < MAX_SCENE_SETS && b->sets[set_count]) {
        sets[set_count] = (char *)b->sets[set_count];
        ++set_count;
    }
    for (int k = 0; k < o->set_count; ++k) /* main.c caps it at CASE_MAX_SETS */
        sets[set_count++] = o->sets[k];
    struct sph_case *c = calloc(1, sizeof *c);
    struct sph_scene scene;
    struct solver s;
    char options[512];
    if (!c)
        return snprintf(error, error_size, "out of host memory") > 0;
    int failed = case_load(path, set_count, sets, c, error, error_size) ||
                 scene_build(c, &scene, error, error_size);
    if (failed) {
        free(c);
        return 1;
    }
    solver_choose_loop(c, dev);
    solver_choose_lane_lists(c, scene.count, (double)dev->global_memory, 0);
    solver_build_options(c, options, sizeof options);
    failed = device_build(dev, device_source_dir(), options, error, error_size);
    if (!failed && (failed = solver_create(&s, dev, c, &scene, error, error_size)) != 0)
        solver_release(&s); /* what it made before it failed */
    if (!failed) {
        r->name = b->name;
        r->dimension = c->dimension;
        r->particles = s.n_real;
        r->slots = s.capacity;
        r->bytes_per_slot = solver_bytes_per_particle(&s);
        solver_memory_breakdown(&s, &r->memory);
        r->device_bytes = (double)r->bytes_per_slot * s.capacity;
        fprintf(stderr, "sph bench: %s: %d particles, %d slots allocated, %d-D ...\n", b->name,
                s.n_real, s.capacity, c->dimension);
        failed = step_scene(&s, c, o, r, error, error_size);
        if (cl_failed() && snprintf(error, error_size, "%s", cl_failure()) > 0)
            failed = 1;
        r->ghosts = s.n - s.n_real; /* the mirror images of the last sort */
        /* the lane lists, sized at each sort: as allocated at the end, in
         * place of their estimate */
        r->lane_list_bytes = (double)solver_lane_list_bytes(&s);
        r->device_bytes += r->lane_list_bytes - (double)s.lane_list_estimate * s.capacity;
        solver_release(&s);
    }
    scene_free(&scene);
    free(c);
    return failed;
}

static void print_scene(const struct scene_result *r, const struct device_ceilings *ceil)
{
    const double pairs = r->neighbours_mean * r->particles;
    printf("\n%s: %d particles (and %d mirror ghosts), %.1f neighbours, %d x %ld steps: %.3f "
           "ms/step (median), "
           "%.3g particle-steps/s, %.3g pair interactions/s, %.0f B/particle of device "
           "memory\n",
           r->name, r->particles, r->ghosts, r->neighbours_mean, r->repeats, r->steps / r->repeats,
           1e3 * r->median_s, r->particles / r->median_s, pairs / r->median_s,
           r->device_bytes / r->particles);
    /* others' share of this VM's cores: timings are comparable where it is low */
    if (isfinite(r->steal_fraction))
        printf("CPU steal during the timed steps: %.1f%%\n", 100 * r->steal_fraction);
    profile_print(&r->profile, ceil, r->steps, stdout);
}

/* Bytes per particle slot of each device buffer. */
static void write_memory_json(const struct solver_memory *m, FILE *f)
{
    fprintf(f, "{");
    for (int k = 0; k < m->count; ++k)
        fprintf(f, "%s\"%s\": %zu", k ? ", " : "", m->name[k], m->bytes[k]);
    fprintf(f, "}");
}

static void write_scene_json(const struct scene_result *r, FILE *f)
{
    const double pairs = r->neighbours_mean * r->particles;
    fprintf(f,
            "    {\"name\": \"%s\", \"dimension\": %d, \"particles\": %d, \"ghosts\": %d, "
            "\"slots\": %d, "
            "\"neighbours_mean\": %.4g, \"steps\": %ld, \"repeats\": %d,\n     "
            "\"seconds_per_step\": [",
            r->name, r->dimension, r->particles, r->ghosts, r->slots, r->neighbours_mean,
            r->steps / r->repeats, r->repeats);
    for (int k = 0; k < r->repeats; ++k)
        fprintf(f, "%s%.6g", k ? ", " : "", r->seconds_per_step[k]);
    fprintf(f,
            "], \"median_seconds_per_step\": %.6g, \"particle_steps_per_s\": %.6g, "
            "\"pair_interactions_per_s\": %.6g,\n     \"bytes_per_particle\": %.1f, "
            "\"bytes_per_slot\": %zu, \"lane_list_bytes_per_particle\": %.1f, "
            "\"memory_bytes_per_slot\": ",
            r->median_s, r->particles / r->median_s, pairs / r->median_s,
            r->device_bytes / r->particles, r->bytes_per_slot, r->lane_list_bytes / r->particles);
    write_memory_json(&r->memory, f);
    if (isfinite(r->steal_fraction))
        fprintf(f, ",\n     \"cpu_steal_fraction\": %.4g", r->steal_fraction);
    else
        fprintf(f, ",\n     \"cpu_steal_fraction\": null");
    fprintf(f,
            ",\n     \"wall_s\": %.6g, \"device_s\": %.6g,\n     \"kernels\": ", r->profile.wall_s,
            profile_device_seconds(&r->profile));
    profile_write_json(&r->profile, r->steps, f);
    fprintf(f, "}");
}

int bench_main(const struct bench_options *o)
{
    struct sph_device dev;
    char error[SPH_ERROR_MAX] = "";
    if (device_open(o->device, 1, &dev, error, sizeof error)) {
        fprintf(stderr, "sph bench: %s\n", error);
        return 2;
    }
    const int tier = o->quick ? TIER_QUICK : TIER_STANDARD | (o->large ? TIER_LARGE : 0);
    const int count = (int)(sizeof suite / sizeof suite[0]);
    struct scene_result *results = calloc((size_t)count, sizeof *results);
    if (!results) {
        fprintf(stderr, "sph bench: out of host memory\n");
        device_close(&dev);
        return 2;
    }
    struct device_ceilings ceil = {0, 0};
    int done = 0, code = 0, have_ceilings = 0;
    for (int k = 0; k < count && code == 0; ++k) {
        const int named =
            (suite[k].tiers & TIER_NAMED) && o->only && strcmp(suite[k].name, o->only) == 0;
        if (!named && (!(suite[k].tiers & tier) || (o->only && !strstr(suite[k].name, o->only))))
            continue;
        if (run_scene(&dev, &suite[k], o, &results[done], error, sizeof error)) {
            fprintf(stderr, "sph bench: %s: %s\n", suite[k].name, error);
            code = 2;
            break;
        }
        if (!have_ceilings) /* the probe kernels are in every program */
            have_ceilings = device_ceilings(&dev, &ceil, error, sizeof error) == 0;
        print_scene(&results[done], have_ceilings ? &ceil : NULL);
        ++done;
    }
    if (done == 0 && code == 0) {
        fprintf(stderr, "sph bench: no scene matches '%s'\n", o->only ? o->only : "");
        code = 1;
    }
    if (code == 0 && o->json_path) {
        char temporary[SPH_PATH_MAX + 32];
        FILE *f = output_file_begin(o->json_path, temporary, sizeof temporary);
        if (!f) {
            fprintf(stderr, "sph bench: cannot write %s\n", o->json_path);
            code = 1;
        } else {
            fprintf(f,
                    "{\n  \"device\": \"%s\",\n  \"ceiling_gb_per_s\": %.6g,\n"
                    "  \"ceiling_gflop_per_s\": %.6g,\n  \"warmup_steps\": %d,\n  \"scenes\": [\n",
                    dev.name, ceil.bandwidth_gb_s, ceil.gflop_s, o->warmup);
            for (int k = 0; k < done; ++k) {
                write_scene_json(&results[k], f);
                fprintf(f, "%s\n", k + 1 < done ? "," : "");
            }
            fprintf(f, "  ]\n}\n");
            if (output_file_commit(f, temporary, o->json_path) != 0)
                code = 1;
            else
                fprintf(stderr, "sph bench: wrote %s\n", o->json_path);
        }
    }
    free(results);
    device_close(&dev);
    return code;
}
