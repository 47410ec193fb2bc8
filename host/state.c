/* Device buffers: one per particle field (structure of arrays), created from
 * the scene, read back for output. */
#include "solver.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The walls the device pushes with a contact spring: all but the held ones,
 * which are symmetry planes (host/case.c, held_walls). */
static int penalty_wall_count(const struct sph_case *c)
{
    int count = 0;
    for (int w = 0; w < c->wall_count; ++w)
        count += !c->walls[w].hold;
    return count;
}

void solver_configure(struct solver *s, const struct sph_case *c)
{
    s->dim = c->dimension;
    s->double_precision = c->numerics.double_precision;
    s->total_lagrangian = c->numerics.total_lagrangian;
    s->reference_update = c->numerics.reference_update;
    s->part_contact = case_has_part_contact(c);
    s->lanes = solver_lanes(c);
    s->lane_lists = solver_uses_lane_lists(c);
    s->csph = c->numerics.csph;
    s->av_scheme = c->numerics.av_scheme;
    s->artificial_stress = c->numerics.as_epsilon > 0;
    s->tensor_smoothing = c->numerics.tensor_smoothing;
    s->viscosity = case_has_viscosity(c);
    s->wall_count = penalty_wall_count(c); /* wall_force exists only with them */
    const size_t r = s->double_precision ? sizeof(cl_double) : sizeof(cl_float);
    s->element_size[ELEM_REAL] = r;
    s->element_size[ELEM_INT] = sizeof(cl_int);
    s->element_size[ELEM_VEC] = (s->dim == 2 ? 2 : 4) * r;
    s->element_size[ELEM_SYMT] = (s->dim == 2 ? 4 : 6) * r; /* kernels/common.cl's symt */
    s->element_size[ELEM_FULLT] = (s->dim == 2 ? 4 : 16) * r;
    s->lane_list_estimate = solver_lane_list_estimate(c);
}

/* The lane lists' device memory per particle (host/step.c,
 * solver_lane_lists_build), for the memory checks before a run: a lane
 * block lists the particles within (1 + skin) supports of its eight, about
 * a ball of that radius plus a spacing; a quarter more for the lists'
 * headroom, 4 B each, shared by 8 particles. Measured on the 3-D bar (h =
 * 1.2 dx): 195 entries per block, at most 276; the estimate takes 306. */
size_t solver_lane_list_estimate(const struct sph_case *c)
{
    if (!solver_uses_lane_lists(c))
        return 0;
    const double radius = sph_support_q(c->numerics.kernel) * c->numerics.h_over_dx *
                              solver_reach_factor(c) * (1.0 + SPH_GRID_SKIN) +
                          1.0; /* in spacings */
    const double ball =
        c->dimension == 3 ? 4.0 / 3.0 * M_PI * pow(radius, 3) : M_PI * radius * radius;
    return (size_t)ceil(1.25 * ball * sizeof(cl_int) / SPH_LANES_DEFAULT);
}

size_t solver_case_bytes_per_particle(const struct sph_case *c)
{
    struct solver s;
    memset(&s, 0, sizeof s);
    solver_configure(&s, c);
    return solver_bytes_per_particle(&s);
}

int solver_case_coarsest_level(const struct sph_case *c)
{
    int coarsest = 0;
    for (int b = 0; b < c->body_count; ++b)
        if (c->bodies[b].grading.enabled && c->bodies[b].grading.levels > coarsest)
            coarsest = c->bodies[b].grading.levels;
    return coarsest;
}

int solver_case_graded(const struct sph_case *c)
{
    return solver_case_coarsest_level(c) > 0; /* grading.levels >= 1 (host/case.c) */
}

void solver_choose_loop(struct sph_case *c, const struct sph_device *dev)
{
    if (c->numerics.neighbour_loop == SPH_LOOP_AUTO)
        c->numerics.neighbour_loop = dev->is_gpu ? SPH_LOOP_PLAIN : SPH_LOOP_LANES;
}

int solver_lanes(const struct sph_case *c)
{
    /* auto not yet resolved for a device (sph check, unit tests): a CPU's */
    return c->numerics.neighbour_loop == SPH_LOOP_PLAIN ? 1 : SPH_LANES_DEFAULT;
}

