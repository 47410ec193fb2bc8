/* The device neighbour search against brute force: random points, lattice
 * points lying exactly on cell faces, and points moved after the sort (the
 * grid skin), in 2-D and 3-D, on the default OpenCL device. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "device.h"
#include "launch.h"
#include "scene.h"
#include "solver.h"

#define MAX_LIST 256

struct fixture {
    struct sph_device dev;
    struct sph_case c;
    struct sph_scene scene;
    struct solver s;
};

static unsigned rng_state = 12345u;
static double uniform(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return (rng_state >> 8) / 16777216.0;
}

static void make_case(struct sph_case *c, int dim)
{
    memset(c, 0, sizeof *c);
    snprintf(c->path, sizeof c->path, "test");
    snprintf(c->name, sizeof c->name, "neighbours");
    c->dimension = dim;
    c->thickness = 1.0;
    c->material_count = 1;
    c->materials[0] = (struct case_material){.name = "m",
                                             .density = 1000.0,
                                             .youngs_modulus = 1e9,
                                             .poisson_ratio = 0.3,
                                             .eos = SPH_EOS_LINEAR,
                                             .strength = SPH_STRENGTH_ELASTIC};
    c->numerics.dx = 1.0;
    c->numerics.kernel = SPH_KERNEL_WENDLAND_C2;
    c->numerics.h_over_dx = 1.2;
    c->numerics.cfl = 0.3;
    c->numerics.end_time = 1.0;
}

static void make_scene(struct sph_scene *s, const double *xyz, int n)
{
    memset(s, 0, sizeof *s);
    s->count = n;
    s->position = malloc(sizeof(double) * 3 * n);
    memcpy(s->position, xyz, sizeof(double) * 3 * n);
    s->velocity = calloc((size_t)3 * n, sizeof(double));
    s->mass = calloc((size_t)n, sizeof(double));
    s->density = calloc((size_t)n, sizeof(double));
    s->material = calloc((size_t)n, sizeof(int));
    s->flags = calloc((size_t)n, sizeof(int));
    for (int p = 0; p < n; ++p)
        s->mass[p] = s->density[p] = 1000.0;
}

static void setup(struct fixture *f, int dim, const double *xyz, int n)
{
    char error[512];
    make_case(&f->c, dim);
    make_scene(&f->scene, xyz, n);
    char options[256];
    solver_build_options(&f->c, options, sizeof options);
    if (device_open(NULL, 0, &f->dev, error, sizeof error) ||
        device_build(&f->dev, device_source_dir(), options, error, sizeof error) ||
        solver_create(&f->s, &f->dev, &f->c, &f->scene, error, sizeof error) ||
        solver_sort(&f->s, error, sizeof error))
        fail_msg("setup: %s", error);
}

static void teardown(struct fixture *f)
{
    solver_release(&f->s);
    device_close(&f->dev);
    scene_free(&f->scene);
}

static int compare_int(const void *a, const void *b)
{
    return (*(const int *)a > *(const int *)b) - (*(const int *)a < *(const int *)b);
}

/* Device positions (sorted order) as floats, and the ids of that order. */
static void read_positions(struct fixture *f, float *pos, int *id)
{
    const int w = f->c.dimension == 2 ? 2 : 4;
    CL_CHECK(clEnqueueReadBuffer(f->dev.queue, f->s.field[FIELD_POS], CL_TRUE, 0,
                                 sizeof(float) * w * f->s.n, pos, 0, NULL, NULL));
    CL_CHECK(clEnqueueReadBuffer(f->dev.queue, f->s.field[FIELD_ID], CL_TRUE, 0,
                                 sizeof(int) * f->s.n, id, 0, NULL, NULL));
}

