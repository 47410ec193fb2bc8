/* The fixed list of kernel launches: grid sort, pass 1, material, pass 2,
 * integrate, reduce. */
#include "launch.h"
#include "solver.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int solver_create_buffers(struct solver *s, const struct sph_case *c, const struct sph_scene *scene,
                          char *error, size_t error_size);
void solver_upload_constants(struct solver *s, const struct sph_case *c);
void solver_release_buffers(struct solver *s);

#define MAX_CELLS (1 << 26) /* 256 MiB of cell ranges: beyond, particles have left */

/* The step's kernels, one list for making and releasing them. */
static void step_kernels(struct solver *s, int make)
{
    struct kernels *k = &s->k;
    const int tl_contact = s->total_lagrangian && s->part_contact;
    const struct kernel_slot list[] = {
        {&k->cell_keys, "grid_cell_keys", 0},
        {&k->bucket_count, "grid_bucket_count", 0},
        {&k->bucket_block_total, "grid_bucket_block_total", 0},
        {&k->bucket_block_offsets, "grid_bucket_block_offsets", 0},
        {&k->bucket_block_scan, "grid_bucket_block_scan", 0},
        {&k->bucket_scatter, "grid_bucket_scatter", 0},
        {&k->bucket_order, "grid_bucket_order", 0},
        {&k->fill_int, "grid_fill_int", 0},
        {&k->cell_ranges, "grid_cell_ranges", 0},
        {&k->bounds, "grid_bounds", 0},
        {k->gather, "grid_gather", 1},
        {k->copy, "grid_copy", 1},
        {&k->pass1, "pass1_velocity_gradient", 0},
        {&k->pass2, "pass2_momentum_energy", 0},
        {&k->kick, "integrate_kick", 0},
        {&k->drift, "integrate_drift", 0},
        {&k->reduce, "reduce_step", 0},
        {&k->neighbour_count, s->total_lagrangian ? "health_neighbour_count" : NULL, 0},
        {&k->tl_correction, s->total_lagrangian ? "tl_correction" : NULL, 0},
        {&k->tl_deformation, s->total_lagrangian ? "tl_deformation" : NULL, 0},
        {&k->tl_momentum, s->total_lagrangian ? "tl_momentum" : NULL, 0},
        {&k->tl_reference_reset, s->reference_update > 0 ? "tl_reference_reset" : NULL, 0},
        {&k->health_pairs, "health_pairs", 0},
        {&k->health, "health_indicators", 0},
        {&k->neighbour_reach, s->graded ? "grid_neighbour_reach" : NULL, 0},
        {&k->cell_max_level, s->graded ? "grid_cell_max_level" : NULL, 0},
        {&k->coarser_seed, s->graded ? "grid_coarser_seed" : NULL, 0},
        {&k->coarser_spread, s->graded ? "grid_coarser_spread" : NULL, 0},
        {&k->apply_reach, s->graded ? "grid_apply_reach" : NULL, 0},
        {&k->lane_list_build, s->lane_lists ? "lane_list_build" : NULL, 0},
        {&k->contact_cell_keys, tl_contact ? "contact_cell_keys" : NULL, 0},
        {&k->contact_cell_ranges, tl_contact ? "contact_cell_ranges" : NULL, 0},
        {&k->contact_cell_parts, tl_contact ? "contact_cell_parts" : NULL, 0},
        {&k->tl_part_contact, tl_contact ? "tl_part_contact" : NULL, 0},
    };
    solver_kernels(s, list, (int)(sizeof list / sizeof list[0]), make);
}

static void create_kernels(struct solver *s)
{
    step_kernels(s, 1);
}

double solver_time_step(const struct solver *s, double cfl, double max_signal)
{
    return fmin(cfl * s->run.h / max_signal, s->dt_viscous);
}

static void release_kernels(struct solver *s)
{
    step_kernels(s, 0);
}