double solver_reach_factor(const struct sph_case *c)
{
    return c->numerics.tensor_smoothing ? SPH_TENSOR_AXIS_MAX : 1.0;
}

int solver_uses_lane_lists(const struct sph_case *c)
{
    return solver_lanes(c) > 1 && c->numerics.lane_lists != 0; /* auto unresolved: with */
}

void solver_choose_lane_lists(struct sph_case *c, double particles, double device_bytes, int quiet)
{
    if (c->numerics.lane_lists != SPH_LANE_LISTS_AUTO)
        return;
    c->numerics.lane_lists = 1;
    const double with = particles * (double)solver_case_bytes_per_particle(c),
                 without = with - particles * (double)solver_lane_list_estimate(c);
    if (with > device_bytes && without <= device_bytes) {
        c->numerics.lane_lists = 0;
        if (!quiet)
            fprintf(stderr,
                    "sph: numerics.lane_lists auto: without the lane lists (%.2f GiB with them, "
                    "%.2f GiB without, the device has %.2f GiB): the neighbour passes walk the "
                    "cells, the same results, slower\n",
                    with / (1 << 30), without / (1 << 30), device_bytes / (1 << 30));
    }
}

void solver_build_options(const struct sph_case *c, char *options, size_t size)
{
    const struct case_numerics *num = &c->numerics;
    int plastic = 0;
    for (int m = 0; m < c->material_count; ++m) /* plasticity or any failure */
        plastic |=
            c->materials[m].strength != SPH_STRENGTH_ELASTIC || c->materials[m].failure_stretch > 0;
    /* -w: PoCL's compiler prints ABI notes (-Wpsabi) about float8/float16
     * arguments on every first build; the sources are kept free of real
     * warnings with clang -x cl -fsyntax-only -Wall (docs/ARCHITECTURE.md) */
    snprintf(
        options, size,
        "-cl-std=CL1.2 -cl-kernel-arg-info -w -DSPH_DIM=%d -DSPH_KERNEL=%d%s%s%s%s%s%s%s%s%s%s%s",
        c->dimension, (int)num->kernel, solver_case_graded(c) ? " -DSPH_GRADED" : "",
        c->dimension == 2 && c->plane == SPH_PLANE_STRESS         ? " -DSPH_PLANE_STRESS"
        : c->dimension == 2 && c->plane == SPH_PLANE_AXISYMMETRIC ? " -DSPH_AXISYMMETRIC"
                                                                  : "",
        num->csph ? " -DSPH_CSPH" : "",
        num->as_epsilon > 0
            ? (num->as_lattice_weight ? " -DSPH_ARTIFICIAL_STRESS -DSPH_AS_LATTICE_WEIGHT"
                                      : " -DSPH_ARTIFICIAL_STRESS")
            : "",
        num->xsph_epsilon > 0 ? " -DSPH_XSPH" : "", plastic ? " -DSPH_PLASTICITY" : "",
        num->av_scheme == SPH_AV_LIMITED         ? " -DSPH_AV_LIMITED"
        : num->av_scheme == SPH_AV_SWITCH        ? " -DSPH_AV_SWITCH"
        : num->av_scheme == SPH_AV_CULLEN_DEHNEN ? " -DSPH_AV_SWITCH -DSPH_AV_CULLEN_DEHNEN"
                                                 : "",
        num->av_balsara ? " -DSPH_AV_BALSARA" : "", num->double_precision ? " -DSPH_DOUBLE" : "",
        num->total_lagrangian ? " -DSPH_TOTAL_LAGRANGIAN" : "",
        case_has_viscosity(c) ? " -DSPH_VISCOSITY" : "");
    const size_t used = strlen(options);
    /* SPH_BUILD_OPTIONS: kernel developers' experiments, extra -D or -cl-* options */
    const char *extra = getenv("SPH_BUILD_OPTIONS");
    snprintf(options + used, size - used, " -DSPH_LANES=%d%s%s%s%s%s %s", solver_lanes(c),
             solver_lanes(c) > 1 && !solver_uses_lane_lists(c) ? " -DSPH_LANE_CELL_WALK" : "",
             c->projectile.enabled && c->projectile.boundary_integral ? " -DSPH_SPHERE_WALL" : "",
             num->tensor_smoothing ? " -DSPH_TENSOR_SMOOTHING" : "",
             case_has_part_contact(c) ? " -DSPH_PART_CONTACT" : "",
             num->reference_update > 0 ? " -DSPH_REFERENCE_UPDATE" : "", extra ? extra : "");
}

