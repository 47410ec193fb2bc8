/* Lattice fill of the case's bodies, group flags and the load. */
#include "scene.h"
#include "solver.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_PARTICLES 200000000L

static double lattice_count(double length, double dx)
{
    return floor(length / dx + 0.5);
}

/* Particles of a box on a square lattice of spacing dx, centred in the box
 * so that a box of n dx holds n particles per axis at half-spacing from its
 * faces (bodies that share a face then continue one lattice). */
static double box_particles(const struct case_box *box, int dim, double dx, int counts[3])
{
    double total = 1;
    for (int a = 0; a < 3; ++a) {
        double count = a < dim ? lattice_count(box->max[a] - box->min[a], dx) : 1;
        if (count < 1)
            count = 1;
        total *= count;
        counts[a] = count < (double)MAX_PARTICLES ? (int)count : (int)MAX_PARTICLES;
    }
    return total;
}

/* Which face of the box along axis a lies on a plane normal to that axis
 * at `position`: -1 the lower, +1 the upper, 0 neither. */
static int face_on_plane(const struct case_box *box, int a, double position)
{
    const double tolerance = 1e-9 * (box->max[a] - box->min[a]);
    if (fabs(box->min[a] - position) <= tolerance)
        return -1;
    if (fabs(box->max[a] - position) <= tolerance)
        return 1;
    return 0;
}

/* The face of the box along axis a that lies on a symmetry plane or on a
 * rigid wall normal to that axis (-1 lower, +1 upper, 0 none). */
static int anchored_face(const struct sph_case *c, const struct case_box *box, int a)
{
    for (int k = 0; k < c->symmetry_count; ++k)
        if (c->symmetry[k].axis == a) {
            const int face = face_on_plane(box, a, c->symmetry[k].position);
            if (face)
                return face;
        }
    for (int w = 0; w < c->wall_count; ++w) {
        const struct case_wall *wall = &c->walls[w];
        if (fabs(fabs(wall->normal[a]) - 1) > 1e-9)
            continue;
        const int face = face_on_plane(box, a, wall->point[a]);
        if (face)
            return face;
    }
    return 0;
}

/* First lattice coordinate along axis a: centred in the box, or half a
 * spacing from a face that lies on a symmetry plane (so that the lattice
 * and its mirror image continue each other across the plane) or on a rigid
 * wall (so that no particle starts inside the wall's contact spring, which
 * acts within dx/2 of the plane, kernels/integrate.cl: centred, a box whose
 * length is not a whole number of spacings put its end layer up to dx/2
 * into it, and a Taylor bar at dx = 0.75 mm started with that layer
 * thrown off the wall at 670 m/s). */
static double lattice_start(const struct sph_case *c, const struct case_box *box, int a, int count)
{
    const double dx = c->numerics.dx;
    switch (anchored_face(c, box, a)) {
    case -1:
        return box->min[a] + 0.5 * dx;
    case 1:
        return box->max[a] - 0.5 * dx - (count - 1) * dx;
    default:
        return 0.5 * (box->min[a] + box->max[a]) - 0.5 * (count - 1) * dx;
    }
}

static int inside(const struct case_box *box, const double *x, int dim)
{
    for (int a = 0; a < dim; ++a)
        if (x[a] < box->min[a] || x[a] > box->max[a])
            return 0;
    return 1;
}

/* Whether a lattice point of the body's box belongs to its shape. */
static int in_shape(const struct case_body *b, const double *x, int dim)
{
    if (b->shape != SPH_SHAPE_CYLINDER)
        return 1;
    double r2 = 0;
    for (int a = 0; a < dim; ++a)
        if (a != b->axis) {
            const double d = x[a] - b->centre[a];
            r2 += d * d;
        }
    return r2 <= b->radius * b->radius && r2 >= b->inner_radius * b->inner_radius;
}

