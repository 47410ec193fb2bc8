/* Graded lattices: a body filled finest around the region of interest and
 * coarser away from it (bodies[].grading).
 *
 * Level k has spacing 2^k dx and covers box_k less box_(k-1): box_0 is the
 * fine box, box_k adds `layers` particles of level k on every side, and the
 * coarsest level fills the rest of the body. Every lattice starts at the
 * body's corner nearest the fine box (for a penetration target: the impact
 * face and the axis), and box_k's faces are snapped outward to whole cells
 * of level k + 1, so the levels tile the body without gaps or overlaps. A
 * particle's level and how many grid cells its neighbour search reaches go
 * into its flags (include/sph_shared.h); kernels/common.cl turns them into
 * the pair's smoothing length and the search.
 *
 * The track form (an oblique shot) replaces the boxes by tubes about a
 * segment: region k is the set of level-(k + 1) cells whose centre lies
 * within R_k of the segment, R_0 = track_radius and R_k = R_(k-1) +
 * (layers + sqrt(dim)) 2^k dx, and a level-k cell is filled at level k when
 * its parent cell is in region k and the cell itself is not in region
 * k - 1. The radii grow by at least a parent's half-diagonal per level, so
 * a cell of region k - 1 always has its parent in region k: the levels
 * nest and tile the body as the boxes do. */
#include <math.h>

#include "scene.h"

#define MAX_LEVELS 7

struct grading_frame {
    int dim, levels, track;
    double dx;
    double from[3], to[3], radius[MAX_LEVELS];   /* the track form: segment and R_k, m */
    double anchor[3];                            /* the body corner the lattices start from */
    double sign[3];                              /* +1 where the body lies above the anchor */
    double lo[MAX_LEVELS][3], hi[MAX_LEVELS][3]; /* box_k in t = sign (x - anchor) >= 0 */
};

static void make_track(const struct case_grading *gr, struct grading_frame *g)
{
    g->track = 1;
    for (int a = 0; a < 3; ++a)
        g->from[a] = gr->track_from[a], g->to[a] = gr->track_to[a];
    double r = gr->track_radius;
    for (int k = 0; k < g->levels; ++k) {
        if (k > 0)
            r += (gr->layers + sqrt((double)g->dim)) * g->dx * (1 << k);
        g->radius[k] = r;
    }
}

static void make_frame(const struct sph_case *c, const struct case_body *b, struct grading_frame *g)
{
    const struct case_grading *gr = &b->grading;
    g->dim = c->dimension;
    g->levels = gr->levels;
    g->dx = c->numerics.dx;
    g->track = 0;
    if (gr->track_radius > 0)
        make_track(gr, g);
    for (int a = 0; a < 3; ++a) {
        g->anchor[a] = 0;
        g->sign[a] = 1;
        if (a >= g->dim)
            continue;
        /* the track form anchors at the corner nearest the entry point */
        const double centre =
            g->track ? gr->track_from[a] : 0.5 * (gr->fine.min[a] + gr->fine.max[a]);
        const int from_min = fabs(centre - b->box.min[a]) <= fabs(b->box.max[a] - centre);
        g->anchor[a] = from_min ? b->box.min[a] : b->box.max[a];
        g->sign[a] = from_min ? 1.0 : -1.0;
        const double t0 = g->sign[a] * (gr->fine.min[a] - g->anchor[a]);
        const double t1 = g->sign[a] * (gr->fine.max[a] - g->anchor[a]);
        double lo = fmax(fmin(t0, t1), 0.0), hi = fmax(t0, t1);
        for (int k = 0; k < g->levels; ++k) {
            const double widen = k == 0 ? 0.0 : gr->layers * g->dx * (1 << k);
            const double cell = g->dx * (1 << (k + 1)); /* the next level's spacing */
            lo = fmax(floor((lo - widen) / cell + 1e-9) * cell, 0.0);
            hi = ceil((hi + widen) / cell - 1e-9) * cell;
            g->lo[k][a] = lo;
            g->hi[k][a] = hi;
        }
    }
}

/* Distance from x to the segment from - to, m. */
static double segment_distance(const double from[3], const double to[3], const double x[3], int dim)
{
    double d[3] = {0, 0, 0}, r[3] = {0, 0, 0}, dd = 0, rd = 0;
    for (int a = 0; a < dim; ++a) {
        d[a] = to[a] - from[a], r[a] = x[a] - from[a];
        dd += d[a] * d[a], rd += r[a] * d[a];
    }
    const double s = dd > 0 ? fmin(fmax(rd / dd, 0.0), 1.0) : 0.0;
    double off2 = 0;
    for (int a = 0; a < dim; ++a)
        off2 += (r[a] - s * d[a]) * (r[a] - s * d[a]);
    return sqrt(off2);
}

/* Track form: whether the level-(k + 1) cell holding frame point t is in
 * region k (its centre within R_k of the segment). */
static int in_track_region(const struct grading_frame *g, int k, const double *t)
{
    const double cell = g->dx * (1 << (k + 1));
    double x[3] = {0, 0, 0};
    for (int a = 0; a < g->dim; ++a)
        x[a] = g->anchor[a] + g->sign[a] * (floor(t[a] / cell) + 0.5) * cell;
    return segment_distance(g->from, g->to, x, g->dim) <= g->radius[k];
}

