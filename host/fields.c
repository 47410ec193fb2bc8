/* The field registry: one row per particle field, and everything the host
 * derives from it (which fields a configuration has and mirrors, and the
 * host copies a snapshot writes). Allocation and the memory breakdown
 * (host/state.c), re-sort gathers (host/launch.c), ghost refreshes
 * (host/ghost.c), kernel arguments (host/launch.c) and snapshots
 * (host/output.c) are loops over this table; no other file lists fields. */
#include "solver.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define ALL USED_ALWAYS
#define TL USED_TOTAL_LAGRANGIAN

const struct field_info field_table[FIELD_COUNT] = {
    [FIELD_POS] = {"position", "pos", ELEM_VEC, 1, ALL, ALL, MIRROR_POSITION, "m"},
    [FIELD_POS0] = {"initial_position", "pos0", ELEM_VEC, 1, ALL, ALL, MIRROR_POSITION, NULL},
    [FIELD_DISPLACEMENT] = {"displacement", "displacement", ELEM_VEC, 1, ALL, ALL, MIRROR_REFLECT,
                            "m"},
    [FIELD_VEL] = {"velocity", "vel", ELEM_VEC, 1, ALL, ALL, MIRROR_REFLECT, "m/s"},
    [FIELD_VEL_HALF] = {"velocity_half_step", "vel_half", ELEM_VEC, 1, ALL, ALL, MIRROR_REFLECT,
                        NULL},
    [FIELD_DENSITY_CHANGE] = {"density_change", "density_change", ELEM_REAL, 1, ALL, ALL,
                              MIRROR_COPY, NULL},
    [FIELD_ENERGY] = {"internal_energy", "energy", ELEM_REAL, 1, ALL, ALL, MIRROR_COPY, "J/kg"},
    /* written as the full stress, a derived column */
    [FIELD_STRESS] = {"deviatoric_stress", "deviatoric_stress", ELEM_SYMT, 1, ALL, ALL,
                      MIRROR_REFLECT, NULL},
    [FIELD_PLASTIC_STRAIN] = {"plastic_strain", "plastic_strain", ELEM_REAL, 1, ALL, ALL,
                              MIRROR_COPY, "1"},
    [FIELD_TEMPERATURE] = {"temperature", "temperature", ELEM_REAL, 1, ALL, ALL, MIRROR_COPY, "K"},
    [FIELD_MASS] = {"mass", "mass", ELEM_REAL, 1, ALL, ALL, MIRROR_COPY,
                    "kg (2-D: per m of thickness; axisymmetric: per radian)"},
    [FIELD_FLAGS] = {"flags", "flags", ELEM_INT, 1, ALL, ALL, MIRROR_FLAGS, "bit set (README)"},
    [FIELD_MATERIAL] = {"material", "material", ELEM_INT, 1, ALL, ALL, MIRROR_COPY,
                        "index into materials[]"},
    /* a ghost's id is its own (kernels/ghost.cl) */
    [FIELD_ID] = {"id", "id", ELEM_INT, 1, ALL, 0, MIRROR_NONE,
                  "index of the particle in the scene"},
    [FIELD_RHO] = {"density", "rho", ELEM_REAL, 1, ALL, ALL, MIRROR_COPY, "kg/m^3"},
    [FIELD_PRESSURE] = {"pressure", "pressure", ELEM_REAL, 1, ALL, ALL, MIRROR_COPY, "Pa"},
    [FIELD_SOUND_SPEED] = {"sound_speed", "sound_speed", ELEM_REAL, 1, ALL, ALL, MIRROR_COPY, NULL},
    [FIELD_ARTIFICIAL_STRESS] = {"artificial_stress", "artificial_stress", ELEM_SYMT, 1,
                                 USED_ARTIFICIAL_STRESS, USED_ARTIFICIAL_STRESS, MIRROR_REFLECT,
                                 NULL},
    /* symmetric (kernels/pass1.cl); the total Lagrangian form keeps its
     * correction here too */
    [FIELD_CSPH] = {"csph_correction", "csph", ELEM_SYMT, 1, USED_CSPH | TL, USED_CSPH | TL,
                    MIRROR_REFLECT, NULL},
    [FIELD_DEFORMATION_GRADIENT] = {"deformation_gradient", "deformation_gradient", ELEM_FULLT, 1,
                                    TL, TL, MIRROR_REFLECT, NULL},
    [FIELD_FIRST_PIOLA] = {"first_piola_corrected", "first_piola", ELEM_FULLT, 1, TL, TL,
                           MIRROR_REFLECT, NULL},
    /* numerics.reference_update: pos0 is the reference and displacement is
     * measured from it; this offset (reference minus initial position) is
     * added back where the displacement is reported (the probe, snapshots) */
    [FIELD_REFERENCE_OFFSET] = {"reference_offset", "reference_offset", ELEM_VEC, 1, TL, 0,
                                MIRROR_NONE, NULL},
    /* rho0 of the reference, V0 = m / rho0 (the material's density until
     * the first reference update) */
    [FIELD_REFERENCE_DENSITY] = {"reference_density", "reference_density", ELEM_REAL, 1, TL, TL,
                                 MIRROR_COPY, NULL},
    /* the limited viscosity's reconstruction reads a neighbour's (pass 1
     * -> pass 2); both passes 1 use their own L at once */
    [FIELD_VELOCITY_GRADIENT] = {"velocity_gradient", "velocity_gradient", ELEM_FULLT, 1,
                                 USED_AV_LIMITED | USED_TENSOR_SMOOTHING, USED_AV_LIMITED,
                                 MIRROR_REFLECT, NULL},
    [FIELD_AV_ALPHA] = {"artificial_viscosity_alpha", "av_alpha", ELEM_REAL, 1, USED_AV_SWITCH,
                        USED_AV_SWITCH, MIRROR_COPY, "1"},
    /* d(div v)/dt, Cullen & Dehnen's shock indicator, from two steps */
    [FIELD_AV_DIVERGENCE] = {"velocity_divergence", "av_divergence", ELEM_REAL, 1,
                             USED_AV_CULLEN_DEHNEN, 0, MIRROR_NONE, NULL},
    /* kept apart so that the elastic part integrates on its own
     * (kernels/material.cl); pass 2 reads only the sum, deviatoric_stress */
    [FIELD_VISCOUS_STRESS] = {"viscous_stress", "viscous_stress", ELEM_SYMT, 1, USED_VISCOSITY, 0,
                              MIRROR_NONE, NULL},
    /* the kernel's ellipsoid, carried by integrate_drift with pass 1's L
     * (the reason velocity_gradient exists with it) */
    [FIELD_SMOOTHING_METRIC] = {"smoothing_metric", "smoothing_metric", ELEM_SYMT, 1,
                                USED_TENSOR_SMOOTHING, USED_TENSOR_SMOOTHING, MIRROR_REFLECT, "1"},
    /* read of a neighbour by the lane lists' build */
    [FIELD_SMOOTHING_REACH] = {"smoothing_reach", "smoothing_reach", ELEM_REAL, 1,
                               USED_TENSOR_SMOOTHING, USED_TENSOR_SMOOTHING, MIRROR_COPY, "1"},
    [FIELD_ACCELERATION] = {"acceleration", "acceleration", ELEM_VEC, 0, ALL, 0, MIRROR_NONE, NULL},
    [FIELD_ENERGY_RATE] = {"energy_rate", "energy_rate", ELEM_REAL, 0, ALL, 0, MIRROR_NONE, NULL},
    /* pass 2 rewrites it every step; kept as state (sorted, checkpointed)
     * because snapshots write only state: a snapshot a resumed run writes
     * before its first step then holds the interrupted step's values, not
     * zeros (tools/av_work_split.py reads it) */
    [FIELD_VISCOUS_HEATING] = {"artificial_viscosity_heating", "viscous_heating", ELEM_REAL, 1, ALL,
                               0, MIRROR_NONE, "W/kg"},
    [FIELD_HOURGLASS_POWER] = {"hourglass_power", "hourglass_power", ELEM_REAL, 0, TL, 0,
                               MIRROR_NONE, NULL},
    [FIELD_XSPH_VELOCITY] = {"xsph_velocity", "xsph_velocity", ELEM_VEC, 0, ALL, ALL,
                             MIRROR_REFLECT, NULL},
    /* written by the kick and read by the reduction only with walls */
    [FIELD_WALL_FORCE] = {"wall_force", "wall_force", ELEM_VEC, 0, USED_WALLS, 0, MIRROR_NONE,
                          NULL},
};