static int allocate(struct sph_scene *s, int n)
{
    s->position = calloc((size_t)n * 3, sizeof(double));
    s->velocity = calloc((size_t)n * 3, sizeof(double));
    s->mass = calloc((size_t)n, sizeof(double));
    s->density = calloc((size_t)n, sizeof(double));
    s->material = calloc((size_t)n, sizeof(int));
    s->flags = calloc((size_t)n, sizeof(int));
    return s->position && s->velocity && s->mass && s->density && s->material && s->flags;
}

/* One particle of body `body` at x: mass rho0 (2^level dx)^d (axisymmetric:
 * times r, the ring's mass per radian). */
struct fill_context {
    const struct sph_case *c;
    struct sph_scene *s;
    int *body_of;
    int body, n;
};

/* A body particle's initial velocity at x (case_body.velocity_gradient). */
static void initial_velocity(const struct case_body *body, const double x[3], double *v)
{
    for (int a = 0; a < 3; ++a) {
        v[a] = 0.0;
        if (body->fixed)
            continue;
        v[a] = body->velocity[a];
        for (int b = 0; b < 3; ++b)
            v[a] += body->velocity_gradient[3 * a + b] * (x[b] - body->centre[b]);
    }
}

static void put_particle(struct fill_context *f, const double x[3], int level, int reach)
{
    const struct sph_case *c = f->c;
    const struct case_body *body = &c->bodies[f->body];
    const struct case_material *m = &c->materials[body->material];
    const int n = f->n, dim = c->dimension;
    const int axisymmetric = dim == 2 && c->plane == SPH_PLANE_AXISYMMETRIC;
    const double spacing = c->numerics.dx * (1 << level);
    for (int a = 0; a < 3; ++a)
        f->s->position[3 * n + a] = x[a];
    initial_velocity(body, x, &f->s->velocity[3 * n]);
    f->s->density[n] = m->density;
    f->s->mass[n] = m->density * pow(spacing, dim) * (axisymmetric ? x[0] : 1.0);
    f->s->material[n] = body->material;
    f->s->flags[n] = (body->fixed ? SPH_FLAG_FIXED : 0) | (level << SPH_LEVEL_SHIFT) |
                     (reach << SPH_REACH_SHIFT) | (body->part << SPH_PART_SHIFT);
    f->body_of[n] = f->body;
    ++f->n;
}

static int emit_particle(struct sph_particle_sink *sink, const double x[3], int level, int reach)
{
    struct fill_context *f = sink->context;
    if (in_shape(&f->c->bodies[f->body], x, f->c->dimension)) {
        if (f->s)
            put_particle(f, x, level, reach);
        else
            ++f->n;
    }
    return 0;
}

/* Particles of a graded body (host/grading.c); with s NULL only counts. */
static int fill_graded(const struct sph_case *c, int b, struct sph_scene *s, int *body_of, int n)
{
    struct fill_context f = {.c = c, .s = s, .body_of = body_of, .body = b, .n = n};
    struct sph_particle_sink sink = {.skin = SPH_GRID_SKIN, .emit = emit_particle, .context = &f};
    grading_fill(c, &c->bodies[b], &sink);
    return f.n;
}

static int fill_bodies(const struct sph_case *c, struct sph_scene *s, int *body_of)
{
    const int dim = c->dimension;
    const double dx = c->numerics.dx;
    const int axisymmetric = dim == 2 && c->plane == SPH_PLANE_AXISYMMETRIC;
    int n = 0;
    for (int b = 0; b < c->body_count; ++b) {
        const struct case_body *body = &c->bodies[b];
        const struct case_material *m = &c->materials[body->material];
        if (body->grading.enabled) {
            n = fill_graded(c, b, s, body_of, n);
            continue;
        }
        int counts[3];
        box_particles(&body->box, dim, dx, counts);
        double start[3];
        for (int a = 0; a < 3; ++a)
            start[a] = a < dim ? lattice_start(c, &body->box, a, counts[a]) : 0.0;
        for (int k = 0; k < counts[2]; ++k)
            for (int j = 0; j < counts[1]; ++j)
                for (int i = 0; i < counts[0]; ++i) {
                    const int idx[3] = {i, j, k};
                    double x[3];
                    for (int a = 0; a < 3; ++a)
                        x[a] = a < dim ? start[a] + idx[a] * dx : 0.0;
                    if (!in_shape(body, x, dim))
                        continue;
                    for (int a = 0; a < 3; ++a)
                        s->position[3 * n + a] = x[a];
                    initial_velocity(body, x, &s->velocity[3 * n]);
                    s->density[n] = m->density;
                    /* axisymmetric: the ring's mass per radian, rho0 r dx^2 */
                    s->mass[n] = m->density * pow(dx, dim) * (axisymmetric ? x[0] : 1.0);
                    s->material[n] = body->material;
                    s->flags[n] = (body->fixed ? SPH_FLAG_FIXED : 0) | (1 << SPH_REACH_SHIFT) |
                                  (body->part << SPH_PART_SHIFT);
                    body_of[n] = b;
                    ++n;
                }
    }
    return n;
}