/* The largest element of the fields in use (persistent ones only, or all). */
static size_t largest_element(const struct solver *s, int persistent_only)
{
    size_t largest = 0;
    for (int f = 0; f < FIELD_COUNT; ++f)
        if ((field_table[f].persistent || !persistent_only) &&
            solver_field_used(s, (enum field)f) && s->element_size[field_table[f].kind] > largest)
            largest = s->element_size[field_table[f].kind];
    return largest;
}

/* The gather spare serves every persistent field's reorder. */
size_t solver_spare_element(const struct solver *s)
{
    return largest_element(s, 1);
}

static size_t field_bytes(const struct solver *s, enum field f)
{
    return solver_field_used(s, f) ? s->element_size[field_table[f].kind] * (size_t)s->capacity : 0;
}

void solver_memory_breakdown(const struct solver *s, struct solver_memory *out)
{
    out->count = 0;
    for (int f = 0; f < FIELD_COUNT; ++f)
        if (solver_field_used(s, (enum field)f)) {
            out->name[out->count] = field_table[f].name;
            out->bytes[out->count++] = s->element_size[field_table[f].kind];
        }
    out->name[out->count] = "gather_spare";
    out->bytes[out->count++] = solver_spare_element(s);
    out->name[out->count] = "sort_keys";
    out->bytes[out->count++] = sizeof(cl_ulong);
    if (s->lane_list_estimate) {
        out->name[out->count] = "lane_lists (estimate)";
        out->bytes[out->count++] = s->lane_list_estimate;
    }
}

size_t solver_bytes_per_particle(const struct solver *s)
{
    struct solver_memory m;
    solver_memory_breakdown(s, &m);
    size_t bytes = 0;
    for (int k = 0; k < m.count; ++k)
        bytes += m.bytes[k];
    return bytes;
}

cl_mem solver_create_buffer(struct solver *s, size_t bytes)
{
    if (cl_failed())
        return NULL;
    cl_int err = CL_SUCCESS;
    if (!bytes)
        bytes = 16;
    cl_mem m = clCreateBuffer(s->dev->context, CL_MEM_READ_WRITE, bytes, NULL, &err);
    CL_CHECK_ERR("clCreateBuffer", err);
    /* zeroed: nothing a kernel reads is ever undefined, the ghost slots
     * and the padding of a reduction included. (oclgrind --uninitialized
     * keeps one record per buffer of its initialised bytes, and each host
     * write or buffer copy replaces it with one of its own extent: after a
     * clEnqueueFillBuffer it knows one pattern, after the writes below a
     * buffer beyond one block is known only as its last block.) One 16 MiB
     * block of zeros, kept for the process, is written over it without
     * waiting: a buffer made during a re-sort (a grown grid) costs no
     * synchronisation. */
    static const size_t block = (size_t)16 << 20;
    static void *zeros;
    if (m && !zeros)
        zeros = CHECKED_CALLOC(1, block, "zeros for new buffers");
    for (size_t at = 0; m && zeros && at < bytes; at += block)
        CL_CHECK(clEnqueueWriteBuffer(s->dev->queue, m, CL_FALSE, at,
                                      bytes - at < block ? bytes - at : block, zeros, 0, NULL,
                                      NULL));
    return m;
}

/* Converts doubles to the device real type and uploads them: `count`
 * values, then zeros up to the buffer's capacity x `width` reals. The whole
 * buffer goes in one write because oclgrind (21.10) resizes its record of a
 * buffer's initialised bytes to each host write: a write of the real
 * particles only would leave the ghost slots that kernels fill later
 * looking uninitialised to it. */