static void fill_run_params(struct solver *s, const struct sph_case *c)
{
    const struct case_numerics *num = &c->numerics;
    const double h = num->h_over_dx * num->dx;
    s->run.h = (real)h;
    s->dt_viscous = case_viscous_time_step(c, h);
    /* the search's support: with a tensor smoothing length the longest axis's */
    s->run.support = (real)(h * sph_support_q(num->kernel) * solver_reach_factor(c));
    s->run.av_alpha = (real)num->av_alpha;
    s->run.av_beta = (real)num->av_beta;
    s->run.av_eta_crit = (real)(1.0 / num->h_over_dx);
    s->run.av_alpha_min = (real)num->av_alpha_min;
    s->run.as_epsilon = (real)num->as_epsilon;
    s->run.as_inv_w_dx = (real)(1.0 / sph_kernel_w_host(num->kernel, c->dimension, num->dx, h));
    s->run.xsph_epsilon = (real)num->xsph_epsilon;
    s->run.damping = (real)num->damping;
    s->run.thickness = (real)(c->dimension == 2 ? c->thickness : 1.0);
    const double c_max = solver_max_sound_speed(c);
    const double v0 = case_fastest_speed(c, 0);
    /* Ten times the fastest wave speed plus twice the fastest initial speed:
     * far above any physical particle speed of these cases, and reached
     * within a few steps by a runaway instability. */
    s->run.velocity_limit = (real)(10.0 * c_max + 2.0 * v0);
    s->run.hourglass = (real)num->hourglass;
    s->run.axis_radius = (real)(0.25 * num->dx);
    s->run.sphere_radius = (real)(c->projectile.enabled ? 0.5 * c->projectile.diameter : 0.0);
    s->run.as_exponent = num->as_exponent;
    s->run.material_count = c->material_count;
}

int solver_create(struct solver *s, struct sph_device *dev, const struct sph_case *c,
                  const struct sph_scene *scene, char *error, size_t error_size)
{
    memset(s, 0, sizeof *s);
    s->dev = dev;
    s->dim = c->dimension;
    s->n = s->n_scene = scene->count;
    solver_configure(s, c);
    s->graded = solver_case_graded(c);
    s->coarsest_level = solver_case_coarsest_level(c);
    s->dx = c->numerics.dx;
    s->skin = SPH_GRID_SKIN;
    s->moved_since_contact_search = HUGE_VAL;
    s->thickness_scale = c->dimension != 2                    ? 1.0
                         : c->plane == SPH_PLANE_AXISYMMETRIC ? 2.0 * M_PI /* per radian */
                                                              : c->thickness;
    s->probe_count = scene->probe_count;
    fill_run_params(s, c);
    /* over several processes: this rank's share of the scene (host/domain.c) */
    struct sph_scene local = {0};
    if (dist_size() > 1 && solver_domain_setup(s, scene, &local, error, error_size)) {
        scene_free(&local);
        return 1;
    }
    const struct sph_scene *own = s->domain.active ? &local : scene;
    solver_ghosts_setup(s, c, own);
    if (s->domain.active)
        solver_domain_size(s);
    /* the reductions' work-groups: one per 1024 particles, at most
     * REDUCE_MAX_GROUPS (a small scene's sums need no more; under oclgrind
     * each group's local-memory tree is interpreted, and 64 of them took
     * seconds per launch on a 21-particle scene) */
    s->reduce_groups = (int)fmin(REDUCE_MAX_GROUPS, fmax(1.0, ceil(s->n / 1024.0)));
    const int failed = solver_create_buffers(s, c, own, error, error_size);
    scene_free(&local);
    if (failed)
        return 1;
    solver_upload_constants(s, c);
    create_kernels(s);
    solver_ghosts_create(s);
    solver_domain_create(s);
    if (solver_projectile_create(s, c, scene, error, error_size))
        return 1;
    if (cl_failed()) /* a buffer, upload or kernel the calls above could not make */
        return snprintf(error, error_size, "%s", cl_failure()) > 0;
    return 0;
}

void solver_release(struct solver *s)
{
    solver_projectile_release(s);
    solver_domain_release(s);
    solver_ghosts_release(s);
    release_kernels(s);
    solver_release_buffers(s);
}

static void read_bounds(struct solver *s, double lo[3], double hi[3])
{
    SET_ARGS(s, s->k.bounds, MEM("partials", s->bounds_partials), INT("n", s->n));
    solver_launch(s, s->k.bounds, (size_t)s->reduce_groups * REDUCE_GROUP, REDUCE_GROUP);
    const size_t count = 6 * (size_t)s->reduce_groups;
    double values[6 * REDUCE_MAX_GROUPS] = {0};
    solver_read_reals(s, s->bounds_partials, count, values);
    for (int a = 0; a < 3; ++a) {
        lo[a] = HUGE_VAL;
        hi[a] = -HUGE_VAL;
    }
    for (int g = 0; g < s->reduce_groups; ++g)
        for (int a = 0; a < s->dim; ++a) {
            lo[a] = fmin(lo[a], values[6 * g + a]);
            hi[a] = fmax(hi[a], values[6 * g + 3 + a]);
        }
}