double scene_particle_spacing(const struct sph_case *c, const struct sph_scene *scene, int i)
{
    return c->numerics.dx * (double)(1 << SPH_LEVEL_OF(scene->flags[i]));
}

double scene_particle_distance(const struct sph_scene *scene, int i, const double point[3])
{
    double d2 = 0;
    for (int a = 0; a < 3; ++a)
        d2 += (scene->position[3 * i + a] - point[a]) * (scene->position[3 * i + a] - point[a]);
    return sqrt(d2);
}

/* projectile.embedded: the particles the contact would push at t = 0
 * (centre closer than R - dx_i/2 to the sphere's: the contact layer's
 * centres ride half a spacing inside the sphere, kernels/projectile.cl)
 * are left out, so that it starts inside the target, the material's face on
 * its surface, without a gap for an ambient pressure to close (a sphere
 * towed through a liquid at rest: tools/towed_sphere_drag.py). Returns the
 * new count. */
static int carve_projectile(const struct sph_case *c, struct sph_scene *s, int *body_of, int n)
{
    const struct case_projectile *cp = &c->projectile;
    if (!cp->enabled || !cp->embedded)
        return n;
    int kept = 0;
    for (int p = 0; p < n; ++p) {
        if (scene_particle_distance(s, p, cp->centre) <
            0.5 * cp->diameter - 0.5 * scene_particle_spacing(c, s, p))
            continue;
        for (int a = 0; a < 3; ++a) {
            s->position[3 * kept + a] = s->position[3 * p + a];
            s->velocity[3 * kept + a] = s->velocity[3 * p + a];
        }
        s->mass[kept] = s->mass[p];
        s->density[kept] = s->density[p];
        s->material[kept] = s->material[p];
        s->flags[kept] = s->flags[p];
        body_of[kept] = body_of[p];
        ++kept;
    }
    return kept;
}

static int apply_groups(const struct sph_case *c, struct sph_scene *s, const int *body_of,
                        char *error, size_t error_size)
{
    for (int g = 0; g < c->group_count; ++g) {
        const struct case_group *group = &c->groups[g];
        const int is_probe = c->has_probe && c->probe.group == g;
        int members = 0;
        if (group->load.enabled && s->load) {
            snprintf(error, error_size,
                     "%s: group '%s' carries a second load; one loaded group is supported", c->path,
                     group->name);
            return 1;
        }
        for (int p = 0; p < s->count; ++p) {
            if ((group->body >= 0 && body_of[p] != group->body) ||
                !inside(&group->region, &s->position[3 * p], c->dimension))
                continue;
            ++members;
            if (group->fixed) {
                s->flags[p] |= SPH_FLAG_FIXED;
                s->velocity[3 * p] = s->velocity[3 * p + 1] = s->velocity[3 * p + 2] = 0;
            }
            if (group->load.enabled)
                s->flags[p] |= SPH_FLAG_LOADED;
            if (is_probe)
                s->flags[p] |= SPH_FLAG_PROBE;
        }
        if (members == 0) {
            snprintf(error, error_size,
                     "%s: group '%s' holds no particle: its region contains no lattice point at "
                     "dx = %g m",
                     c->path, group->name, c->numerics.dx);
            return 1;
        }
        if (group->load.enabled) {
            s->load = &group->load;
            s->loaded_count = members;
            /* 2-D particles are per metre of thickness (axisymmetric: per
             * radian): so is their load */
            const double per_length = c->dimension != 2                    ? 1.0
                                      : c->plane == SPH_PLANE_AXISYMMETRIC ? 0.5 / M_PI
                                                                           : 1.0 / c->thickness;
            for (int a = 0; a < 3; ++a)
                s->load_force[a] = group->load.force[a] * per_length;
        }
        if (is_probe)
            s->probe_count = members;
    }
    return 0;
}