/* Runs grid_neighbour_list and compares every list with brute force. */
static void compare_with_brute_force(struct fixture *f)
{
    const int n = f->s.n, w = f->c.dimension == 2 ? 2 : 4;
    const float radius = (float)f->s.run.support;
    cl_kernel k = NULL;
    const struct kernel_slot slot = {&k, "grid_neighbour_list", 0};
    solver_kernels(&f->s, &slot, 1, 1);
    cl_mem count = solver_create_buffer(&f->s, sizeof(int) * n);
    cl_mem list = solver_create_buffer(&f->s, sizeof(int) * n * MAX_LIST);
    const cl_int max_list = MAX_LIST, cn = n;
    SET_ARGS(&f->s, k, RAW("radius", sizeof radius, &radius), MEM("count", count),
             MEM("list", list), INT("max_list", max_list), INT("n", cn));
    solver_launch(&f->s, k, (size_t)n, 0);
    assert_false(cl_failed());
    int *counts = malloc(sizeof(int) * n), *lists = malloc(sizeof(int) * n * MAX_LIST);
    int *id = malloc(sizeof(int) * n), *expected = malloc(sizeof(int) * MAX_LIST);
    float *pos = malloc(sizeof(float) * w * n);
    CL_CHECK(clEnqueueReadBuffer(f->dev.queue, count, CL_TRUE, 0, sizeof(int) * n, counts, 0, NULL,
                                 NULL));
    CL_CHECK(clEnqueueReadBuffer(f->dev.queue, list, CL_TRUE, 0, sizeof(int) * n * MAX_LIST, lists,
                                 0, NULL, NULL));
    read_positions(f, pos, id);
    long pairs = 0;
    for (int i = 0; i < n; ++i) {
        int m = 0;
        for (int j = 0; j < n; ++j) {
            float r2 = 0;
            for (int d = 0; d < f->c.dimension; ++d) {
                const float dd = pos[i * w + d] - pos[j * w + d];
                r2 += dd * dd;
            }
            if (j != i && r2 < radius * radius && m < MAX_LIST)
                expected[m++] = id[j];
        }
        assert_int_equal(counts[i], m);
        qsort(expected, (size_t)m, sizeof(int), compare_int);
        qsort(&lists[i * MAX_LIST], (size_t)m, sizeof(int), compare_int);
        assert_memory_equal(expected, &lists[i * MAX_LIST], sizeof(int) * m);
        pairs += m;
    }
    assert_true(pairs > 4L * n); /* the sets are not trivially empty */
    free(counts), free(lists), free(id), free(expected), free(pos);
    clReleaseMemObject(count);
    clReleaseMemObject(list);
    solver_kernels(&f->s, &slot, 1, 0);
}

/* Moves every particle by up to 0.99 of half the skin without re-sorting. */
static void jiggle(struct fixture *f)
{
    const int n = f->s.n, w = f->c.dimension == 2 ? 2 : 4;
    float *pos = malloc(sizeof(float) * w * n);
    int *id = malloc(sizeof(int) * n);
    read_positions(f, pos, id);
    const double reach = 0.99 * 0.5 * f->s.skin * f->s.run.support / sqrt(f->c.dimension);
    for (int i = 0; i < n; ++i)
        for (int d = 0; d < f->c.dimension; ++d)
            pos[i * w + d] += (float)(reach * (2 * uniform() - 1));
    CL_CHECK(clEnqueueWriteBuffer(f->dev.queue, f->s.field[FIELD_POS], CL_TRUE, 0,
                                  sizeof(float) * w * n, pos, 0, NULL, NULL));
    free(pos), free(id);
}

static void random_points(double *xyz, int n, int dim, double size)
{
    for (int p = 0; p < n; ++p)
        for (int a = 0; a < 3; ++a)
            xyz[3 * p + a] = a < dim ? size * uniform() : 0.0;
}

/* Lattice of spacing cell/2 from the particles' minimum: every other plane
 * of points lies exactly on a cell face (the grid origin is min - cell). */
static int face_lattice(double *xyz, int dim, double cell, int per_axis)
{
    int n = 0;
    const int nz = dim == 3 ? per_axis : 1;
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < per_axis; ++j)
            for (int i = 0; i < per_axis; ++i, ++n) {
                xyz[3 * n] = i * 0.5 * cell;
                xyz[3 * n + 1] = j * 0.5 * cell;
                xyz[3 * n + 2] = dim == 3 ? k * 0.5 * cell : 0.0;
            }
    return n;
}