/* Sizes the grid to the particles' bounding box plus one cell each side. */
static int layout_grid(struct solver *s, char *error, size_t error_size)
{
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    read_bounds(s, lo, hi);
    struct grid *g = &s->grid;
    g->cell_size = s->run.support * (1.0 + s->skin) / SPH_GRID_SPLIT;
    double cells = 1;
    for (int a = 0; a < 3; ++a) {
        if (a < s->dim) {
            if (!isfinite(lo[a]) || !isfinite(hi[a])) {
                snprintf(error, error_size, "particle positions are not finite (NaN)");
                return 1;
            }
            g->origin[a] = lo[a] - g->cell_size;
            const double span = (hi[a] - lo[a]) / g->cell_size + 3.0;
            cells *= span;
            g->dims[a] = span < (double)MAX_CELLS ? (int)span : MAX_CELLS;
        } else {
            g->origin[a] = 0;
            g->dims[a] = 1;
        }
    }
    if (cells > (double)MAX_CELLS) {
        snprintf(error, error_size,
                 "particles spread over %.3g cells (box %.3g x %.3g x %.3g m): particles have "
                 "left the domain",
                 cells, hi[0] - lo[0], hi[1] - lo[1], s->dim == 3 ? hi[2] - lo[2] : 0.0);
        return 1;
    }
    g->cell_count = g->dims[0] * g->dims[1] * g->dims[2];
    g->dims4 = (cl_int4){{g->dims[0], g->dims[1], g->dims[2], 0}};
    if (g->cell_count > g->cell_capacity) {
        g->cell_capacity = g->cell_count + g->cell_count / 4;
        solver_make_cell_buffers(s, sizeof(cl_int) * (size_t)g->cell_capacity);
    }
    return 0;
}

void solver_make_cell_buffers(struct solver *s, size_t bytes)
{
    cl_mem *cells[] = {&s->cell_start,       &s->cell_end,
                       &s->cell_level,       &s->cell_coarser[0],
                       &s->cell_coarser[1],  &s->contact_cell_start,
                       &s->contact_cell_end, &s->contact_cell_part_bits};
    const int tl_contact = s->total_lagrangian && s->part_contact;
    for (int c = 0; c < 8; ++c) {
        solver_release_buffer(cells[c]);
        /* the level buffers: graded lattices only; the contact search's:
         * the total Lagrangian form with parts only */
        if (c < 2 || (c < 5 && s->graded) || (c >= 5 && tl_contact))
            *cells[c] = solver_create_buffer(s, bytes);
    }
}

static void sort_keys(struct solver *s)
{
    SET_ARGS(s, s->k.cell_keys, INT("n", s->n));
    solver_launch(s, s->k.cell_keys, (size_t)s->n, 0);
    solver_sort_keys(s, s->sort_keys, s->grid.cell_count);
}

/* Each cell's range of sorted keys into start / end (cleared to -1 first)
 * by `ranges` (grid_cell_ranges, or the contact search's). */
static void cell_ranges(struct solver *s, cl_kernel ranges, cl_mem start, cl_mem end)
{
    const cl_int minus_one = -1, cells = s->grid.cell_count;
    cl_mem targets[2] = {start, end};
    for (int t = 0; t < 2; ++t) {
        SET_ARGS(s, s->k.fill_int, MEM("a", targets[t]), INT("value", minus_one), INT("n", cells));
        solver_launch(s, s->k.fill_int, (size_t)cells, 0);
    }
    SET_ARGS(s, ranges, INT("n", s->n));
    solver_launch(s, ranges, (size_t)s->n, 0);
}

/* Graded lattices: each particle's search reach from the levels about it
 * (kernels/grid.cl, "Graded lattices"). */
static void graded_reach(struct solver *s)
{
    struct real_arg a_skin;
    const cl_int cells = s->grid.cell_count;
    SET_ARGS(s, s->k.cell_max_level, INT("cells", cells));
    solver_launch(s, s->k.cell_max_level, (size_t)cells, 0);
    SET_ARGS(s, s->k.coarser_seed, MEM("coarser_out", s->cell_coarser[0]), INT("cells", cells));
    solver_launch(s, s->k.coarser_seed, (size_t)cells, 0);
    for (int axis = 0; axis < s->dim; ++axis) {
        const cl_int rows = cells / s->grid.dims[axis]; /* of cells along the axis */
        SET_ARGS(s, s->k.coarser_spread, MEM("coarser_in", s->cell_coarser[axis % 2]),
                 MEM("coarser_out", s->cell_coarser[(axis + 1) % 2]), INT("axis", axis),
                 real_value(s, &a_skin, "skin", s->skin), INT("coarsest", s->coarsest_level),
                 INT("rows", rows));
        solver_launch(s, s->k.coarser_spread, (size_t)rows, 0);
    }
    /* the gather spare (free after the gathers) holds the reaches */
    struct real_arg a_cell;
    SET_ARGS(s, s->k.neighbour_reach, MEM("cell_coarser", s->cell_coarser[s->dim % 2]),
             real_value(s, &a_skin, "skin", s->skin),
             real_value(s, &a_cell, "cell_size", s->grid.cell_size), MEM("reach", s->gather_spare),
             INT("n", s->n));
    solver_launch(s, s->k.neighbour_reach, (size_t)s->n, 0);
    SET_ARGS(s, s->k.apply_reach, MEM("reach", s->gather_spare), INT("n", s->n));
    solver_launch(s, s->k.apply_reach, (size_t)s->n, 0);
}