#undef ALL
#undef TL

unsigned solver_configuration(const struct solver *s)
{
    return USED_ALWAYS | (s->total_lagrangian ? USED_TOTAL_LAGRANGIAN : 0u) |
           (s->csph ? USED_CSPH : 0u) | (s->av_scheme == SPH_AV_LIMITED ? USED_AV_LIMITED : 0u) |
           (s->av_scheme == SPH_AV_SWITCH || s->av_scheme == SPH_AV_CULLEN_DEHNEN ? USED_AV_SWITCH
                                                                                  : 0u) |
           (s->av_scheme == SPH_AV_CULLEN_DEHNEN ? USED_AV_CULLEN_DEHNEN : 0u) |
           (s->artificial_stress ? USED_ARTIFICIAL_STRESS : 0u) |
           (s->wall_count > 0 ? USED_WALLS : 0u) | (s->viscosity ? USED_VISCOSITY : 0u) |
           (s->tensor_smoothing ? USED_TENSOR_SMOOTHING : 0u);
}

int solver_field_used(const struct solver *s, enum field f)
{
    return (field_table[f].used & solver_configuration(s)) != 0;
}

int solver_field_mirrored(const struct solver *s, enum field f)
{
    return (field_table[f].read_across & solver_configuration(s)) != 0;
}