static void upload_reals(struct solver *s, cl_mem buffer, const double *values, size_t count,
                         int width)
{
    const size_t r = s->element_size[ELEM_REAL], slots = (size_t)s->capacity * width;
    unsigned char *tmp = CHECKED_CALLOC(slots * r + 1, 1, "upload staging");
    if (!tmp)
        return;
    for (size_t k = 0; k < count; ++k) {
        if (s->double_precision)
            memcpy(tmp + k * r, &values[k], r);
        else {
            const float v = (float)values[k];
            memcpy(tmp + k * r, &v, r);
        }
    }
    CL_CHECK(
        clEnqueueWriteBuffer(s->dev->queue, buffer, CL_TRUE, 0, slots * r, tmp, 0, NULL, NULL));
    free(tmp);
}

/* The tensor smoothing's metric on the lattice: the identity (kernels/
 * tensor_smoothing.cl), and its longest semi-axis 1, in every slot. */
static void upload_identity_metric(struct solver *s)
{
    const int width = s->dim == 2 ? 4 : 6; /* kernels/common.cl's symt */
    const size_t count = (size_t)s->capacity * width;
    double *values = CHECKED_CALLOC(count + 1, sizeof(double), "metric upload");
    if (!values)
        return;
    for (size_t k = 0; k < (size_t)s->capacity; ++k)
        for (int a = 0; a < 3; ++a)
            values[k * width + a] = 1.0;
    upload_reals(s, s->field[FIELD_SMOOTHING_METRIC], values, count, width);
    for (size_t k = 0; k < (size_t)s->capacity; ++k)
        values[k] = 1.0; /* the longest semi-axis over h0 */
    upload_reals(s, s->field[FIELD_SMOOTHING_REACH], values, (size_t)s->capacity, 1);
    free(values);
}

/* 3-component host vectors of n particles to the device vec layout (2 or
 * 4 reals), zeros in the other slots. */
static void upload_vectors(struct solver *s, cl_mem buffer, const double *xyz, int n)
{
    const int width = s->dim == 2 ? 2 : 4;
    double *wide = CHECKED_CALLOC((size_t)n * width + 1, sizeof(double), "vector upload");
    if (!wide)
        return;
    for (int p = 0; p < n; ++p)
        for (int a = 0; a < s->dim; ++a)
            wide[(size_t)p * width + a] = xyz[3 * p + a];
    upload_reals(s, buffer, wide, (size_t)n * width, width);
    free(wide);
}

/* n ints, zeros in the other slots (one write: see upload_reals). */
static void upload_ints(struct solver *s, cl_mem buffer, const int *values, int n)
{
    int *wide = CHECKED_CALLOC((size_t)s->capacity + 1, sizeof(int), "int upload");
    if (!wide)
        return;
    memcpy(wide, values, (size_t)n * sizeof(int));
    CL_CHECK(clEnqueueWriteBuffer(s->dev->queue, buffer, CL_TRUE, 0,
                                  (size_t)s->capacity * sizeof(cl_int), wide, 0, NULL, NULL));
    free(wide);
}

/* The material table in double, from the case. */
struct material_double {
#define SPH_DECLARE_DOUBLE(name) cl_double name;
    SPH_MATERIAL_REALS(SPH_DECLARE_DOUBLE)
#undef SPH_DECLARE_DOUBLE
    cl_int eos, strength, pad0, pad1;
};

static struct material_double material_entry(const struct case_material *cm)
{
    struct material_double m;
    memset(&m, 0, sizeof m);
    const double nu = cm->poisson_ratio, e = cm->youngs_modulus;
    const double bulk = e / (3.0 * (1.0 - 2.0 * nu)), shear = e / (2.0 * (1.0 + nu));
    const struct case_eos_parameters *eos =
        cm->eos == SPH_EOS_POLYNOMIAL ? &cm->polynomial : &cm->mie_gruneisen;
    m.density = cm->density;
    m.bulk_modulus = bulk;
    m.shear_modulus = shear;
    m.sound_speed = case_material_sound_speed(cm);
    m.yield_stress = cm->yield_stress;
    m.hardening_b = cm->johnson_cook.b;
    m.hardening_n = cm->johnson_cook.n;
    m.plane_stress_nu = nu / (1.0 - nu);
    m.eos_c0 = eos->c0;
    m.eos_s = eos->s;
    m.eos_gamma0 = eos->gamma0;
    m.eos_p0 = eos->p0;
    m.jc_rate_c = cm->johnson_cook.c;
    m.jc_reference_rate = cm->johnson_cook.enabled ? cm->johnson_cook.reference_rate : 1.0;
    m.jc_thermal_m = cm->johnson_cook.m;
    m.melt_temperature = cm->johnson_cook.melt_temperature;
    m.room_temperature = cm->room_temperature;
    m.heat_capacity = cm->heat_capacity;
    m.taylor_quinney = cm->taylor_quinney;
    m.failure_strain = cm->failure == SPH_FAILURE_NONE    ? -1.0
                       : cm->failure == SPH_FAILURE_YIELD ? 0.0
                                                          : cm->failure_strain;
    m.viscosity = cm->viscosity;
    m.cavitation_pressure = cm->cavitation_pressure;
    m.failure_stretch = cm->failure_stretch;
    m.eos = cm->eos;
    m.strength = cm->strength;
    return m;
}