int solver_sort(struct solver *s, char *error, size_t error_size)
{
    /* over several processes the particles migrate first (collective); the
     * rest is this rank's, and every rank learns whether any failed */
    int failed = s->domain.active && solver_domain_exchange(s, error, error_size);
    failed =
        failed || solver_ghosts_rebuild(s, error, error_size) || layout_grid(s, error, error_size);
    if (!failed) {
        sort_keys(s);
        cell_ranges(s, s->k.cell_ranges, s->cell_start, s->cell_end);
        solver_gather_persistent(s);
        s->moved_since_sort = 0;
        /* the contact list holds slots of the old order */
        s->moved_since_contact_search = HUGE_VAL;
        ++s->sorts;
        solver_ghosts_reindex(s);
        if (s->graded)
            graded_reach(s);
        solver_lane_lists_build(s);
    }
    return dist_agree(failed, error, error_size);
}

/* Room for `count` ints in *m (grown by a quarter beyond need, *capacity
 * its ints); what it held is lost. */
static void ensure_ints(struct solver *s, cl_mem *m, long *capacity, long count)
{
    if (*m && count <= *capacity)
        return;
    solver_release_buffer(m);
    *capacity = count + count / 4 + 16;
    *m = solver_create_buffer(s, sizeof(cl_int) * (size_t)*capacity);
}

/* One launch of lane_list_build: the first walk (rewalk 0, list_claim
 * zeroed first) or the second, of the blocks over their room. */
static void lane_list_launch(struct solver *s, cl_mem at, double reach_scale, cl_int rewalk)
{
    const cl_int blocks = (cl_int)solver_lane_blocks(s), zero = 0, two = 2;
    const cl_int capacity = (cl_int)s->lane_list_capacity;
    struct real_arg a_scale;
    if (!rewalk) {
        SET_ARGS(s, s->k.fill_int, MEM("a", s->lane_list_claim), INT("value", zero), INT("n", two));
        solver_launch(s, s->k.fill_int, 2, 0);
    }
    SET_ARGS(s, s->k.lane_list_build, MEM("at", at),
             real_value(s, &a_scale, "reach_scale", reach_scale),
             MEM("list_claim", s->lane_list_claim), INT("capacity", capacity),
             INT("rewalk", rewalk), INT("n", s->n));
    solver_launch(s, s->k.lane_list_build, (size_t)blocks, 0);
}

/* The candidates within reach_scale x the pair's support of some lane at
 * the sort: 1 + skin in the updated form (the grid's margin: the list
 * serves until the next sort, as the cells do), 1 in the total Lagrangian
 * form (its reference positions move only at a reference update, which
 * sorts); 1e-4 more for the rounding of
 * the distance tests, so that the list holds every candidate a pass's test
 * can accept. One walk per sort and one read-back (the entries claimed and
 * the blocks left to write; kernels/lanes.cl, lane_list_build). A list too
 * short is grown and the walk done again; the list starts empty, so every
 * run takes that path at its first sort and keeps a quarter more than it
 * used. A block with more candidates than its private room is walked again
 * alone, writing straight into its claimed place. */
void solver_lane_lists_build(struct solver *s)
{
    if (!s->lane_lists) { /* the passes walk the cells: tokens to bind */
        ensure_ints(s, &s->lane_list_range, &s->lane_list_range_capacity, 2);
        ensure_ints(s, &s->lane_list, &s->lane_list_capacity, 1);
        return;
    }
    ensure_ints(s, &s->lane_list_range, &s->lane_list_range_capacity, 2 * solver_lane_blocks(s));
    ensure_ints(s, &s->lane_list_claim, &s->lane_list_claim_capacity, 2);
    ensure_ints(s, &s->lane_list, &s->lane_list_capacity, 1);
    const int tl = s->total_lagrangian;
    const double scale = (tl ? 1.0 : 1.0 + s->skin) * (1.0 + 1e-4);
    cl_mem at = s->field[tl ? FIELD_POS0 : FIELD_POS];
    cl_int claim[2] = {0, 0}; /* entries claimed, blocks over their room */
    do {                      /* the counts do not change: at most one growth */
        if (claim[0] > s->lane_list_capacity)
            ensure_ints(s, &s->lane_list, &s->lane_list_capacity, claim[0]);
        lane_list_launch(s, at, scale, 0);
        CL_CHECK(clEnqueueReadBuffer(s->dev->queue, s->lane_list_claim, CL_TRUE, 0, sizeof claim,
                                     claim, 0, NULL, NULL));
    } while (!cl_failed() && claim[0] > s->lane_list_capacity);
    s->lane_list_entries = claim[0];
    if (claim[1] > 0)
        lane_list_launch(s, at, scale, 1);
}

