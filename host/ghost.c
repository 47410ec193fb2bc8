/* Symmetry planes through mirror (ghost) particles: which real particles
 * get images, where the images live in the field buffers, and when they are
 * copied (kernels/ghost.cl has the copies and the physics comment).
 *
 * Ghosts are rebuilt before every cell sort: the arrays are first compacted
 * by id (reals in slots 0 .. n_real - 1, in their original order), the host
 * reads the real positions and lists every image of a particle within
 * `width` of one plane, two planes (and of their corner) or three, and the
 * images take the slots after the reals. The cell sort then mixes them with
 * the reals like any particle; index_of_id finds both again. */
#include "launch.h"
#include "solver.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Graded lattices: a particle's pairs reach 1.5 of its own supports (the
 * mean smoothing length with a coarser neighbour); every pair across a
 * plane (or a domain boundary, host/domain.c) then has both images, and stays
 * equal and opposite. */
double solver_reach_scale(const struct solver *s, int flags)
{
    return s->graded ? 1.5 * (double)(1 << SPH_LEVEL_OF(flags)) : 1.0;
}

/* Images of one position: every non-empty subset of the planes it is close
 * to. Writes their masks, returns how many. */
static int images(const struct ghosts *g, const double *x, double scale, int dim, int masks[7])
{
    int near = 0;
    for (int a = 0; a < dim; ++a)
        if (g->reflected[a] && fabs(x[a] - g->plane[a]) < g->width * scale)
            near |= 1 << a;
    int count = 0;
    for (int m = 1; m < 8; ++m)
        if ((m & near) == m)
            masks[count++] = m;
    return count;
}

void solver_ghosts_setup(struct solver *s, const struct sph_case *c, const struct sph_scene *scene)
{
    struct ghosts *g = &s->ghosts;
    memset(g, 0, sizeof *g);
    for (int k = 0; k < c->symmetry_count; ++k) {
        const int a = c->symmetry[k].axis;
        g->reflected[a] = 1;
        g->plane[a] = c->symmetry[k].position;
        /* the side the body lies on (the lattice starts half a spacing off
         * the plane, so no particle sits on it) */
        g->side[a] = scene_side_of_plane(scene, a, g->plane[a]);
        ++g->plane_count;
    }
    s->n_real = scene->count;
    s->capacity = scene->count;
    if (g->plane_count == 0)
        return;
    /* the support plus the distance particles may move between sorts */
    g->width = s->run.support * (1.0 + s->skin);
    const unsigned held = case_held_wall_axes(c);
    int initial = 0, held_images = 0, masks[7];
    for (int p = 0; p < scene->count; ++p) {
        const int m = images(g, &scene->position[3 * p], solver_reach_scale(s, scene->flags[p]),
                             c->dimension, masks);
        initial += m;
        for (int k = 0; k < m; ++k)
            held_images += (masks[k] & (int)held) != 0;
    }
    /* room for the layer near the planes to thicken as the body deforms,
     * and a face held on a wall (host/case.c, held_walls) to spread along
     * it: tenfold in area (a Taylor bar's face grows about fivefold, its
     * 3-D quarter's here 8.5-fold: docs/validation_taylor.md) */
    g->capacity = 2 * initial + 8 * held_images + 256;
    s->capacity = scene->count + g->capacity;
}

/* The ghosts' kernels, one list for making and releasing them. */
static void ghost_kernels(struct solver *s, int make)
{
    struct ghosts *g = &s->ghosts;
    const struct kernel_slot list[] = {
        {&g->index_kernel, "ghost_index_of_id", 0},
        {&g->id_keys, "ghost_id_keys", 0},
        {&g->init, "ghost_init", 0},
        {g->refresh, "ghost_refresh", 1},
    };
    solver_kernels(s, list, (int)(sizeof list / sizeof list[0]), make);
}

