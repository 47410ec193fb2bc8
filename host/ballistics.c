/* The rigid projectile on the host side: its constants from the case, its
 * two launches per step, and what the history reads of it (penetration,
 * velocity, force, cavity diameters). The physics is in
 * kernels/projectile.cl. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "launch.h"
#include "solver.h"

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* `count` doubles into a buffer of device reals. */
static void write_reals(struct solver *s, cl_mem m, const double *values, size_t count)
{
    float *narrow = s->double_precision ? NULL : CHECKED_CALLOC(count, sizeof(float), "reals");
    if (!s->double_precision && !narrow)
        return;
    for (size_t k = 0; narrow && k < count; ++k)
        narrow[k] = (float)values[k];
    CL_CHECK(clEnqueueWriteBuffer(s->dev->queue, m, CL_TRUE, 0, s->element_size[ELEM_REAL] * count,
                                  s->double_precision ? (const void *)values : (const void *)narrow,
                                  0, NULL, NULL));
    free(narrow);
}

static void write_state(struct solver *s, const double *values)
{
    write_reals(s, s->projectile.state, values, SPH_PROJ_SLOTS);
}

/* Over several processes: this rank's contact sums, and every rank's
 * written back into the first group's slots (the others zeroed), so that
 * each rank's projectile_advance moves the same sphere by the same force. */
void solver_projectile_sums(struct solver *s, double sum[SPH_CONTACT_SLOTS])
{
    const size_t count = (size_t)s->reduce_groups * SPH_CONTACT_SLOTS;
    double v[REDUCE_MAX_GROUPS * SPH_CONTACT_SLOTS] = {0};
    solver_read_reals(s, s->projectile.contact_partials, count, v);
    memset(sum, 0, sizeof(double) * SPH_CONTACT_SLOTS);
    for (size_t k = 0; k < count; ++k)
        sum[k % SPH_CONTACT_SLOTS] += v[k];
}

void solver_projectile_share(struct solver *s, const double sum[SPH_CONTACT_SLOTS])
{
    double v[REDUCE_MAX_GROUPS * SPH_CONTACT_SLOTS] = {0};
    memcpy(v, sum, sizeof(double) * SPH_CONTACT_SLOTS);
    write_reals(s, s->projectile.contact_partials, v, (size_t)s->reduce_groups * SPH_CONTACT_SLOTS);
}

/* Whole-model factors: a 2-D particle is per metre of thickness or (axi)
 * per radian; each symmetry plane halves the model, except the axis of an
 * axisymmetric case, which the 2 pi already covers. Components normal to a
 * plane cancel against the mirror image. */
static void model_factors(struct solver *s, const struct sph_case *c, struct projectile *p)
{
    const int axisymmetric = c->dimension == 2 && c->plane == SPH_PLANE_AXISYMMETRIC;
    double multiplicity = 1;
    for (int a = 0; a < 3; ++a)
        p->mask[a] = a < c->dimension ? 1.0 : 0.0;
    for (int k = 0; k < c->symmetry_count; ++k) {
        p->mask[c->symmetry[k].axis] = 0;
        if (!(axisymmetric && c->symmetry[k].axis == 0))
            multiplicity *= 2;
    }
    p->scale = s->thickness_scale * multiplicity;
    p->momentum_scale = multiplicity; /* the reduction already applies the thickness */
}

/* Where the shot line origin + s u enters and leaves the target, m along
 * u: over the particles whose centre lies within sqrt(dim) / 2 own
 * spacings of the line, the smallest x . u less half a spacing and the largest plus half a
 * spacing. The extreme particle of the whole target is not the face the
 * sphere meets once the shot is oblique or the face is not flat. Entry is
 * HUGE_VAL and exit -HUGE_VAL when the line misses the target. */
