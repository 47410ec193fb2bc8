/* Impact figures of a snapshot (host/run_parts.h): the body's extent along
 * walls[0]'s normal and the radius of its lowest layer (particles within
 * dx/2 of the lowest) around the axis through the wall's point, both plus
 * dx/2 per side so the initial lattice gives the box's dimensions (a bar
 * that rebounds off the wall is measured the same way); the largest
 * plastic strain and temperature; the damaged particles. */
#include <math.h>
#include <string.h>

#include "domain.h"
#include "run_parts.h"

static void measure_footprint(struct impact_metrics *m, const struct sph_case *c,
                              const struct host_fields *f)
{
    const double dx = c->numerics.dx;
    const struct case_wall *w = &c->walls[0];
    const double *pos = HOST_REALS(f, FIELD_POS);
    const int *flags = HOST_INTS(f, FIELD_FLAGS);
    double lowest = HUGE_VAL, highest = -HUGE_VAL, radius = 0;
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1 && f->distributed) /* each rank holds its share */
            dist_min(&lowest, 1), dist_max(&highest, 1);
        for (int p = 0; p < f->n; ++p) {
            if (flags[p] & SPH_FLAG_FIXED)
                continue;
            double r[3], height = 0;
            for (int a = 0; a < 3; ++a) {
                r[a] = pos[3 * p + a] - w->point[a];
                height += r[a] * w->normal[a];
            }
            if (pass == 0) {
                lowest = fmin(lowest, height);
                highest = fmax(highest, height);
            } else if (height < lowest + 0.5 * dx) {
                double lateral = 0;
                for (int a = 0; a < 3; ++a) {
                    const double t = r[a] - height * w->normal[a];
                    lateral += t * t;
                }
                radius = fmax(radius, sqrt(lateral));
            }
        }
    }
    if (f->distributed)
        dist_max(&radius, 1);
    m->final_length = highest - lowest + dx;
    m->footprint_radius = radius + 0.5 * dx;
}

void impact_measure(struct impact_metrics *m, const struct sph_case *c, const struct host_fields *f,
                    char *damaged)
{
    const double *plastic_strain = HOST_REALS(f, FIELD_PLASTIC_STRAIN);
    const double *temperature = HOST_REALS(f, FIELD_TEMPERATURE);
    const int *flags = HOST_INTS(f, FIELD_FLAGS);
    double most[2] = {m->max_plastic_strain, m->max_temperature}, count = 0;
    if (f->distributed) /* rows of other ranks are theirs to mark */
        memset(damaged, 0, (size_t)f->n_total);
    for (int p = 0; p < f->n; ++p) {
        most[0] = fmax(most[0], plastic_strain[p]);
        most[1] = fmax(most[1], temperature[p]);
        const int hit = (flags[p] & SPH_FLAG_DAMAGED) != 0;
        damaged[f->id ? f->id[p] : p] = (char)hit;
        count += hit;
    }
    if (f->distributed) {
        dist_max(most, 2);
        dist_sum(&count, 1);
        dist_or_bytes(damaged, (size_t)f->n_total);
    }
    m->max_plastic_strain = most[0], m->max_temperature = most[1];
    m->damaged_fraction = fmax(m->damaged_fraction, count / (f->n_total > 0 ? f->n_total : 1));
    if (c->wall_count > 0)
        measure_footprint(m, c, f);
}