/* Slots by id: the mirrors' and the MPI halos' (host/domain.c). */
static int ghosts_in_use(const struct solver *s)
{
    return s->ghosts.plane_count > 0 || s->domain.active;
}

void solver_ghosts_create(struct solver *s)
{
    struct ghosts *g = &s->ghosts;
    if (!ghosts_in_use(s))
        return;
    g->source_id = solver_create_buffer(s, sizeof(cl_int) * ((size_t)g->capacity + 1));
    g->mask = solver_create_buffer(s, sizeof(cl_int) * ((size_t)g->capacity + 1));
    g->index_of_id = solver_create_buffer(s, sizeof(cl_int) * (size_t)s->capacity);
    ghost_kernels(s, 1);
}

void solver_ghosts_release(struct solver *s)
{
    struct ghosts *g = &s->ghosts;
    cl_mem *buffers[] = {&g->source_id, &g->mask, &g->index_of_id};
    for (size_t k = 0; k < sizeof buffers / sizeof buffers[0]; ++k)
        if (*buffers[k])
            clReleaseMemObject(*buffers[k]);
    ghost_kernels(s, 0);
}

void solver_ghosts_reindex(struct solver *s)
{
    struct ghosts *g = &s->ghosts;
    if (!ghosts_in_use(s))
        return;
    SET_ARGS(s, g->index_kernel, MEM("index_of_id", g->index_of_id), INT("n", s->n));
    solver_launch(s, g->index_kernel, (size_t)s->n, 0);
}

/* Copies one field into the ghosts' slots. */
static void refresh_field(struct solver *s, enum field f)
{
    struct ghosts *g = &s->ghosts;
    const struct field_info *info = &field_table[f];
    if (!solver_field_mirrored(s, f) || g->count == 0)
        return;
    cl_kernel k = g->refresh[info->kind];
    const cl_int first = s->n - g->count;
#define GHOST_ARG_LIST                                                                             \
    MEM("field", s->field[f]), MEM("ghost_source_id", g->source_id), MEM("ghost_mask", g->mask),   \
        MEM("index_of_id", g->index_of_id), INT("first_ghost", first),                             \
        INT("ghost_count", g->count)
    if (info->kind == ELEM_VEC) {
        const cl_int is_position = info->mirror == MIRROR_POSITION;
        struct real4_arg plane;
        SET_ARGS(s, k, GHOST_ARG_LIST, real4_value(s, &plane, "plane", g->plane),
                 INT("is_position", is_position));
    } else if (info->kind == ELEM_INT) {
        const int flags = info->mirror == MIRROR_FLAGS;
        const cl_int keep = flags ? SPH_GHOST_KEEP_FLAGS : ~0;
        const cl_int set = flags ? SPH_FLAG_GHOST : 0;
        SET_ARGS(s, k, GHOST_ARG_LIST, INT("keep", keep), INT("set", set));
    } else
        SET_ARGS(s, k, GHOST_ARG_LIST);
#undef GHOST_ARG_LIST
    solver_launch(s, k, (size_t)g->count, 0);
}

void solver_ghosts_refresh(struct solver *s, const enum field *fields, int count)
{
    solver_domain_refresh(s, fields, count); /* the halo first: mirrors may image it */
    if (s->ghosts.plane_count == 0 || s->ghosts.count == 0)
        return;
    if (fields) {
        for (int k = 0; k < count; ++k)
            refresh_field(s, fields[k]);
        return;
    }
    for (int f = 0; f < FIELD_COUNT; ++f)
        refresh_field(s, (enum field)f);
}

void solver_compact(struct solver *s)
{
    struct ghosts *g = &s->ghosts;
    SET_ARGS(s, g->id_keys, INT("n", s->n));
    solver_launch(s, g->id_keys, (size_t)s->n, 0);
    solver_sort_keys(s, s->sort_keys, s->n); /* ids are below n (kernels/ghost.cl) */
    solver_gather_persistent(s);
}