static void shot_line_faces(const struct sph_case *c, const struct sph_scene *scene,
                            const double origin[3], const double axis[3], double *entry,
                            double *exit)
{
    *entry = HUGE_VAL, *exit = -HUGE_VAL;
    /* a cylinder of radius sqrt(dim) / 2 spacings holds a particle of any
     * lattice the line crosses, and on a face tilted by theta its particles'
     * faces spread by no more than that radius times tan theta */
    const double reach2 = 0.25 * c->dimension;
    for (int i = 0; i < scene->count; ++i) {
        const double spacing = scene_particle_spacing(c, scene, i);
        double r[3], along = 0, off2 = 0;
        for (int a = 0; a < 3; ++a)
            r[a] = scene->position[3 * i + a] - origin[a], along += r[a] * axis[a];
        for (int a = 0; a < 3; ++a)
            off2 += (r[a] - along * axis[a]) * (r[a] - along * axis[a]);
        if (off2 > reach2 * spacing * spacing)
            continue;
        const double x_along = along + dot3(origin, axis);
        *entry = fmin(*entry, x_along - 0.5 * spacing);
        *exit = fmax(*exit, x_along + 0.5 * spacing);
    }
}

static void impact_axis(const struct case_projectile *cp, double axis[3])
{
    const double speed = sqrt(dot3(cp->velocity, cp->velocity));
    for (int a = 0; a < 3; ++a)
        axis[a] = cp->velocity[a] / speed;
}

/* The contact law (kernels/projectile.cl) pushes on a particle whose centre
 * comes closer to the sphere's than radius - half its spacing; at t = 0 no
 * particle may reach into the sphere at all (centre within radius + half
 * its spacing) unless the sphere is embedded, and the shot line must meet
 * the target. */
int projectile_check_scene(const struct sph_case *c, const struct sph_scene *scene, char *error,
                           size_t error_size)
{
    const struct case_projectile *cp = &c->projectile;
    if (!cp->enabled)
        return 0;
    const double radius = 0.5 * cp->diameter;
    int worst = -1;
    double worst_overlap = 1e-9 * radius;
    /* an embedded sphere starts inside: host/scene.c removed what it overlaps */
    if (!cp->embedded)
        for (int i = 0; i < scene->count; ++i) {
            const double overlap = radius + 0.5 * scene_particle_spacing(c, scene, i) -
                                   scene_particle_distance(scene, i, cp->centre);
            if (overlap > worst_overlap)
                worst_overlap = overlap, worst = i;
        }
    if (worst >= 0) {
        const double *x = &scene->position[3 * worst];
        snprintf(error, error_size,
                 "%s: projectile.centre: the sphere overlaps the target at t = 0 (the particle at "
                 "[%.6g, %.6g, %.6g] m is %.4g m inside its surface plus half a spacing); move it "
                 "back along the shot",
                 c->path, x[0], x[1], x[2], worst_overlap);
        return 1;
    }
    double axis[3], entry, exit;
    impact_axis(cp, axis);
    shot_line_faces(c, scene, cp->centre, axis, &entry, &exit);
    if (!(entry < HUGE_VAL) || exit < dot3(cp->centre, axis)) {
        snprintf(error, error_size,
                 "%s: projectile: the shot line from projectile.centre along projectile.velocity "
                 "meets no particle of the target ahead of the sphere",
                 c->path);
        return 1;
    }
    return 0;
}

/* The projectile's kernels, one list for making and releasing them. */
static void projectile_kernels(struct solver *s, int make)
{
    const struct kernel_slot list[] = {{&s->k.projectile_contact, "projectile_contact", 0},
                                       {&s->k.projectile_advance, "projectile_advance", 0},
                                       {&s->k.projectile_cavity, "projectile_cavity", 0}};
    solver_kernels(s, list, (int)(sizeof list / sizeof list[0]), make);
}