long solver_lane_blocks(const struct solver *s)
{
    return ((long)s->n + s->lanes - 1) / s->lanes;
}

size_t solver_lane_list_bytes(const struct solver *s)
{
    return s->lane_lists
               ? sizeof(cl_int) * (size_t)(s->lane_list_capacity + s->lane_list_range_capacity +
                                           s->lane_list_claim_capacity)
               : 0;
}

/* Work-items of passes 1 and 2: one per particle, or per lane block. */
static size_t pass_items(const struct solver *s)
{
    return (size_t)solver_lane_blocks(s);
}

/* Pass 1 and, particle by particle at its end, the material update. */
static void pass1(struct solver *s, double dt)
{
    struct real_arg a_dt;
    SET_ARGS(s, s->k.pass1, real_value(s, &a_dt, "dt", dt), INT("n", s->n));
    solver_launch(s, s->k.pass1, pass_items(s), 0);
}

static void pass2(struct solver *s)
{
    SET_ARGS(s, s->k.pass2, INT("n", s->n));
    solver_launch(s, s->k.pass2, pass_items(s), 0);
}

/* Total Lagrangian passes (kernels/total_lagrangian.cl). */
static void tl_correction(struct solver *s)
{
    SET_ARGS(s, s->k.tl_correction, INT("n", s->n));
    solver_launch(s, s->k.tl_correction, (size_t)s->n, 0);
}

static void tl_deformation(struct solver *s, double dt)
{
    struct real_arg a_dt;
    SET_ARGS(s, s->k.tl_deformation, real_value(s, &a_dt, "dt", dt), INT("n", s->n));
    solver_launch(s, s->k.tl_deformation, pass_items(s), 0);
}

static void tl_momentum(struct solver *s)
{
    SET_ARGS(s, s->k.tl_momentum, INT("n", s->n));
    solver_launch(s, s->k.tl_momentum, pass_items(s), 0);
}

/* The contact of parts in the total Lagrangian form (kernels/
 * contact_current.cl): a cell list of the current positions, sorted
 * (tl_contact_list_current says when) on the reference grid's cells (particles outside its box sit
 * in its border cells) with the set of parts in each cell, then the
 * contact pass over it, which adds to what tl_momentum wrote. */
static void tl_contact_search(struct solver *s)
{
    SET_ARGS(s, s->k.contact_cell_keys, INT("n", s->n));
    solver_launch(s, s->k.contact_cell_keys, (size_t)s->n, 0);
    solver_sort_keys(s, s->contact_keys, s->grid.cell_count);
    cell_ranges(s, s->k.contact_cell_ranges, s->contact_cell_start, s->contact_cell_end);
    const cl_int zero = 0, cells = s->grid.cell_count;
    SET_ARGS(s, s->k.fill_int, MEM("a", s->contact_cell_part_bits), INT("value", zero),
             INT("n", cells));
    solver_launch(s, s->k.fill_int, (size_t)cells, 0);
    SET_ARGS(s, s->k.contact_cell_parts, INT("n", s->n));
    solver_launch(s, s->k.contact_cell_parts, (size_t)s->n, 0);
}

/* The contact search's list, searched again only once a particle may have
 * left the cell it was keyed to by more than the walk's reach (SPH_GRID_
 * SPLIT cells) less the contact's d (the lattice spacing): tl_part_contact
 * walks the cells around each particle's current cell, so a pair closer
 * than d is found while the other particle has drifted less than that
 * since the search
 * (moved_since_contact_search, a bound without a stored position). The
 * list and the bound are checkpointed, so a resumed run searches at the
 * same steps. */
static void tl_contact_list_current(struct solver *s)
{
    const double d = s->run.h * s->run.av_eta_crit; /* the lattice spacing */
    if (s->moved_since_contact_search < 0.9 * (SPH_GRID_SPLIT * s->grid.cell_size - d))
        return;
    tl_contact_search(s);
    s->moved_since_contact_search = 0;
}

static void tl_part_contact(struct solver *s)
{
    tl_contact_list_current(s);
    SET_ARGS(s, s->k.tl_part_contact, INT("n", s->n));
    solver_launch(s, s->k.tl_part_contact, pass_items(s), 0);
}