/* A run longer than this is a typo (a time in ns given as s), not a study. */
#define MAX_STEPS 1e8

/* The first step's signal speed: the stiffest material's sound speed plus
 * the fastest body or projectile, m/s. */
static double signal_speed(const struct sph_case *c)
{
    return solver_max_sound_speed(c) + case_fastest_speed(c, 1);
}

/* Steps to end_time at the first step's time step, CFL or the physical
 * viscosity's limit where that is smaller (as solver_time_step): a lower
 * bound (the step shrinks as material compresses). */
static double step_estimate(const struct sph_case *c)
{
    const double h = c->numerics.h_over_dx * c->numerics.dx;
    const double dt = fmin(c->numerics.cfl * h / signal_speed(c), case_viscous_time_step(c, h));
    return c->numerics.end_time / dt;
}

int scene_has_track(const struct sph_case *c)
{
    for (int b = 0; b < c->body_count; ++b)
        if (c->bodies[b].grading.enabled && c->bodies[b].grading.track_radius > 0)
            return 1;
    return 0;
}

int scene_estimate(const struct sph_case *c, double *points, char *error, size_t error_size)
{
    double total = 0, largest = -1;
    int widest = 0;
    for (int b = 0; b < c->body_count; ++b) {
        int counts[3];
        const double body =
            c->bodies[b].grading.enabled
                ? grading_points(c, &c->bodies[b])
                : box_particles(&c->bodies[b].box, c->dimension, c->numerics.dx, counts);
        total += body;
        if (body > largest)
            largest = body, widest = b;
    }
    *points = total;
    if (!(total <= (double)MAX_PARTICLES)) /* also NaN */
        return snprintf(error, error_size,
                        "%s: the bodies span %.3g lattice points at numerics.dx = %g m (body '%s' "
                        "%.3g); the limit is %.0f million particles: use a larger numerics.dx or "
                        "smaller bodies",
                        c->path, total, c->numerics.dx, c->bodies[widest].name, largest,
                        MAX_PARTICLES / 1e6) > 0;
    const double steps = step_estimate(c);
    if (!(steps <= MAX_STEPS))
        return snprintf(error, error_size,
                        "%s: numerics.end_time = %g s takes about %.3g steps of %.3g s (CFL "
                        "%g, h = %g m, signal speed %.4g m/s, or the viscous limit 0.125 h^2 "
                        "rho0 / eta); the limit is %.0e steps: check end_time's units or use a "
                        "shorter one",
                        c->path, c->numerics.end_time, steps, c->numerics.end_time / steps,
                        c->numerics.cfl, c->numerics.h_over_dx * c->numerics.dx, signal_speed(c),
                        MAX_STEPS) > 0;
    return 0;
}

double scene_side_of_plane(const struct sph_scene *scene, int axis, double position)
{
    double mean = 0;
    for (int p = 0; p < scene->count; ++p)
        mean += scene->position[3 * p + axis] - position;
    return mean >= 0 ? 1.0 : -1.0;
}

/* A held wall is a symmetry plane, which mirrors the side the material is
 * on whatever the normal says (host/ghost.c); the normal must agree, or the
 * impact summary measures from the wrong end (host/impact.c). */