int solver_projectile_create(struct solver *s, const struct sph_case *c,
                             const struct sph_scene *scene, char *error, size_t error_size)
{
    struct projectile *p = &s->projectile;
    memset(p, 0, sizeof *p);
    const struct case_projectile *cp = &c->projectile;
    if (!cp->enabled)
        return 0;
    p->enabled = 1;
    p->prescribed = cp->prescribed;
    p->no_slip = cp->no_slip;
    p->radius = 0.5 * cp->diameter;
    p->mass = cp->density * M_PI * pow(cp->diameter, 3) / 6.0;
    const double speed = sqrt(dot3(cp->velocity, cp->velocity));
    p->stiffness_speed = solver_max_sound_speed(c) + speed;
    impact_axis(cp, p->axis);
    for (int a = 0; a < 3; ++a)
        p->origin[a] = cp->centre[a];
    model_factors(s, c, p);
    shot_line_faces(c, scene, p->origin, p->axis, &p->surface, &p->exit_face);
    p->probe_spacing = cp->cavity_probe_spacing;
    p->probe_count = cp->cavity_probe_count;
    const size_t r = s->element_size[ELEM_REAL];
    p->state = solver_create_buffer(s, r * SPH_PROJ_SLOTS);
    p->contact_partials = solver_create_buffer(s, r * SPH_CONTACT_SLOTS * (size_t)s->reduce_groups);
    if (cl_failed())
        return snprintf(error, error_size, "%s", cl_failure()) > 0;
    double state[SPH_PROJ_SLOTS] = {0};
    for (int a = 0; a < 3; ++a) {
        state[SPH_PROJ_X + a] = cp->centre[a];
        state[SPH_PROJ_V + a] = cp->velocity[a];
    }
    write_state(s, state);
    projectile_kernels(s, 1);
    return 0;
}

void solver_projectile_contact(struct solver *s, double dt, double dt_prev)
{
    struct projectile *p = &s->projectile;
    struct real_arg a_speed, a_dx, a_dt, a_prev;
    SET_ARGS(s, s->k.projectile_contact, MEM("state", p->state),
             real_value(s, &a_speed, "stiffness_speed", p->stiffness_speed),
             real_value(s, &a_dx, "dx", s->dx), real_value(s, &a_dt, "dt", dt),
             real_value(s, &a_prev, "dt_prev", dt_prev), INT("no_slip", p->no_slip),
             MEM("partials", p->contact_partials), INT("n", s->n));
    solver_launch(s, s->k.projectile_contact, (size_t)s->reduce_groups * REDUCE_GROUP,
                  REDUCE_GROUP);
}

void solver_projectile_advance(struct solver *s, double dt, double dt_prev)
{
    struct projectile *p = &s->projectile;
    struct real4_arg a_mask;
    struct real_arg a_scale, a_mass, a_dt, a_prev;
    SET_ARGS(s, s->k.projectile_advance, MEM("state", p->state),
             MEM("partials", p->contact_partials), INT("groups", s->reduce_groups),
             real4_value(s, &a_mask, "mask", p->mask), real_value(s, &a_scale, "scale", p->scale),
             real_value(s, &a_mass, "sphere_mass", p->mass), INT("prescribed", p->prescribed),
             real_value(s, &a_dt, "dt", dt), real_value(s, &a_prev, "dt_prev", dt_prev));
    solver_launch(s, s->k.projectile_advance, 1, 1);
}