/* Output columns derived from the fields (derive_columns). */
static const struct host_column derived_table[DERIVED_COUNT] = {
    [DERIVED_STRESS] = {"stress", "Pa (XX, YY, ZZ, XY, YZ, XZ)", 6, 0, NULL},
    [DERIVED_VON_MISES] = {"von_mises_stress", "Pa", 1, 0, NULL},
    [DERIVED_SMOOTHING_LENGTH] = {"smoothing_length", "m", 1, 0, NULL},
    [DERIVED_PART] = {"part", "bodies[].part", 1, 1, NULL},
};

/* Host components of an element: vectors padded to 3, symmetric tensors as
 * Tensor6; full tensors are not written. */
static int host_components(enum element_kind kind)
{
    static const int components[ELEM_COUNT] = {
        [ELEM_REAL] = 1, [ELEM_INT] = 1, [ELEM_VEC] = 3, [ELEM_SYMT] = 6, [ELEM_FULLT] = 0};
    return components[kind];
}

static double real_at(const struct solver *s, const unsigned char *element, int k)
{
    if (s->double_precision) {
        double v;
        memcpy(&v, element + k * sizeof v, sizeof v);
        return v;
    }
    float v;
    memcpy(&v, element + k * sizeof v, sizeof v);
    return v;
}

/* One device element into row `row` of a host column. The device's
 * symmetric tensor is xx, yy, zz, xy (, xz, yz in 3-D): kernels/common.cl. */
static void unpack_element(const struct solver *s, enum element_kind kind,
                           const unsigned char *element, struct host_column *col, int row)
{
    if (kind == ELEM_INT) {
        memcpy((int *)col->data + row, element, sizeof(int));
        return;
    }
    double *out = (double *)col->data + (size_t)row * col->components;
    if (kind == ELEM_REAL)
        out[0] = real_at(s, element, 0);
    else if (kind == ELEM_VEC)
        for (int a = 0; a < s->dim; ++a)
            out[a] = real_at(s, element, a);
    else if (kind == ELEM_SYMT) {
        for (int a = 0; a < 4; ++a)
            out[a] = real_at(s, element, a);
        if (s->dim == 3)
            out[4] = real_at(s, element, 5), out[5] = real_at(s, element, 4);
    }
}

/* Reads field f into its column (row_of_slot: each device slot's row, -1
 * for ghost and halo slots, which are skipped). */
static int read_column(struct solver *s, enum field f, const int *row_of_slot,
                       struct host_fields *o, struct host_column *col)
{
    const enum element_kind kind = field_table[f].kind;
    const size_t element = s->element_size[kind], n = (size_t)s->n;
    unsigned char *raw = CHECKED_CALLOC(element * n + 1, 1, "field read-back");
    col->data = CHECKED_CALLOC((size_t)o->n * col->components + 1,
                               col->is_int ? sizeof(int) : sizeof(double), "snapshot field");
    if (!raw || !col->data) {
        free(raw);
        return 1;
    }
    CL_CHECK(clEnqueueReadBuffer(s->dev->queue, s->field[f], CL_TRUE, 0, element * n, raw, 0, NULL,
                                 NULL));
    for (size_t k = 0; k < n; ++k)
        if (row_of_slot[k] >= 0)
            unpack_element(s, kind, raw + k * element, col, row_of_slot[k]);
    free(raw);
    /* gathered over several processes: each rank filled its own rows and
     * the others are zero, so the sum is every rank's column, exactly */
    const size_t values = (size_t)o->n * col->components;
    if (s->domain.active && !o->distributed && col->is_int)
        dist_sum_ints(col->data, values);
    else if (s->domain.active && !o->distributed)
        dist_sum(col->data, values);
    if (f == FIELD_ID) /* the scene index, not a rank's own numbering */
        for (int row = 0; row < o->n; ++row)
            ((int *)col->data)[row] = o->id ? o->id[row] : row;
    return 0;
}