static void run_random(int dim, int n, double size)
{
    double *xyz = malloc(sizeof(double) * 3 * n);
    random_points(xyz, n, dim, size);
    struct fixture f;
    setup(&f, dim, xyz, n);
    compare_with_brute_force(&f);
    jiggle(&f);
    compare_with_brute_force(&f);
    teardown(&f);
    free(xyz);
}

static void run_faces(int dim, int per_axis)
{
    double *xyz = malloc(sizeof(double) * 3 * per_axis * per_axis * per_axis);
    /* support 2.4 (Wendland, h = 1.2), skin 0.2: cell 2.88 / SPH_GRID_SPLIT;
     * the lattice puts particles on the faces of those cells */
    const double cell = 2.4 * 1.2 / SPH_GRID_SPLIT;
    const int n = face_lattice(xyz, dim, cell, per_axis);
    struct fixture f;
    setup(&f, dim, xyz, n);
    assert_true(fabs(f.s.grid.cell_size - cell) < 1e-6);
    compare_with_brute_force(&f);
    teardown(&f);
    free(xyz);
}

/* The sort itself (kernels/grid.cl, a counting sort by cell, each cell
 * ordered by slot): keys in order and a permutation of the slots, for
 * counts from one key to a few thousand, spread over many cells (more than
 * one block of the prefix sum) and crowded into a few (long runs of one
 * cell for the per-cell insertion sort). */
static void test_sort_any_count(void **state)
{
    (void)state;
    const int counts[] = {1, 2, 3, 5, 64, 127, 1000, 1025};
    const double sizes[] = {100.0, 0.5}; /* m; cells of 2.88 m (make_case) */
    for (size_t c = 0; c < 2 * sizeof counts / sizeof counts[0]; ++c) {
        const int n = counts[c / 2];
        double *xyz = malloc(sizeof(double) * 3 * n);
        random_points(xyz, n, 3, sizes[c % 2]);
        struct fixture f;
        setup(&f, 3, xyz, n);
        cl_ulong *keys = malloc(sizeof(cl_ulong) * n);
        int *seen = calloc((size_t)n, sizeof(int));
        CL_CHECK(clEnqueueReadBuffer(f.dev.queue, f.s.sort_keys, CL_TRUE, 0, sizeof(cl_ulong) * n,
                                     keys, 0, NULL, NULL));
        for (int k = 0; k < n; ++k) {
            if (k > 0)
                assert_true(keys[k - 1] <= keys[k]);
            const int slot = (int)(keys[k] & 0xffffffffu);
            assert_true(slot >= 0 && slot < n);
            seen[slot]++;
        }
        for (int k = 0; k < n; ++k)
            assert_int_equal(seen[k], 1);
        free(seen);
        free(keys);
        teardown(&f);
        free(xyz);
    }
}

static void test_random_2d(void **state)
{
    (void)state, run_random(2, 3000, 60.0);
}
static void test_random_3d(void **state)
{
    (void)state, run_random(3, 3000, 14.0);
}
static void test_cell_faces_2d(void **state)
{
    (void)state, run_faces(2, 40);
}
static void test_cell_faces_3d(void **state)
{
    (void)state, run_faces(3, 14);
}

/* Arguments are bound by name (host/launch.c): a value the kernel does not
 * take, or one given for a particle field, is refused with the kernel and
 * the argument named; the right values bind. */