/* Pass 1 and the stress-derived fields of the updated or total form. */
static void deformation_and_material(struct solver *s, double dt)
{
    /* the kick changed the half-step velocity, pass 2 the XSPH velocity */
    static const enum field moved[] = {FIELD_VEL_HALF, FIELD_XSPH_VELOCITY};
    solver_ghosts_refresh(s, moved, 2);
    if (s->total_lagrangian)
        tl_deformation(s, dt); /* with the material update, as pass 1 */
    else
        pass1(s, dt);
}

void solver_prime(struct solver *s)
{
    if (s->total_lagrangian)
        tl_correction(s);
    deformation_and_material(s, 0.0);
}

void solver_step(struct solver *s, double dt, double dt_prev, const double load[3])
{
    struct real_arg a_dt, a_prev, a_dx;
    struct real4_arg a_load;
    solver_ghosts_refresh(s, NULL, 0); /* the state the previous step left */
    if (s->total_lagrangian) {
        tl_momentum(s);
        if (s->part_contact)
            tl_part_contact(s);
    } else
        pass2(s);
    if (s->projectile.enabled)
        solver_projectile_contact(s, dt, dt_prev); /* adds to the accelerations */
    SET_ARGS(s, s->k.kick, real_value(s, &a_dx, "dx", s->dx), real_value(s, &a_dt, "dt", dt),
             real_value(s, &a_prev, "dt_prev", dt_prev),
             real4_value(s, &a_load, "load_force", load), INT("n", s->n));
    solver_launch(s, s->k.kick, (size_t)s->n, 0);
    deformation_and_material(s, dt);
    /* symmetry planes the particles must not cross (side 0: no plane) */
    double side[3], plane[3];
    for (int a = 0; a < 3; ++a) {
        side[a] = s->ghosts.reflected[a] ? s->ghosts.side[a] : 0.0;
        plane[a] = s->ghosts.plane[a];
    }
    /* the gap off the planes (kernels/integrate.cl) keeps a particle from
     * its own image, where the updated form's kernel gradient vanishes; the
     * total Lagrangian form takes its gradients on the reference and its
     * density from F, and a gap of dx / 4 there held the first layer of the
     * held 3-D copper face off the wall while the second, squashed tenfold,
     * came down onto it (0.007 dx apart at 0.28 mm) */
    struct real4_arg a_side, a_plane;
    struct real_arg a_gap;
    SET_ARGS(s, s->k.drift, real_value(s, &a_dt, "dt", dt),
             real4_value(s, &a_plane, "plane", plane), real4_value(s, &a_side, "side", side),
             real_value(s, &a_gap, "plane_gap", s->total_lagrangian ? 0.0 : 0.25 * s->dx),
             INT("n", s->n));
    solver_launch(s, s->k.drift, (size_t)s->n, 0);
}

static void combine_partials(const struct solver *s, const double *v, struct reduction *out)
{
    memset(out, 0, sizeof *out);
    double bad = 1e300;
    for (int g = 0; g < s->reduce_groups; ++g) {
        const double *p = &v[g * SPH_RED_SLOTS];
        out->max_signal = fmax(out->max_signal, p[SPH_RED_MAX_SIGNAL]);
        out->max_speed = fmax(out->max_speed, p[SPH_RED_MAX_SPEED]);
        out->max_drift_speed = fmax(out->max_drift_speed, p[SPH_RED_MAX_DRIFT]);
        bad = fmin(bad, p[SPH_RED_BAD_INDEX]);
        out->load_power += p[SPH_RED_LOAD_POWER];
        out->kinetic += p[SPH_RED_KINETIC];
        out->internal += p[SPH_RED_INTERNAL];
        for (int a = 0; a < 3; ++a) {
            out->probe_displacement[a] += p[SPH_RED_PROBE_DISP_X + a];
            out->momentum[a] += p[SPH_RED_MOMENTUM_X + a];
            out->wall_force[a] += p[SPH_RED_WALL_FORCE_X + a];
        }
        out->wall_power += p[SPH_RED_WALL_POWER];
        out->viscous_power += p[SPH_RED_VISCOUS_POWER];
        out->hourglass_power += p[SPH_RED_HOURGLASS_POWER];
        out->max_distortion = fmax(out->max_distortion, p[SPH_RED_MAX_DISTORTION]);
    }
    out->bad_id = bad < (double)s->n_real ? (long)bad : -1;
    for (int a = 0; a < 3; ++a)
        out->probe_displacement[a] /= s->probe_count > 0 ? s->probe_count : 1;
    /* 2-D sums are per metre of thickness */
    out->load_power *= s->thickness_scale;
    out->kinetic *= s->thickness_scale;
    out->internal *= s->thickness_scale;
    out->wall_power *= s->thickness_scale;
    out->viscous_power *= s->thickness_scale;
    out->hourglass_power *= s->thickness_scale;
    for (int a = 0; a < 3; ++a) {
        out->momentum[a] *= s->thickness_scale;
        out->wall_force[a] *= s->thickness_scale;
    }
}