static void upload_materials(struct solver *s, const struct sph_case *c)
{
    struct material_double wide[SPH_MAX_MATERIALS];
    struct sph_material narrow[SPH_MAX_MATERIALS];
    memset(narrow, 0, sizeof narrow);
    for (int m = 0; m < c->material_count; ++m) {
        wide[m] = material_entry(&c->materials[m]);
#define SPH_NARROW(name) narrow[m].name = (real)wide[m].name;
        SPH_MATERIAL_REALS(SPH_NARROW)
#undef SPH_NARROW
        narrow[m].eos = wide[m].eos;
        narrow[m].strength = wide[m].strength;
    }
    /* `real` is fixed at host compile time to float; a double build of the
     * kernels gets the double table, which has the same member order */
    const void *table = s->double_precision ? (const void *)wide : (const void *)narrow;
    const size_t entry = s->double_precision ? sizeof wide[0] : sizeof narrow[0];
    CL_CHECK(clEnqueueWriteBuffer(s->dev->queue, s->materials, CL_TRUE, 0,
                                  entry * (size_t)c->material_count, table, 0, NULL, NULL));
}

/* The largest sound speed over the materials (for dt and the velocity limit). */
double solver_max_sound_speed(const struct sph_case *c)
{
    double c_max = 0;
    for (int m = 0; m < c->material_count; ++m)
        c_max = fmax(c_max, material_entry(&c->materials[m]).sound_speed);
    return c_max;
}

/* The walls in the device layout; gap = dx / 2. */
static void upload_walls(struct solver *s, const struct sph_case *c)
{
    struct {
#define SPH_DECLARE_DOUBLE(name) cl_double name;
        SPH_WALL_REALS(SPH_DECLARE_DOUBLE)
#undef SPH_DECLARE_DOUBLE
    } wide[SPH_MAX_WALLS];
    struct sph_wall narrow[SPH_MAX_WALLS];
    memset(wide, 0, sizeof wide);
    memset(narrow, 0, sizeof narrow);
    int w = 0;
    for (int k = 0; k < c->wall_count; ++k) {
        const struct case_wall *cw = &c->walls[k];
        if (cw->hold) /* a symmetry plane (host/ghost.c), no contact spring */
            continue;
        wide[w].point_x = cw->point[0], wide[w].point_y = cw->point[1];
        wide[w].point_z = cw->point[2];
        wide[w].normal_x = cw->normal[0], wide[w].normal_y = cw->normal[1];
        wide[w].normal_z = cw->normal[2];
        wide[w].friction = cw->friction;
        wide[w].gap = 0.5 * c->numerics.dx;
#define SPH_NARROW(name) narrow[w].name = (real)wide[w].name;
        SPH_WALL_REALS(SPH_NARROW)
#undef SPH_NARROW
        ++w;
    }
    s->wall_count = w;
    if (w == 0)
        return;
    const void *table = s->double_precision ? (const void *)wide : (const void *)narrow;
    const size_t entry = s->double_precision ? sizeof wide[0] : sizeof narrow[0];
    CL_CHECK(clEnqueueWriteBuffer(s->dev->queue, s->walls, CL_TRUE, 0, entry * (size_t)w, table, 0,
                                  NULL, NULL));
}

