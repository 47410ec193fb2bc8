/* Scene: particles from a case (lattice fill of the bodies, groups, loads). */
#ifndef SPH_SCENE_H
#define SPH_SCENE_H

#include "sph_case.h"

/* Host copy of the initial particle state, array of structures by field.
 * Vectors are stored with 3 components (z = 0 in 2-D). */
struct sph_scene {
    int count;
    double *position; /* 3 per particle, m */
    double *velocity; /* 3 per particle, m/s */
    double *mass;     /* kg (2-D: kg per metre of thickness) */
    double *density;  /* kg/m^3 */
    int *material;
    int *flags;       /* enum sph_flag */
    int loaded_count; /* particles that carry the load */
    int probe_count;
    double load_force[3];                /* total load at full scale, N (2-D: N per metre) */
    const struct case_load *load;        /* the loaded group's law, or NULL */
    double domain_min[3], domain_max[3]; /* initial bounding box, m */
};

/* Where a lattice fill puts its particles (host/grading.c): emit returns
 * non-zero to stop. */
struct sph_particle_sink {
    double skin; /* neighbour-grid margin over the support (host/step.c) */
    int (*emit)(struct sph_particle_sink *sink, const double x[3], int level, int reach);
    void *context;
};

/* The level (0 finest) a graded body's lattice has at point x, m. */
int grading_level_at(const struct sph_case *c, const struct case_body *b, const double x[3]);
/* The lattice points grading_fill visits for a graded body: an upper bound
 * of its particles, in floating point (no loop over particles). */
double grading_points(const struct sph_case *c, const struct case_body *b);
/* Fills a graded body (bodies[].grading) level by level; returns the
 * particles emitted, or -1 when emit stopped it. */
int grading_fill(const struct sph_case *c, const struct case_body *b,
                 struct sph_particle_sink *out);

/* The lattice points the fill visits (an upper bound of the particles: close
 * for uniform and box-graded bodies, the bounding box of each level's tube
 * for a track-graded one), in floating point before any loop or
 * allocation; non-zero with `error` naming the widest body past 200
 * million, or a run of more than 1e8 steps. scene_build calls it first. */
int scene_estimate(const struct sph_case *c, double *points, char *error, size_t error_size);

/* Whether a body is graded about a track (its estimate is a loose bound). */
int scene_has_track(const struct sph_case *c);

/* Fills `scene` from `c`. Returns 0, or non-zero with one sentence in
 * `error` (no particles, overlapping loads, empty group). */
int scene_build(const struct sph_case *c, struct sph_scene *scene, char *error, size_t error_size);

/* Particle i's lattice spacing, m (numerics.dx on its grading level). */
double scene_particle_spacing(const struct sph_case *c, const struct sph_scene *scene, int i);

/* Particle i's distance from `point`, m. */
double scene_particle_distance(const struct sph_scene *scene, int i, const double point[3]);
/* The side of the plane x_axis = position the particles lie on: +1 or -1
 * (by their mean offset; +1 when it is zero). */
double scene_side_of_plane(const struct sph_scene *scene, int axis, double position);

/* The load scale factor of the time law at time t (0..1). */
double scene_load_scale(const struct case_load *load, double t);

void scene_free(struct sph_scene *scene);

#endif