static int compare_ints(const void *a, const void *b)
{
    const int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* Each device slot's row: its scene index when the rows are the whole
 * scene; when they are this rank's share, its place among the rank's
 * scene indices in ascending order (o->id). */
static int read_rows(struct solver *s, struct host_fields *o, int **row_of_slot)
{
    *row_of_slot = CHECKED_CALLOC((size_t)s->n + 1, sizeof(int), "field read-back");
    if (!*row_of_slot)
        return 1;
    int *rows = *row_of_slot;
    CL_CHECK(clEnqueueReadBuffer(s->dev->queue, s->field[FIELD_ID], CL_TRUE, 0,
                                 sizeof(cl_int) * (size_t)s->n, rows, 0, NULL, NULL));
    solver_domain_rows(s, rows, s->n);
    if (!o->distributed)
        return 0;
    /* (scene index, slot) pairs sorted by scene index */
    int *pairs = CHECKED_CALLOC(2 * (size_t)s->n + 1, sizeof(int), "field read-back");
    o->id = CHECKED_CALLOC((size_t)s->n + 1, sizeof(int), "snapshot ids");
    if (!pairs || !o->id) {
        free(pairs);
        return 1;
    }
    o->n = 0;
    for (int k = 0; k < s->n; ++k)
        if (rows[k] >= 0)
            pairs[2 * o->n] = rows[k], pairs[2 * o->n + 1] = k, ++o->n;
    qsort(pairs, (size_t)o->n, 2 * sizeof(int), compare_ints);
    for (int row = 0; row < o->n; ++row)
        o->id[row] = pairs[2 * row], rows[pairs[2 * row + 1]] = row;
    free(pairs);
    return 0;
}

/* The full stress sigma = S - p I and its von Mises equivalent
 * sqrt(3/2 S:S) from the deviatoric stress; each particle's h (graded
 * lattices: a level-l particle's is 2^l times the fine one) and part (its
 * flag bits, so that ParaView can colour by it). */
static int derive_columns(const struct solver *s, struct host_fields *o)
{
    for (int d = 0; d < DERIVED_COUNT; ++d) {
        struct host_column *col = &o->column[FIELD_COUNT + d];
        *col = derived_table[d];
        col->data =
            CHECKED_CALLOC((size_t)o->n * col->components + 1, sizeof(double), "snapshot field");
        if (!col->data)
            return 1;
    }
    const double *dev = HOST_REALS(o, FIELD_STRESS), *p = HOST_REALS(o, FIELD_PRESSURE);
    const int *flags = HOST_INTS(o, FIELD_FLAGS);
    double *stress = o->column[FIELD_COUNT + DERIVED_STRESS].data;
    double *von_mises = o->column[FIELD_COUNT + DERIVED_VON_MISES].data;
    double *h = o->column[FIELD_COUNT + DERIVED_SMOOTHING_LENGTH].data;
    int *part = o->column[FIELD_COUNT + DERIVED_PART].data;
    /* the total Lagrangian form measures the displacement from its
     * reference; the snapshot's is from the initial position */
    const double *offset = HOST_REALS(o, FIELD_REFERENCE_OFFSET);
    double *displacement = o->column[FIELD_DISPLACEMENT].data;
    for (int q = 0; offset && displacement && q < 3 * o->n; ++q)
        displacement[q] += offset[q];
    for (int q = 0; q < o->n; ++q) {
        const double *S = &dev[6 * q]; /* XX, YY, ZZ, XY, YZ, XZ */
        for (int a = 0; a < 6; ++a)
            stress[6 * q + a] = S[a] - (a < 3 ? p[q] : 0.0);
        von_mises[q] = sqrt(1.5 * (S[0] * S[0] + S[1] * S[1] + S[2] * S[2] +
                                   2.0 * (S[3] * S[3] + S[5] * S[5] + S[4] * S[4])));
        h[q] = s->run.h * (double)(1 << SPH_LEVEL_OF(flags[q]));
        part[q] = SPH_PART_OF(flags[q]);
    }
    return 0;
}

int solver_read_fields(struct solver *s, struct host_fields *o)
{
    memset(o, 0, sizeof *o);
    o->n = o->n_total = s->n_scene;
#ifdef SPH_PARALLEL_HDF5
    o->distributed = s->domain.active; /* written collectively (host/output.c) */
#endif
    int *row_of_slot = NULL;
    int failed = read_rows(s, o, &row_of_slot);
    for (int f = 0; f < FIELD_COUNT && !failed; ++f) {
        const struct field_info *info = &field_table[f];
        const int derived_input = f == FIELD_STRESS || f == FIELD_REFERENCE_OFFSET;
        if (!solver_field_used(s, (enum field)f) || (!info->units && !derived_input))
            continue;
        o->column[f] = (struct host_column){info->name, info->units, host_components(info->kind),
                                            info->kind == ELEM_INT, NULL};
        failed = read_column(s, (enum field)f, row_of_slot, o, &o->column[f]);
    }
    free(row_of_slot);
    failed = failed || derive_columns(s, o);
    if (o->distributed) /* every rank goes on to write, or none */
        failed = dist_any(failed);
    if (failed)
        host_fields_free(o);
    return failed;
}

void host_fields_free(struct host_fields *f)
{
    for (int k = 0; k < HOST_COLUMNS; ++k)
        free(f->column[k].data);
    free(f->id);
    memset(f, 0, sizeof *f);
}