/* Reads the first `sources` particles' positions (slots 0 .. sources - 1
 * after the compaction) as doubles, 3 per particle, and their flags. */
static double *source_positions(struct solver *s, int sources, int *flags)
{
    const int width = s->dim == 2 ? 2 : 4;
    const size_t r = s->element_size[ELEM_REAL], count = (size_t)sources * width;
    unsigned char *raw = CHECKED_CALLOC(count * r + 1, 1, "positions read-back");
    double *x = CHECKED_CALLOC((size_t)sources * 3 + 1, sizeof(double), "positions");
    if (!raw || !x) {
        free(raw), free(x);
        return NULL;
    }
    CL_CHECK(clEnqueueReadBuffer(s->dev->queue, s->field[FIELD_POS], CL_TRUE, 0, count * r, raw, 0,
                                 NULL, NULL));
    CL_CHECK(clEnqueueReadBuffer(s->dev->queue, s->field[FIELD_FLAGS], CL_TRUE, 0,
                                 sizeof(int) * (size_t)sources, flags, 0, NULL, NULL));
    for (int p = 0; p < sources; ++p)
        for (int a = 0; a < s->dim; ++a) {
            const size_t k = (size_t)p * width + a;
            if (s->double_precision)
                memcpy(&x[3 * p + a], raw + k * r, r);
            else {
                float v;
                memcpy(&v, raw + k * r, r);
                x[3 * p + a] = v;
            }
        }
    free(raw);
    return x;
}

int solver_ghosts_rebuild(struct solver *s, char *error, size_t error_size)
{
    struct ghosts *g = &s->ghosts;
    if (g->plane_count == 0)
        return 0;
    solver_compact(s);
    /* the reals' images, and the MPI halo's (host/domain.c) */
    const int sources = s->n_real + s->domain.halo_count;
    int *flags = CHECKED_CALLOC((size_t)sources + 1, sizeof(int), "ghost source flags");
    double *x = flags ? source_positions(s, sources, flags) : NULL;
    int *source = CHECKED_CALLOC((size_t)g->capacity + 1, sizeof(int), "ghost sources");
    int *mask = CHECKED_CALLOC((size_t)g->capacity + 1, sizeof(int), "ghost masks");
    if (!x || !source || !mask) {
        free(x), free(flags), free(source), free(mask);
        return snprintf(error, error_size, "%s", cl_failure()) > 0;
    }
    int count = 0, overflow = 0, masks[7];
    for (int p = 0; p < sources; ++p) {
        const int m = images(g, &x[3 * p], solver_reach_scale(s, flags[p]), s->dim, masks);
        for (int k = 0; k < m; ++k) {
            if (count < g->capacity) {
                source[count] = p; /* after the compaction the slot is the id */
                mask[count] = masks[k];
            } else
                overflow = 1;
            ++count;
        }
    }
    free(x), free(flags);
    if (overflow) {
        snprintf(error, error_size,
                 "the symmetry planes need %d mirror particles but room was made for %d (the "
                 "body spread along a symmetry plane far beyond its initial size)",
                 count, g->capacity);
        free(source), free(mask);
        return 1;
    }
    g->count = count;
    s->n = sources + count;
    if (count > 0) {
        CL_CHECK(clEnqueueWriteBuffer(s->dev->queue, g->source_id, CL_TRUE, 0,
                                      sizeof(int) * (size_t)count, source, 0, NULL, NULL));
        CL_CHECK(clEnqueueWriteBuffer(s->dev->queue, g->mask, CL_TRUE, 0,
                                      sizeof(int) * (size_t)count, mask, 0, NULL, NULL));
        SET_ARGS(s, g->init, INT("first_ghost", sources), INT("ghost_count", g->count));
        solver_launch(s, g->init, (size_t)count, 0);
    }
    free(source), free(mask);
    solver_ghosts_reindex(s);
    solver_ghosts_refresh(s, NULL, 0);
    return 0;
}