static int check_held_sides(const struct sph_case *c, const struct sph_scene *s, char *error,
                            size_t error_size)
{
    for (int w = 0; w < c->wall_count; ++w) {
        const struct case_wall *wall = &c->walls[w];
        if (!wall->hold)
            continue;
        const int a = case_wall_axis(wall);
        const double side = scene_side_of_plane(s, a, wall->point[a]);
        if (side * wall->normal[a] < 0) {
            snprintf(error, error_size,
                     "%s: wall '%s' is held with its normal along %s%c, but the bodies lie on its "
                     "%s side: a wall's normal points towards the material",
                     c->path, wall->name, wall->normal[a] > 0 ? "+" : "-", "xyz"[a],
                     side > 0 ? "+" : "-");
            return 1;
        }
    }
    return 0;
}

int scene_build(const struct sph_case *c, struct sph_scene *s, char *error, size_t error_size)
{
    memset(s, 0, sizeof *s);
    double points = 0;
    if (scene_estimate(c, &points, error, error_size))
        return 1;
    long total = 0;
    for (int b = 0; b < c->body_count; ++b) {
        int counts[3];
        total += c->bodies[b].grading.enabled
                     ? fill_graded(c, b, NULL, NULL, 0)
                     : (long)box_particles(&c->bodies[b].box, c->dimension, c->numerics.dx, counts);
    }
    if (total <= 0 || total > MAX_PARTICLES) {
        snprintf(error, error_size,
                 "%s: the bodies give %ld particles at dx = %g m (expected 1 "
                 "to 200 million)",
                 c->path, total, c->numerics.dx);
        return 1;
    }
    int *body_of = calloc((size_t)total, sizeof(int));
    if (!body_of || !allocate(s, (int)total)) {
        free(body_of);
        scene_free(s);
        snprintf(error, error_size, "out of host memory for %ld particles", total);
        return 1;
    }
    s->count = carve_projectile(c, s, body_of, fill_bodies(c, s, body_of));
    for (int b = 0; b < c->body_count; ++b) {
        int members = 0;
        for (int p = 0; p < s->count; ++p)
            members += body_of[p] == b;
        if (members == 0) {
            snprintf(error, error_size,
                     "%s: body '%s' holds no particle: its shape contains no lattice point at "
                     "dx = %g m%s",
                     c->path, c->bodies[b].name, c->numerics.dx,
                     c->projectile.enabled && c->projectile.embedded
                         ? " outside the embedded projectile (projectile.embedded removes the "
                           "points it overlaps)"
                         : "");
            free(body_of);
            scene_free(s);
            return 1;
        }
    }
    if (check_held_sides(c, s, error, error_size)) {
        free(body_of);
        scene_free(s);
        return 1;
    }
    const int status = apply_groups(c, s, body_of, error, error_size);
    free(body_of);
    if (status) {
        scene_free(s);
        return status;
    }
    for (int a = 0; a < 3; ++a) {
        s->domain_min[a] = HUGE_VAL;
        s->domain_max[a] = -HUGE_VAL;
    }
    for (int p = 0; p < s->count; ++p)
        for (int a = 0; a < 3; ++a) {
            s->domain_min[a] = fmin(s->domain_min[a], s->position[3 * p + a]);
            s->domain_max[a] = fmax(s->domain_max[a], s->position[3 * p + a]);
        }
    return 0;
}

double scene_load_scale(const struct case_load *load, double t)
{
    if (!load || !load->enabled)
        return 0.0;
    switch (load->law) {
    case SPH_LOAD_LINEAR_RAMP:
        return t < load->ramp_time ? t / load->ramp_time : 1.0;
    case SPH_LOAD_QUADRATIC_RAMP:
        return t < load->ramp_time ? (t / load->ramp_time) * (t / load->ramp_time) : 1.0;
    default:
        return 1.0;
    }
}

void scene_free(struct sph_scene *s)
{
    free(s->position);
    free(s->velocity);
    free(s->mass);
    free(s->density);
    free(s->material);
    free(s->flags);
    memset(s, 0, sizeof *s);
}