static int in_level_box(const struct grading_frame *g, int k, const double *t)
{
    if (k < 0)
        return 0;
    if (k >= g->levels)
        return 1;
    if (g->track)
        return in_track_region(g, k, t);
    for (int a = 0; a < g->dim; ++a)
        if (t[a] < g->lo[k][a] || t[a] > g->hi[k][a])
            return 0;
    return 1;
}

/* Grid cells (sized for the finest level: support (1 + skin) / SPH_GRID_SPLIT) a level-k
 * particle searches among its own level; kernels/grid.cl
 * (grid_neighbour_reach) widens it at every sort where a coarser level is
 * near. */
static int search_reach(int k, double skin)
{
    return (int)ceil(SPH_GRID_SPLIT * ((double)(1 << k) + skin) / (1.0 + skin) - 1e-9);
}

/* The lattice indices level k visits along each axis: a superset of the
 * cells in region k (the box form's box_k, the track form's tube's bounding
 * box), the whole body for the coarsest level. Cells outside would be
 * skipped by in_level_box anyway; bounding the loop keeps a fine level from
 * walking the whole body at the fine spacing. */
static void level_range(const struct grading_frame *g, const struct case_body *b, int k,
                        long first[3], long last[3])
{
    const double spacing = g->dx * (1 << k);
    for (int a = 0; a < 3; ++a) {
        first[a] = 0, last[a] = 0;
        if (a >= g->dim)
            continue;
        const double extent = b->box.max[a] - b->box.min[a];
        double lo = 0, hi = extent;
        if (k < g->levels && !g->track)
            lo = g->lo[k][a], hi = g->hi[k][a];
        else if (k < g->levels) {
            const double t0 = g->sign[a] * (g->from[a] - g->anchor[a]);
            const double t1 = g->sign[a] * (g->to[a] - g->anchor[a]);
            const double margin = g->radius[k] + 2 * g->dx * (1 << (k + 1));
            lo = fmin(t0, t1) - margin, hi = fmax(t0, t1) + margin;
        }
        /* t = (i + 1/2) spacing <= extent; clamped in double before the
         * casts (a hostile dx would overflow a long: scene_estimate then
         * refuses the case on these counts) */
        const double count = fmin(ceil(extent / spacing - 1e-9), 1e15);
        first[a] = (long)fmin(fmax(floor(fmax(lo, 0.0) / spacing - 0.5) - 1, 0.0), 1e15);
        last[a] = (long)fmax(fmin(ceil(fmin(hi, extent) / spacing - 0.5) + 1, count - 1), -1.0);
    }
}

double grading_points(const struct sph_case *c, const struct case_body *b)
{
    struct grading_frame g;
    make_frame(c, b, &g);
    double points = 0;
    for (int k = 0; k <= g.levels; ++k) {
        long first[3], last[3];
        level_range(&g, b, k, first, last);
        double level = 1;
        for (int a = 0; a < g.dim; ++a)
            level *= last[a] >= first[a] ? (double)(last[a] - first[a] + 1) : 0.0;
        points += level;
    }
    return points;
}

int grading_fill(const struct sph_case *c, const struct case_body *b, struct sph_particle_sink *out)
{
    struct grading_frame g;
    make_frame(c, b, &g);
    const int dim = c->dimension;
    int added = 0;
    for (int k = 0; k <= g.levels; ++k) {
        const double spacing = g.dx * (1 << k);
        double extent[3] = {0, 0, 0};
        long first[3], last[3];
        level_range(&g, b, k, first, last);
        for (int a = 0; a < dim; ++a)
            extent[a] = b->box.max[a] - b->box.min[a];
        for (long kz = first[2]; kz <= last[2]; ++kz)
            for (long ky = first[1]; ky <= last[1]; ++ky)
                for (long kx = first[0]; kx <= last[0]; ++kx) {
                    const long idx[3] = {kx, ky, kz};
                    double t[3] = {0, 0, 0}, x[3] = {0, 0, 0};
                    int inside = 1;
                    for (int a = 0; a < dim; ++a) {
                        t[a] = (idx[a] + 0.5) * spacing;
                        x[a] = g.anchor[a] + g.sign[a] * t[a];
                        inside &= t[a] <= extent[a];
                    }
                    if (!inside || !in_level_box(&g, k, t) || in_level_box(&g, k - 1, t))
                        continue;
                    if (out->emit(out, x, k, search_reach(k, out->skin)))
                        return -1;
                    ++added;
                }
    }
    return added;
}

int grading_level_at(const struct sph_case *c, const struct case_body *b, const double x[3])
{
    struct grading_frame g;
    make_frame(c, b, &g);
    double t[3] = {0, 0, 0};
    for (int a = 0; a < g.dim; ++a)
        t[a] = g.sign[a] * (x[a] - g.anchor[a]);
    int k = 0;
    while (k < g.levels && !in_level_box(&g, k, t))
        ++k;
    return k;
}