static void upload_run_params(struct solver *s)
{
    const double v[14] = {s->run.h,          s->run.support,     s->run.av_alpha,
                          s->run.av_beta,    s->run.av_eta_crit, s->run.av_alpha_min,
                          s->run.as_epsilon, s->run.as_inv_w_dx, s->run.xsph_epsilon,
                          s->run.damping,    s->run.thickness,   s->run.velocity_limit,
                          s->run.hourglass,  s->run.axis_radius};
    if (!s->double_precision) {
        CL_CHECK(clEnqueueWriteBuffer(s->dev->queue, s->run_params, CL_TRUE, 0, sizeof s->run,
                                      &s->run, 0, NULL, NULL));
        return;
    }
    struct {
        cl_double v[14];
        cl_int as_exponent, material_count;
    } wide;
    for (int k = 0; k < 14; ++k)
        wide.v[k] = v[k];
    wide.as_exponent = s->run.as_exponent;
    wide.material_count = s->run.material_count;
    CL_CHECK(clEnqueueWriteBuffer(s->dev->queue, s->run_params, CL_TRUE, 0, sizeof wide, &wide, 0,
                                  NULL, NULL));
}

void solver_memory_error(const struct sph_case *c, const struct sph_device *dev, double bytes,
                         size_t per_particle, double particles, int estimate, char *error,
                         size_t size)
{
    const size_t lists = solver_lane_list_estimate(c);
    char advice[160] = "use a coarser dx";
    if (lists)
        snprintf(advice, sizeof advice,
                 "use a coarser dx, or numerics.lane_lists: false (%zu bytes per particle less, "
                 "slower neighbour passes)",
                 lists);
    snprintf(error, size,
             "the case needs %s%.2f GiB of device memory (%zu bytes x %.0f particles) but %s has "
             "%.2f GiB; %s (for PoCL, POCL_MEMORY_LIMIT=<GiB> sets the limit)",
             estimate ? "about " : "", bytes / (1 << 30), per_particle, particles, dev->name,
             (double)dev->global_memory / (1 << 30), advice);
}

int solver_create_buffers(struct solver *s, const struct sph_case *c, const struct sph_scene *scene,
                          char *error, size_t error_size)
{
    const size_t total = solver_bytes_per_particle(s) * (size_t)s->capacity;
    if (total > s->dev->global_memory) {
        solver_memory_error(c, s->dev, (double)total, solver_bytes_per_particle(s), s->capacity, 0,
                            error, error_size);
        return 1;
    }
    const size_t largest = largest_element(s, 0) * (size_t)s->capacity;
    if (largest > s->dev->max_allocation) {
        snprintf(error, error_size,
                 "one buffer of this case needs %.2f GiB but %s allows %.2f GiB per buffer; use a "
                 "coarser dx",
                 (double)largest / (1 << 30), s->dev->name,
                 (double)s->dev->max_allocation / (1 << 30));
        return 1;
    }
    for (int f = 0; f < FIELD_COUNT; ++f)
        s->field[f] = solver_create_buffer(s, field_bytes(s, (enum field)f));
    s->gather_spare = solver_create_buffer(s, solver_spare_element(s) * (size_t)s->capacity);
    s->sort_keys = solver_create_buffer(s, sizeof(cl_ulong) * (size_t)s->capacity);
    if (s->total_lagrangian && s->part_contact)
        s->contact_keys = solver_create_buffer(s, sizeof(cl_ulong) * (size_t)s->capacity);
    s->partials =
        solver_create_buffer(s, s->element_size[ELEM_REAL] * SPH_RED_SLOTS * s->reduce_groups);
    s->bounds_partials = solver_create_buffer(s, s->element_size[ELEM_REAL] * 6 * s->reduce_groups);
    s->materials = solver_create_buffer(s, sizeof(struct material_double) * SPH_MAX_MATERIALS);
    s->run_params = solver_create_buffer(s, 8 * 16);
    s->walls = solver_create_buffer(s, sizeof(cl_double) * 8 * SPH_MAX_WALLS);

    upload_vectors(s, s->field[FIELD_POS], scene->position, s->n_real);
    upload_vectors(s, s->field[FIELD_POS0], scene->position, s->n_real);
    upload_vectors(s, s->field[FIELD_VEL], scene->velocity, s->n_real);
    upload_vectors(s, s->field[FIELD_VEL_HALF], scene->velocity, s->n_real);
    upload_reals(s, s->field[FIELD_RHO], scene->density, (size_t)s->n_real, 1);
    upload_reals(s, s->field[FIELD_MASS], scene->mass, (size_t)s->n_real, 1);
    upload_ints(s, s->field[FIELD_FLAGS], scene->flags, s->n_real);
    upload_ints(s, s->field[FIELD_MATERIAL], scene->material, s->n_real);
    int *ids = CHECKED_CALLOC((size_t)s->n_real, sizeof(int), "particle ids");
    double *temperature = CHECKED_CALLOC((size_t)s->n_real, sizeof(double), "temperatures");
    double *density = CHECKED_CALLOC((size_t)s->n_real, sizeof(double), "reference densities");
    for (int p = 0; ids && temperature && density && p < s->n_real; ++p) {
        ids[p] = p;
        temperature[p] = c->materials[scene->material[p]].room_temperature;
        density[p] = c->materials[scene->material[p]].density;
    }
    if (ids && temperature && density) {
        upload_ints(s, s->field[FIELD_ID], ids, s->n_real);
        upload_reals(s, s->field[FIELD_TEMPERATURE], temperature, (size_t)s->n_real, 1);
        if (s->total_lagrangian)
            upload_reals(s, s->field[FIELD_REFERENCE_DENSITY], density, (size_t)s->n_real, 1);
    }
    free(ids);
    free(temperature);
    free(density);
    if (s->tensor_smoothing)
        upload_identity_metric(s);
    /* every other field starts at zero (solver_create_buffer); the
     * pressure, sound speed and artificial stress of the initial state are
     * written by solver_prime's material update, before anything reads them */
    return 0;
}