/* The step's reduction; `contact` (a step's, over several processes): the
 * projectile's contact sums, made global in the same Allreduce. */
static void reduce(struct solver *s, const double load[3], struct reduction *out, int contact)
{
    struct real4_arg a_load;
    SET_ARGS(s, s->k.reduce, real4_value(s, &a_load, "load_force", load),
             MEM("partials", s->partials), INT("n", s->n));
    solver_launch(s, s->k.reduce, (size_t)s->reduce_groups * REDUCE_GROUP, REDUCE_GROUP);
    double values[REDUCE_MAX_GROUPS * SPH_RED_SLOTS] = {0}, sums[SPH_CONTACT_SLOTS];
    solver_read_reals(s, s->partials, (size_t)s->reduce_groups * SPH_RED_SLOTS, values);
    combine_partials(s, values, out);
    contact = contact && s->domain.active;
    if (contact)
        solver_projectile_sums(s, sums);
    solver_domain_reduce(s, out, contact ? sums : NULL);
    if (contact)
        solver_projectile_share(s, sums);
}

void solver_reduce(struct solver *s, const double load[3], struct reduction *out)
{
    reduce(s, load, out, 0);
}

/* The mirrors' and halo's positions are the step's start's until the next
 * step refreshes them, and the drift has moved their sources since: the
 * health measures between steps take them fresh (tests/check_health.py
 * found pairs counted against the old ones). */
static void refresh_ghost_positions(struct solver *s)
{
    static const enum field moved[] = {FIELD_POS};
    solver_ghosts_refresh(s, moved, 1);
}

/* Each particle's health record (kernels/health.cl, health_pairs) in the
 * gather target, free between sorts (a record is two reals, the target
 * holds a vec or more). */
static void health_records(struct solver *s)
{
    refresh_ghost_positions(s);
    if (s->total_lagrangian && s->part_contact)
        tl_contact_list_current(s); /* the other parts near each particle now */
    struct real_arg a_dx;
    SET_ARGS(s, s->k.health_pairs, real_value(s, &a_dx, "dx", s->dx),
             MEM("records", s->gather_spare), INT("n", s->n));
    solver_launch(s, s->k.health_pairs,
                  s->total_lagrangian ? (size_t)s->n : (size_t)solver_lane_blocks(s), 0);
}

void solver_health(struct solver *s, struct health_reading *out)
{
    health_records(s);
    SET_ARGS(s, s->k.health, MEM("records", s->gather_spare), MEM("partials", s->partials),
             INT("n", s->n));
    solver_launch(s, s->k.health, (size_t)s->reduce_groups * REDUCE_GROUP, REDUCE_GROUP);
    double v[REDUCE_MAX_GROUPS * SPH_HEALTH_SLOTS] = {0};
    solver_read_reals(s, s->partials, (size_t)s->reduce_groups * SPH_HEALTH_SLOTS, v);
    double min_distance = HUGE_VAL, nb_min = HUGE_VAL, nb_max = 0, sums[SPH_HEALTH_SLOTS] = {0};
    for (int g = 0; g < s->reduce_groups; ++g) {
        const double *p = &v[g * SPH_HEALTH_SLOTS];
        min_distance = fmin(min_distance, p[SPH_HEALTH_MIN_DISTANCE]);
        nb_min = fmin(nb_min, p[SPH_HEALTH_NEIGHBOURS_MIN]);
        nb_max = fmax(nb_max, p[SPH_HEALTH_NEIGHBOURS_MAX]);
        for (int k = 0; k < SPH_HEALTH_SLOTS; ++k)
            sums[k] += p[k];
    }
    double minima[2] = {min_distance, nb_min};
    dist_min(minima, 2);
    dist_max(&nb_max, 1);
    dist_sum(sums, SPH_HEALTH_SLOTS);
    min_distance = minima[0], nb_min = minima[1];
    const double count = fmax(sums[SPH_HEALTH_PARTICLES], 1.0);
    out->min_pair_distance = min_distance;
    out->clumped_fraction = sums[SPH_HEALTH_CLUMPED] / count;
    out->swegle_fraction = sums[SPH_HEALTH_SWEGLE] / count;
    out->neighbours_min = nb_min;
    out->neighbours_mean = sums[SPH_HEALTH_NEIGHBOURS_SUM] / count;
    out->neighbours_max = nb_max;
}