static void read_cavity(struct solver *s, struct projectile_reading *out)
{
    struct projectile *p = &s->projectile;
    struct real4_arg a_origin, a_axis;
    struct real_arg a_surface, a_spacing, a_dx;
    SET_ARGS(s, s->k.projectile_cavity, real4_value(s, &a_origin, "origin", p->origin),
             real4_value(s, &a_axis, "axis", p->axis),
             real_value(s, &a_surface, "surface", p->surface),
             real_value(s, &a_spacing, "probe_spacing", p->probe_spacing),
             INT("probe_count", p->probe_count), real_value(s, &a_dx, "dx", s->dx),
             MEM("partials", s->partials), INT("n", s->n));
    solver_launch(s, s->k.projectile_cavity, (size_t)s->reduce_groups * REDUCE_GROUP, REDUCE_GROUP);
    const size_t width = 2 * SPH_MAX_CAVITY_PROBES;
    double *v = CHECKED_CALLOC(width * (size_t)s->reduce_groups, sizeof(double), "cavity partials");
    if (!v)
        return;
    solver_read_reals(s, s->partials, width * (size_t)s->reduce_groups, v);
    /* the nearest empty radius as its negative, so that one maximum over
     * every rank's particles takes both */
    double widest[2 * SPH_MAX_CAVITY_PROBES];
    for (int k = 0; k < SPH_MAX_CAVITY_PROBES; ++k) {
        widest[2 * k] = -HUGE_VAL, widest[2 * k + 1] = 0;
        for (int g = 0; g < s->reduce_groups; ++g) {
            widest[2 * k] = fmax(widest[2 * k], -v[g * width + 2 * k]);
            widest[2 * k + 1] = fmax(widest[2 * k + 1], v[g * width + 2 * k + 1]);
        }
    }
    dist_max(widest, 2 * SPH_MAX_CAVITY_PROBES);
    for (int k = 0; k < SPH_MAX_CAVITY_PROBES; ++k) {
        out->cavity_d1[k] = isfinite(widest[2 * k]) ? -2 * widest[2 * k] : 0.0;
        out->cavity_d2[k] = 2 * widest[2 * k + 1];
    }
    free(v);
}

void solver_projectile_read(struct solver *s, struct projectile_reading *out)
{
    struct projectile *p = &s->projectile;
    memset(out, 0, sizeof *out);
    double state[SPH_PROJ_SLOTS] = {0};
    solver_read_reals(s, p->state, SPH_PROJ_SLOTS, state);
    double along = 0, speed = 0;
    for (int a = 0; a < 3; ++a) {
        out->position[a] = state[SPH_PROJ_X + a];
        out->velocity[a] = state[SPH_PROJ_V + a];
        out->force[a] = state[SPH_PROJ_F + a];
        along += out->position[a] * p->axis[a];
        speed += out->velocity[a] * p->axis[a];
    }
    out->contact_energy = state[SPH_PROJ_CONTACT_ENERGY];
    out->dissipated = state[SPH_PROJ_DISSIPATED];
    out->driver_work = state[SPH_PROJ_DRIVER_WORK];
    for (int a = 0; a < 3; ++a)
        out->driver_impulse_along_axis += state[SPH_PROJ_DRIVER_IMPULSE + a] * p->axis[a];
    out->contacts = (int)state[SPH_PROJ_CONTACTS];
    out->penetration = along + p->radius - p->surface;
    out->speed_along_axis = speed;
    double off2 = 0;
    for (int a = 0; a < 3; ++a) {
        const double r = out->position[a] - p->origin[a];
        const double off = r - (along - dot3(p->origin, p->axis)) * p->axis[a];
        off2 += off * off;
    }
    out->lateral_deflection = sqrt(off2);
    out->through = along - p->radius > p->exit_face;
    read_cavity(s, out);
}

void solver_projectile_motion(struct solver *s, double centre[3], double velocity[3])
{
    double state[SPH_PROJ_SLOTS] = {0};
    solver_read_reals(s, s->projectile.state, SPH_PROJ_SLOTS, state);
    for (int a = 0; a < 3; ++a)
        centre[a] = state[SPH_PROJ_X + a], velocity[a] = state[SPH_PROJ_V + a];
}

void solver_projectile_release(struct solver *s)
{
    struct projectile *p = &s->projectile;
    projectile_kernels(s, 0);
    if (p->state)
        clReleaseMemObject(p->state);
    if (p->contact_partials)
        clReleaseMemObject(p->contact_partials);
    memset(p, 0, sizeof *p);
}