void solver_upload_constants(struct solver *s, const struct sph_case *c)
{
    upload_materials(s, c);
    upload_run_params(s);
    upload_walls(s, c);
}

void solver_release_buffer(cl_mem *m)
{
    if (*m)
        clReleaseMemObject(*m);
    *m = NULL;
}

void solver_release_buffers(struct solver *s)
{
    for (int f = 0; f < FIELD_COUNT; ++f)
        solver_release_buffer(&s->field[f]);
    solver_release_buffer(&s->gather_spare);
    solver_release_buffer(&s->sort_keys);
    solver_release_buffer(&s->contact_keys);
    solver_release_buffer(&s->contact_cell_start);
    solver_release_buffer(&s->contact_cell_end);
    solver_release_buffer(&s->contact_cell_part_bits);
    solver_release_buffer(&s->cell_start);
    solver_release_buffer(&s->cell_level);
    solver_release_buffer(&s->sort_buckets);
    solver_release_buffer(&s->sort_block_totals);
    solver_release_buffer(&s->lane_list_range);
    solver_release_buffer(&s->lane_list);
    solver_release_buffer(&s->lane_list_claim);
    solver_release_buffer(&s->cell_coarser[0]);
    solver_release_buffer(&s->cell_coarser[1]);
    solver_release_buffer(&s->cell_end);
    solver_release_buffer(&s->partials);
    solver_release_buffer(&s->bounds_partials);
    solver_release_buffer(&s->materials);
    solver_release_buffer(&s->run_params);
    solver_release_buffer(&s->walls);
}

void solver_read_reals(struct solver *s, cl_mem m, size_t count, double *out)
{
    if (s->double_precision) {
        CL_CHECK(clEnqueueReadBuffer(s->dev->queue, m, CL_TRUE, 0, count * sizeof(double), out, 0,
                                     NULL, NULL));
        return;
    }
    /* the per-step reductions (at most 64 groups x 21 slots) need no heap */
    float small[2048];
    float *tmp = count <= 2048 ? small : CHECKED_CALLOC(count, sizeof(float), "read-back of reals");
    if (!tmp)
        return;
    CL_CHECK(clEnqueueReadBuffer(s->dev->queue, m, CL_TRUE, 0, count * sizeof(float), tmp, 0, NULL,
                                 NULL));
    for (size_t k = 0; k < count; ++k)
        out[k] = tmp[k];
    if (tmp != small)
        free(tmp);
}