static void test_binding_by_name(void **state)
{
    (void)state;
    const double xyz[] = {0, 0, 0, 1e-3, 0, 0};
    struct fixture f;
    setup(&f, 2, xyz, 2);
    cl_kernel k = NULL;
    const struct kernel_slot slot = {&k, "health_pairs", 0};
    solver_kernels(&f.s, &slot, 1, 1);
    cl_mem records = f.s.gather_spare;
    struct real_arg dx;
    SET_ARGS(&f.s, k, real_value(&f.s, &dx, "dx", 1.0), MEM("records", records), INT("n", f.s.n));
    assert_false(cl_failed());
    SET_ARGS(&f.s, k, real_value(&f.s, &dx, "dx", 1.0), MEM("records", records), INT("n", f.s.n),
             INT("bogus", f.s.n));
    assert_non_null(strstr(cl_failure(), "kernel health_pairs: takes no argument `bogus`"));
    cl_failure_clear();
    SET_ARGS(&f.s, k, real_value(&f.s, &dx, "dx", 1.0), MEM("records", records), INT("n", f.s.n),
             MEM("flags", records));
    assert_non_null(strstr(cl_failure(), "given a value for the field or solver argument `flags`"));
    cl_failure_clear();
    SET_ARGS(&f.s, k, real_value(&f.s, &dx, "dx", 1.0), MEM("records", records), INT("n", f.s.n),
             MEM("run", records));
    assert_non_null(strstr(cl_failure(), "given a value for the field or solver argument `run`"));
    cl_failure_clear();
    SET_ARGS(&f.s, k, real_value(&f.s, &dx, "dx", 1.0), INT("n", f.s.n));
    assert_non_null(
        strstr(cl_failure(), "no field, solver value or given value for argument `records`"));
    cl_failure_clear();
    solver_kernels(&f.s, &slot, 1, 0);
    teardown(&f);
}

/* The field registry is consistent: names and kernel names unique; a
 * field read across is one that exists, and a ghost carries exactly those;
 * a snapshot writes only fields a host column can hold, all of them state
 * a checkpoint holds (not a step's scratch). */
static void test_field_registry(void **state)
{
    (void)state;
    for (int f = 0; f < FIELD_COUNT; ++f) {
        const struct field_info *a = &field_table[f];
        assert_non_null(a->name);
        assert_non_null(a->arg);
        assert_true(a->used != 0);
        assert_int_equal(a->read_across & ~a->used, 0);
        assert_int_equal(a->read_across != 0, a->mirror != MIRROR_NONE);
        if (a->units) {
            assert_true(a->kind != ELEM_FULLT);
            assert_true(a->persistent);
        }
        for (int g = 0; g < f; ++g) {
            assert_string_not_equal(a->name, field_table[g].name);
            assert_string_not_equal(a->arg, field_table[g].arg);
        }
    }
}

/* A snapshot's host copy (host/fields.c): rows in scene order whatever the
 * sort did, vectors padded to 3 components, the derived columns, and no
 * column for a field this configuration lacks. */
static void test_snapshot_columns(void **state)
{
    (void)state;
    enum { N = 40 };
    double xyz[3 * N];
    for (int k = 0; k < 3 * N; ++k)
        xyz[k] = 4.0 * uniform();
    struct fixture f;
    setup(&f, 3, xyz, N);
    struct host_fields h;
    assert_int_equal(solver_read_fields(&f.s, &h), 0);
    assert_int_equal(h.n, N);
    const double *pos = HOST_REALS(&h, FIELD_POS);
    const double *hsml = h.column[FIELD_COUNT + DERIVED_SMOOTHING_LENGTH].data;
    for (int q = 0; q < N; ++q) {
        assert_int_equal(HOST_INTS(&h, FIELD_ID)[q], q);
        for (int a = 0; a < 3; ++a)
            assert_float_equal(pos[3 * q + a], xyz[3 * q + a], 1e-6 * 4.0);
        assert_float_equal(hsml[q], f.s.run.h, 1e-12);
    }
    assert_int_equal(h.column[FIELD_POS].components, 3);
    assert_int_equal(h.column[FIELD_COUNT + DERIVED_STRESS].components, 6);
    assert_null(h.column[FIELD_AV_ALPHA].data);
    assert_null(h.column[FIELD_VELOCITY_GRADIENT].data);
    assert_null(h.column[FIELD_STRESS].units); /* read for the derived stress only */
    host_fields_free(&h);
    teardown(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sort_any_count), cmocka_unit_test(test_random_2d),
        cmocka_unit_test(test_random_3d),      cmocka_unit_test(test_cell_faces_2d),
        cmocka_unit_test(test_cell_faces_3d),  cmocka_unit_test(test_binding_by_name),
        cmocka_unit_test(test_field_registry), cmocka_unit_test(test_snapshot_columns),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