/* Each particle's neighbour count into count[]: in the updated Lagrangian
 * form the health records' (the lane loop's search), in the total
 * Lagrangian form health_neighbour_count's (its reference neighbours not
 * torn apart, or with `reference_baseline` all of them). */
static void neighbour_counts_of_slots(struct solver *s, int *count, int reference_baseline)
{
    if (s->total_lagrangian) {
        refresh_ghost_positions(s);
        SET_ARGS(s, s->k.neighbour_count, MEM("neighbour_count", s->gather_spare),
                 INT("every_reference_neighbour", reference_baseline), INT("n", s->n));
        solver_launch(s, s->k.neighbour_count, (size_t)s->n, 0);
        CL_CHECK(clEnqueueReadBuffer(s->dev->queue, s->gather_spare, CL_TRUE, 0,
                                     sizeof(int) * (size_t)s->n, count, 0, NULL, NULL));
        return;
    }
    health_records(s);
    const size_t real_size = s->element_size[ELEM_REAL], record = 2 * real_size;
    unsigned char *raw = CHECKED_CALLOC((size_t)s->n * record + 1, 1, "health records");
    if (!raw)
        return;
    CL_CHECK(clEnqueueReadBuffer(s->dev->queue, s->gather_spare, CL_TRUE, 0, record * (size_t)s->n,
                                 raw, 0, NULL, NULL));
    for (int k = 0; k < s->n; ++k) { /* the int after the record's real */
        int code;
        memcpy(&code, raw + (size_t)k * record + real_size, sizeof code);
        count[k] = code & SPH_HEALTH_COUNT_MASK;
    }
    free(raw);
}

void solver_neighbour_counts(struct solver *s, int *count_by_id, int reference_baseline)
{
    int *count = CHECKED_CALLOC((size_t)s->n, sizeof(int), "neighbour counts");
    int *id = CHECKED_CALLOC((size_t)s->n, sizeof(int), "neighbour count ids");
    if (!count || !id) {
        free(count), free(id);
        return;
    }
    neighbour_counts_of_slots(s, count, reference_baseline);
    CL_CHECK(clEnqueueReadBuffer(s->dev->queue, s->field[FIELD_ID], CL_TRUE, 0,
                                 sizeof(int) * (size_t)s->n, id, 0, NULL, NULL));
    solver_domain_rows(s, id, s->n);
    if (s->domain.active) /* every rank fills its own; the sum is the whole */
        memset(count_by_id, 0, sizeof(int) * (size_t)s->n_scene);
    for (int k = 0; k < s->n; ++k)
        if (id[k] >= 0)
            count_by_id[id[k]] = count[k];
    if (s->domain.active)
        dist_sum_ints(count_by_id, (size_t)s->n_scene);
    free(count);
    free(id);
}

/* numerics.reference_update: the configuration of now becomes the total
 * Lagrangian form's reference (kernels/total_lagrangian.cl,
 * tl_reference_reset), its neighbours are searched again on it (a sort:
 * the grid, the mirror particles and the lists follow the new reference)
 * and tl_correction gives C and A for it. Taken after a step, where F is
 * the gradient of the positions the drift wrote. */
static int reference_update(struct solver *s, char *error, size_t error_size)
{
    SET_ARGS(s, s->k.tl_reference_reset, INT("n", s->n));
    solver_launch(s, s->k.tl_reference_reset, (size_t)s->n, 0);
    if (solver_sort(s, error, error_size))
        return 1;
    tl_correction(s);
    ++s->reference_updates;
    return 0;
}

int solver_advance(struct solver *s, double dt, double dt_prev, const double load[3],
                   struct reduction *red, char *error, size_t error_size)
{
    /* the total Lagrangian form keeps the reference neighbours: it sorts
     * only at the start and at a reference update (below) */
    const int moved = s->moved_since_sort >= 0.5 * s->skin * s->run.support;
    if (!s->total_lagrangian && moved && solver_sort(s, error, error_size))
        return 1;
    solver_step(s, dt, dt_prev, load);
    reduce(s, load, red, s->projectile.enabled);
    /* the sphere's leap-frog with the particles' (nothing between the
     * contact and here reads it) */
    if (s->projectile.enabled)
        solver_projectile_advance(s, dt, dt_prev);
    /* no particle has drifted farther than the sum of the steps' largest
     * drift: a bound without a stored position per particle (16 B) */
    s->moved_since_sort += red->max_drift_speed * dt;
    s->moved_since_contact_search += red->max_drift_speed * dt;
    if (s->reference_update > 0 && red->max_distortion >= s->reference_update)
        return reference_update(s, error, error_size);
    return 0;
}
