/* One case over many processes (MPI): each rank owns the particles of one
 * box of space, a leaf of an orthogonal recursive bisection balanced by
 * particle count, and runs its own OpenCL device on them (DESIGN.md, "The
 * next shape"). Halos are ghost slots filled from the neighbouring ranks'
 * particles, exactly as the symmetry planes' mirror ghosts are filled from
 * a rank's own (host/ghost.c): the neighbour passes cannot tell them apart.
 *
 * At every re-sort (solver_sort) the reals are compacted, read back, and
 * those whose box changed are sent to their new owner (MPI_Alltoallv of
 * whole particle records: every persistent field of the registry); the
 * boxes are cut again when the largest share passes the mean by
 * DOMAIN_IMBALANCE; then each rank sends the particles within reach of
 * another rank's box to it, and those are the halo until the next sort.
 * Before each neighbour pass the fields the pass reads across (the
 * registry's read_across, as for mirrors) are packed on the device,
 * exchanged and unpacked into the halo slots (kernels/halo.cl).
 *
 * The rest of this file wraps the MPI calls, so that no other file calls
 * MPI (the parallel HDF5's header includes <mpi.h>, but output.c reaches
 * MPI-IO through dist_hdf5_collective); built without MPI they are the
 * one-process versions. */
#include "domain.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "checkpoint.h"
#include "launch.h"
#include "solver.h"

#ifdef SPH_MPI
#include <mpi.h>
#endif

/* ---- processes and collectives */

static int world_rank = 0, world_size = 1, mpi_started = 0;
#ifdef SPH_MPI
/* dist_sum_max: its operation, and the one element it reduces */
#define SUM_MAX_WIDTH 64
static MPI_Op sum_then_max = MPI_OP_NULL;
static MPI_Datatype sum_max_vector = MPI_DATATYPE_NULL;
#endif

void dist_start(int *argc, char ***argv)
{
#ifdef SPH_MPI
    /* Open MPI's singleton start needs its runtime daemons; a plain `sph`
     * is the serial program and does not start MPI at all */
    if (!getenv("OMPI_COMM_WORLD_SIZE") && !getenv("PMI_SIZE") && !getenv("PMIX_RANK"))
        return;
    MPI_Init(argc, argv);
    mpi_started = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &world_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &world_size);
#else
    (void)argc, (void)argv;
#endif
}

void dist_stop(void)
{
#ifdef SPH_MPI
    if (sum_then_max != MPI_OP_NULL)
        MPI_Op_free(&sum_then_max);
    if (sum_max_vector != MPI_DATATYPE_NULL)
        MPI_Type_free(&sum_max_vector);
    if (mpi_started)
        MPI_Finalize();
#endif
    mpi_started = 0;
}

int dist_rank(void)
{
    return world_rank;
}

int dist_size(void)
{
    return world_size;
}

int dist_local_rank(void)
{
    const char *names[] = {"OMPI_COMM_WORLD_LOCAL_RANK", "MPI_LOCALRANKID", "SLURM_LOCALID"};
    for (int k = 0; world_size > 1 && k < 3; ++k)
        if (getenv(names[k]))
            return atoi(getenv(names[k]));
    return world_size > 1 ? world_rank : 0;
}

void dist_abort(int code)
{
#ifdef SPH_MPI
    if (world_size > 1)
        MPI_Abort(MPI_COMM_WORLD, code);
#endif
    exit(code);
}

#ifdef SPH_MPI
static void all_reduce(void *v, size_t n, MPI_Datatype type, MPI_Op op)
{
    if (world_size == 1 || n == 0)
        return;
    /* in pieces below 2^31 elements (MPI's int counts) */
    const size_t piece = (size_t)1 << 30;
    int width = 0;
    MPI_Type_size(type, &width);
    for (size_t at = 0; at < n; at += piece) {
        const size_t count = n - at < piece ? n - at : piece;
        MPI_Allreduce(MPI_IN_PLACE, (char *)v + at * (size_t)width, (int)count, type, op,
                      MPI_COMM_WORLD);
    }
}
#define ALL_REDUCE(v, n, type, op) all_reduce((v), (n), (type), (op))
#else
#define ALL_REDUCE(v, n, type, op) ((void)(v), (void)(n))
#endif

void dist_sum(double *v, size_t n)
{
    ALL_REDUCE(v, n, MPI_DOUBLE, MPI_SUM);
}

void dist_max(double *v, size_t n)
{
    ALL_REDUCE(v, n, MPI_DOUBLE, MPI_MAX);
}

void dist_min(double *v, size_t n)
{
    ALL_REDUCE(v, n, MPI_DOUBLE, MPI_MIN);
}

void dist_sum_ints(int *v, size_t n)
{
    ALL_REDUCE(v, n, MPI_INT, MPI_SUM);
}

void dist_or_bytes(char *v, size_t n)
{
    ALL_REDUCE(v, n, MPI_UNSIGNED_CHAR, MPI_BOR);
}

#ifdef SPH_MPI
/* dist_sum_max's operation on whole vectors of SUM_MAX_WIDTH doubles (one
 * derived element each, so that MPI never hands it a piece, whose offsets
 * would move the split): the first sum_count add, the rest take the
 * maximum (a NaN wins, so that a bad value is never hidden). Every rank
 * reduces the same layout, so the split is one value for the whole job. */
static int sum_count;
static void sum_then_max_op(void *in, void *inout, int *len, MPI_Datatype *type)
{
    (void)type;
    for (int e = 0; e < *len; ++e) {
        const double *a = (const double *)in + (size_t)e * SUM_MAX_WIDTH;
        double *b = (double *)inout + (size_t)e * SUM_MAX_WIDTH;
        for (int k = 0; k < SUM_MAX_WIDTH; ++k)
            b[k] = k < sum_count ? a[k] + b[k] : a[k] > b[k] || isnan(a[k]) ? a[k] : b[k];
    }
}
#endif

void dist_sum_max(double *sums, int n_sums, double *maxima, int n_maxima)
{
#ifdef SPH_MPI
    if (world_size == 1)
        return;
    double v[SUM_MAX_WIDTH] = {0};
    if (n_sums + n_maxima > SUM_MAX_WIDTH)
        abort(); /* a caller's layout, fixed at compile time */
    memcpy(v, sums, sizeof(double) * (size_t)n_sums);
    memcpy(v + n_sums, maxima, sizeof(double) * (size_t)n_maxima);
    if (sum_then_max == MPI_OP_NULL) {
        MPI_Op_create(sum_then_max_op, 1, &sum_then_max);
        MPI_Type_contiguous(SUM_MAX_WIDTH, MPI_DOUBLE, &sum_max_vector);
        MPI_Type_commit(&sum_max_vector);
    }
    sum_count = n_sums;
    MPI_Allreduce(MPI_IN_PLACE, v, 1, sum_max_vector, sum_then_max, MPI_COMM_WORLD);
    memcpy(sums, v, sizeof(double) * (size_t)n_sums);
    memcpy(maxima, v + n_sums, sizeof(double) * (size_t)n_maxima);
#else
    (void)sums, (void)n_sums, (void)maxima, (void)n_maxima;
#endif
}

int dist_any(int flag)
{
    int v = flag != 0;
    ALL_REDUCE(&v, 1, MPI_INT, MPI_MAX);
    return v;
}

int dist_bcast_int(int value)
{
#ifdef SPH_MPI
    if (world_size > 1)
        MPI_Bcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD);
#endif
    return value;
}

int dist_agree(int failed, char *error, size_t size)
{
    if (world_size == 1)
        return failed;
#ifdef SPH_MPI
    int first = failed ? world_rank : world_size;
    MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (first == world_size)
        return 0;
    char text[SPH_ERROR_MAX];
    snprintf(text, sizeof text, "%s", world_rank == first ? error : "");
    MPI_Bcast(text, (int)sizeof text, MPI_CHAR, first, MPI_COMM_WORLD);
    snprintf(error, size, "rank %d of %d: %s", first, world_size, text);
#else
    (void)error, (void)size;
#endif
    return 1;
}

int dist_exchange(const void *send, const int *send_bytes, void **recv, int *recv_bytes)
{
    *recv = NULL;
#ifdef SPH_MPI
    const int n = world_size;
    int *send_at = calloc((size_t)n, sizeof(int)), *recv_at = calloc((size_t)n, sizeof(int));
    MPI_Alltoall(send_bytes, 1, MPI_INT, recv_bytes, 1, MPI_INT, MPI_COMM_WORLD);
    size_t total = 0;
    for (int r = 0; r < n; ++r) {
        if (send_at && r > 0)
            send_at[r] = send_at[r - 1] + send_bytes[r - 1];
        if (recv_at && r > 0)
            recv_at[r] = recv_at[r - 1] + recv_bytes[r - 1];
        total += (size_t)recv_bytes[r];
    }
    *recv = malloc(total + 1);
    int failed = !send_at || !recv_at || !*recv;
    MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (!failed)
        MPI_Alltoallv(send, send_bytes, send_at, MPI_BYTE, *recv, recv_bytes, recv_at, MPI_BYTE,
                      MPI_COMM_WORLD);
    free(send_at), free(recv_at);
    return failed;
#else /* one process never exchanges (its domain is not active) */
    (void)send, (void)send_bytes, (void)recv_bytes;
    return 1;
#endif
}

void dist_exchange_known(const void *send, const int *send_bytes, void *recv, const int *recv_bytes)
{
#ifdef SPH_MPI
    static MPI_Request *requests; /* two per rank, kept for the process */
    if (!requests && !(requests = malloc(2 * sizeof(MPI_Request) * (size_t)world_size))) {
        fprintf(stderr, "sph: rank %d: out of host memory for MPI requests\n", world_rank);
        dist_abort(2);
    }
    int count = 0;
    size_t at = 0;
    for (int r = 0; r < world_size; at += (size_t)recv_bytes[r++])
        if (recv_bytes[r] > 0)
            MPI_Irecv((char *)recv + at, recv_bytes[r], MPI_BYTE, r, 17, MPI_COMM_WORLD,
                      &requests[count++]);
    at = 0;
    for (int r = 0; r < world_size; at += (size_t)send_bytes[r++])
        if (send_bytes[r] > 0)
            MPI_Isend((const char *)send + at, send_bytes[r], MPI_BYTE, r, 17, MPI_COMM_WORLD,
                      &requests[count++]);
    MPI_Waitall(count, requests, MPI_STATUSES_IGNORE);
#else /* one process has no halo: never called */
    (void)send, (void)send_bytes, (void)recv, (void)recv_bytes;
#endif
}

#ifdef SPH_PARALLEL_HDF5
int dist_hdf5_collective(hid_t file_access, hid_t transfer)
{
    return H5Pset_fapl_mpio(file_access, MPI_COMM_WORLD, MPI_INFO_NULL) < 0 ||
           H5Pset_dxpl_mpio(transfer, H5FD_MPIO_COLLECTIVE) < 0;
}
#endif

int dist_allgather(const double *mine, int count, double **all, int *total)
{
    *all = NULL;
#ifdef SPH_MPI
    const int n = world_size;
    int *counts = calloc((size_t)n, sizeof(int)), *at = calloc((size_t)n, sizeof(int));
    int failed = !counts || !at;
    if (!failed) {
        MPI_Allgather(&count, 1, MPI_INT, counts, 1, MPI_INT, MPI_COMM_WORLD);
        *total = 0;
        for (int r = 0; r < n; ++r)
            at[r] = *total, *total += counts[r];
        *all = malloc(sizeof(double) * (size_t)*total + 1);
        failed = !*all;
    }
    MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (!failed)
        MPI_Allgatherv(mine, count, MPI_DOUBLE, *all, counts, at, MPI_DOUBLE, MPI_COMM_WORLD);
    free(counts), free(at);
    return failed;
#else /* one process never re-cuts (its domain is not active) */
    (void)mine, (void)count, (void)total;
    return 1;
#endif
}

/* ---- the domains: an orthogonal recursive bisection */

static int compare_doubles(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The gap between distinct values nearest to index k of sorted `values`:
 * a cut never falls on a lattice plane, where the device's rounding of the
 * coordinates would decide the side. */
static double cut_near(const double *values, long n, long k)
{
    long up = k, down = k;
    while (up < n && values[up] == values[k - 1])
        ++up;
    while (down > 1 && values[down - 2] == values[down - 1])
        --down;
    if (up < n && (up - k <= k - down || down <= 1))
        return 0.5 * (values[up - 1] + values[up]);
    return down > 1 ? 0.5 * (values[down - 2] + values[down - 1]) : -HUGE_VAL;
}

/* Where the n points `pts` (indices into xyz, 3 per point) split at the
 * share k / n along `axis`: the nearest gap (cut_near), -inf or +inf at
 * the ends. scratch holds n doubles. */
static double share_cut(const double *xyz, const int *pts, int n, long k, int axis, double *scratch)
{
    for (int q = 0; q < n; ++q)
        scratch[q] = xyz[3 * pts[q] + axis];
    qsort(scratch, (size_t)n, sizeof(double), compare_doubles);
    return k <= 0 ? -HUGE_VAL : k >= n ? HUGE_VAL : cut_near(scratch, n, k);
}

/* Splits `count` ranks from `first` over the n points `pts` with halo
 * widths `reach` (per point, m): the first count / 2 ranks take the points
 * below a cut at their share, the rest those above it, and each half is
 * split again the same way. The cut goes across the axis whose cut the
 * fewest points reach (the halo it makes; ties: the lowest axis), which on
 * a uniform body is its longest side. Nodes are numbered in preorder from
 * *next. Returns the subtree: a node, or -1 - rank for one rank. */
static int bisect(struct domain *d, const double *xyz, const double *reach, int *pts, int n,
                  double *scratch, int first, int count, int dim, int *next)
{
    if (count == 1)
        return -1 - first;
    const int node = (*next)++, left = count / 2;
    const long k = (long)n * left / count;
    long fewest = -1;
    for (int a = 0; a < dim; ++a) {
        const double at = share_cut(xyz, pts, n, k, a, scratch);
        if (a == 0) /* kept only when no axis can split these points */
            d->split_axis[node] = 0, d->split_at[node] = at;
        /* an axis with no gap near the share (a body one plane thick
         * along it) cannot split these points: its cut would be at
         * infinity, with no halo and every point on one side */
        if (!isfinite(at))
            continue;
        long halo = 0;
        for (int q = 0; q < n; ++q)
            halo += fabs(xyz[3 * pts[q] + a] - at) < reach[pts[q]];
        if (fewest < 0 || halo < fewest)
            fewest = halo, d->split_axis[node] = a, d->split_at[node] = at;
    }
    const int axis = d->split_axis[node];
    const double cut = d->split_at[node];
    int below = 0;
    for (int q = 0; q < n; ++q)
        if (xyz[3 * pts[q] + axis] < cut) {
            const int t = pts[q];
            pts[q] = pts[below], pts[below++] = t;
        }
    d->child[2 * node] = bisect(d, xyz, reach, pts, below, scratch, first, left, dim, next);
    d->child[2 * node + 1] = bisect(d, xyz, reach, pts + below, n - below, scratch, first + left,
                                    count - left, dim, next);
    return node;
}

/* The tree of the domains from every particle's position (3 per point) and
 * halo width (every rank holds the same points, so every rank builds the
 * same tree). Non-zero when out of host memory. */
static int cut_domains(struct domain *d, const double *xyz, const double *reach, int n, int dim)
{
    int *pts = malloc(sizeof(int) * (size_t)n + 1);
    double *scratch = malloc(sizeof(double) * (size_t)n + 1);
    if (pts && scratch) {
        for (int q = 0; q < n; ++q)
            pts[q] = q;
        int next = 0;
        bisect(d, xyz, reach, pts, n, scratch, 0, d->size, dim, &next);
    }
    free(scratch);
    const int failed = !pts || !scratch;
    free(pts);
    return failed;
}

static int owner_of(const struct domain *d, const double *x)
{
    int c = 0;
    while (c >= 0)
        c = d->child[2 * c + (x[d->split_axis[c]] >= d->split_at[c])];
    return -1 - c;
}

/* Marks near[r] for each rank r whose domain lies within `width` of x
 * along each cut on the way down (a box distance, per axis). */
static void ranks_near(const struct domain *d, int c, const double *x, double width, char *near)
{
    if (c < 0) {
        near[-1 - c] = 1;
        return;
    }
    const double along = x[d->split_axis[c]], cut = d->split_at[c];
    if (along - width < cut)
        ranks_near(d, d->child[2 * c], x, width, near);
    if (along + width > cut)
        ranks_near(d, d->child[2 * c + 1], x, width, near);
}

/* How far a particle with these flags reaches into other domains: a
 * support (1 + skin), times the graded lattices' reach (solver_reach_scale,
 * the mirrors' rule). */
static double halo_width(const struct solver *s, int flags)
{
    return s->run.support * (1.0 + s->skin) * solver_reach_scale(s, flags);
}

/* The ranks (near[r], one per rank) within reach of a particle at x with
 * these flags. */
static void reached_by(const struct solver *s, const double *x, int flags, char *near)
{
    memset(near, 0, (size_t)s->domain.size);
    ranks_near(&s->domain, 0, x, halo_width(s, flags), near);
}

static int copy_particle(const struct sph_scene *from, int p, struct sph_scene *to, int q)
{
    memcpy(&to->position[3 * q], &from->position[3 * p], 3 * sizeof(double));
    memcpy(&to->velocity[3 * q], &from->velocity[3 * p], 3 * sizeof(double));
    to->mass[q] = from->mass[p];
    to->density[q] = from->density[p];
    to->material[q] = from->material[p];
    to->flags[q] = from->flags[p];
    return q + 1;
}

/* This rank's particles first, then those within its halo (counted for the
 * mirror ghosts' room, not uploaded). */
static int local_scene(struct solver *s, const struct sph_scene *scene, struct sph_scene *local,
                       int *own)
{
    struct domain *d = &s->domain;
    const size_t n = (size_t)scene->count + 1;
    *local = *scene;
    local->position = calloc(3 * n, sizeof(double));
    local->velocity = calloc(3 * n, sizeof(double));
    local->mass = calloc(n, sizeof(double));
    local->density = calloc(n, sizeof(double));
    local->material = calloc(n, sizeof(int));
    local->flags = calloc(n, sizeof(int));
    d->global_id = calloc(n, sizeof(int));
    if (!local->position || !local->velocity || !local->mass || !local->density ||
        !local->material || !local->flags || !d->global_id)
        return 1;
    char *near = malloc((size_t)d->size);
    if (!near)
        return 1;
    int count = 0;
    for (int p = 0; p < scene->count; ++p)
        if (owner_of(d, &scene->position[3 * p]) == d->rank) {
            d->global_id[count] = p;
            count = copy_particle(scene, p, local, count);
        }
    *own = count;
    for (int p = 0; p < scene->count; ++p) {
        const double *x = &scene->position[3 * p];
        reached_by(s, x, scene->flags[p], near);
        if (owner_of(d, x) != d->rank && near[d->rank])
            count = copy_particle(scene, p, local, count);
    }
    local->count = count;
    free(near);
    return 0;
}

int solver_domain_setup(struct solver *s, const struct sph_scene *scene, struct sph_scene *local,
                        char *error, size_t error_size)
{
    struct domain *d = &s->domain;
    memset(local, 0, sizeof *local);
    d->active = 1;
    d->rank = dist_rank();
    d->size = dist_size();
    d->n_scene = scene->count;
    d->split_axis = calloc((size_t)d->size, sizeof(int));
    d->split_at = calloc((size_t)d->size, sizeof(double));
    d->child = calloc(2 * (size_t)d->size, sizeof(int));
    d->send_count = calloc((size_t)d->size, sizeof(int));
    d->recv_count = calloc((size_t)d->size, sizeof(int));
    d->send_bytes = calloc((size_t)d->size, sizeof(int));
    d->recv_bytes = calloc((size_t)d->size, sizeof(int));
    double *reach = malloc(sizeof(double) * (size_t)scene->count + 1);
    for (int p = 0; reach && p < scene->count; ++p)
        reach[p] = halo_width(s, scene->flags[p]);
    int own = 0;
    int failed = !d->split_axis || !d->split_at || !d->child || !d->send_count || !d->recv_count ||
                 !d->send_bytes || !d->recv_bytes || !reach;
    failed = failed || cut_domains(d, scene->position, reach, scene->count, s->dim) ||
             local_scene(s, scene, local, &own);
    free(reach);
    if (failed)
        return snprintf(error, error_size, "out of host memory for the domain of rank %d",
                        d->rank) > 0;
    d->halo_capacity = 2 * (local->count - own) + 256;
    d->initial_reals = own; /* solver_domain_size: after the mirrors' setup */
    return 0;
}

void solver_domain_size(struct solver *s)
{
    struct domain *d = &s->domain;
    /* room for the share to grow up to the imbalance that cuts the boxes
     * again, and for the halos to thicken */
    const int reals = (int)((1.0 + 2.0 * DOMAIN_IMBALANCE) * d->n_scene / d->size) + 256;
    s->n_real = s->n = d->initial_reals;
    s->capacity = reals + d->halo_capacity + s->ghosts.capacity;
}

/* ---- particle records: every persistent field of the registry */

struct records {
    int fields[FIELD_COUNT], field_count;
    size_t bytes; /* one record: the scene index, then each field's element */
    int count;    /* records held */
    unsigned char *data;
};

static void record_layout(const struct solver *s, struct records *r)
{
    r->field_count = 0;
    r->bytes = sizeof(int);
    for (int f = 0; f < FIELD_COUNT; ++f)
        if (field_table[f].persistent && solver_field_used(s, (enum field)f)) {
            r->fields[r->field_count++] = f;
            r->bytes += s->element_size[field_table[f].kind];
        }
}

/* The reals (slots 0 .. n_real - 1 after the compaction) as records. */
static int read_records(struct solver *s, struct records *r)
{
    const size_t n = (size_t)s->n_real;
    r->data = calloc(n * r->bytes + 1, 1);
    size_t largest = 0;
    for (int k = 0; k < r->field_count; ++k)
        largest = fmax(largest, s->element_size[field_table[r->fields[k]].kind]);
    unsigned char *raw = calloc(n * largest + 1, 1);
    if (!r->data || !raw) {
        free(raw);
        return 1;
    }
    r->count = s->n_real;
    for (size_t p = 0; p < n; ++p)
        memcpy(r->data + p * r->bytes, &s->domain.global_id[p], sizeof(int));
    size_t at = sizeof(int);
    for (int k = 0; k < r->field_count; ++k) {
        const size_t e = s->element_size[field_table[r->fields[k]].kind];
        if (n > 0)
            CL_CHECK(clEnqueueReadBuffer(s->dev->queue, s->field[r->fields[k]], CL_TRUE, 0, n * e,
                                         raw, 0, NULL, NULL));
        for (size_t p = 0; p < n; ++p)
            memcpy(r->data + p * r->bytes + at, raw + p * e, e);
        at += e;
    }
    free(raw);
    return 0;
}

/* A record's position (3 coordinates; z = 0 in 2-D). */
static void record_position(const struct solver *s, const unsigned char *record, double x[3])
{
    const unsigned char *at = record + sizeof(int); /* FIELD_POS: the registry's first */
    x[2] = 0;
    for (int a = 0; a < s->dim && a < 3; ++a) { /* the bound for the compiler: dim is 2 or 3 */
        if (s->double_precision) {
            memcpy(&x[a], at + (size_t)a * sizeof(double), sizeof(double));
        } else {
            float v;
            memcpy(&v, at + (size_t)a * sizeof v, sizeof v);
            x[a] = v;
        }
    }
}

static int record_flags(const struct solver *s, const struct records *r,
                        const unsigned char *record)
{
    size_t at = sizeof(int);
    for (int k = 0; k < r->field_count && r->fields[k] != FIELD_FLAGS; ++k)
        at += s->element_size[field_table[r->fields[k]].kind];
    int flags;
    memcpy(&flags, record + at, sizeof flags);
    return flags;
}

/* Records grouped by destination rank (rank order) and sent; `dest` per
 * record, -1 for none. The received records follow in rank order. */
static int send_records(const struct domain *d, const struct records *from, const int *dest,
                        struct records *to, int *received)
{
    int *bytes = calloc((size_t)d->size, sizeof(int)), *back = calloc((size_t)d->size, sizeof(int));
    size_t *at = calloc((size_t)d->size + 1, sizeof(size_t));
    size_t total = 0;
    for (int p = 0; p < from->count; ++p)
        total += dest[p] >= 0;
    unsigned char *out = calloc(total * from->bytes + 1, 1);
    int failed = !bytes || !back || !at || !out;
    if (!failed) {
        for (int p = 0; p < from->count; ++p) /* grouped by rank, in order within each */
            if (dest[p] >= 0)
                bytes[dest[p]] += (int)from->bytes;
        for (int r = 1; r < d->size; ++r)
            at[r] = at[r - 1] + (size_t)bytes[r - 1];
        for (int p = 0; p < from->count; ++p)
            if (dest[p] >= 0) {
                memcpy(out + at[dest[p]], from->data + (size_t)p * from->bytes, from->bytes);
                at[dest[p]] += from->bytes;
            }
    }
    void *in = NULL;
    failed = dist_exchange(out, bytes, &in, back) || failed;
    *to = *from;
    to->data = in;
    to->count = 0;
    for (int r = 0; r < d->size && !failed; ++r) {
        to->count += back[r] / (int)from->bytes;
        if (received)
            received[r] = back[r] / (int)from->bytes;
    }
    free(bytes), free(back), free(at), free(out);
    return failed;
}

/* Writes the new reals and halos into the field buffers (slots = local
 * ids); a halo keeps the flag bits a mirror keeps (ghost.c). Each buffer
 * is written whole, zeros after the halo: oclgrind keeps only the extent of
 * a buffer's last host write as initialised (host/state.c). */
static void write_records(struct solver *s, const struct records *reals, const struct records *halo)
{
    const int n = reals->count + halo->count;
    size_t at = sizeof(int);
    for (int k = 0; k < reals->field_count; ++k) {
        const int f = reals->fields[k];
        const size_t e = s->element_size[field_table[f].kind];
        unsigned char *raw = calloc((size_t)s->capacity * e + 1, 1);
        if (!raw)
            return;
        for (int p = 0; p < n; ++p) {
            const struct records *r = p < reals->count ? reals : halo;
            const int q = p < reals->count ? p : p - reals->count;
            memcpy(raw + (size_t)p * e, r->data + (size_t)q * r->bytes + at, e);
            if (f == FIELD_ID)
                memcpy(raw + (size_t)p * e, &p, sizeof p);
            if (f == FIELD_FLAGS && p >= reals->count) {
                int flags;
                memcpy(&flags, raw + (size_t)p * e, sizeof flags);
                flags = (flags & SPH_GHOST_KEEP_FLAGS) | SPH_FLAG_GHOST;
                memcpy(raw + (size_t)p * e, &flags, sizeof flags);
            }
        }
        CL_CHECK(clEnqueueWriteBuffer(s->dev->queue, s->field[f], CL_TRUE, 0,
                                      (size_t)s->capacity * e, raw, 0, NULL, NULL));
        free(raw);
        at += e;
    }
}

/* The reals this rank keeps, then those it received. */
static int merge_records(const struct records *kept_from, const int *dest, int rank,
                         const struct records *received, struct records *out)
{
    *out = *kept_from;
    out->count = 0;
    for (int p = 0; p < kept_from->count; ++p)
        out->count += dest[p] == rank;
    out->count += received->count;
    out->data = malloc((size_t)out->count * out->bytes + 1);
    if (!out->data)
        return 1;
    int q = 0;
    for (int p = 0; p < kept_from->count; ++p)
        if (dest[p] == rank)
            memcpy(out->data + (size_t)q++ * out->bytes, kept_from->data + (size_t)p * out->bytes,
                   out->bytes);
    memcpy(out->data + (size_t)q * out->bytes, received->data,
           (size_t)received->count * out->bytes);
    return 0;
}

/* Cuts the domains again when the shares have drifted apart: every rank's
 * positions, gathered and bisected as at the start. */
static int rebalance(struct solver *s, const struct records *r)
{
    struct domain *d = &s->domain;
    double share[2] = {r->count, r->count};
    dist_max(&share[0], 1);
    dist_sum(&share[1], 1);
    if (share[0] <= (1.0 + DOMAIN_IMBALANCE) * share[1] / d->size)
        return 0;
    /* positions, then halo widths */
    double *mine = malloc(3 * sizeof(double) * (size_t)r->count + 1), *all = NULL;
    double *width = malloc(sizeof(double) * (size_t)r->count + 1), *widths = NULL;
    int total = 0, n = 0, failed = !mine || !width;
    for (int p = 0; !failed && p < r->count; ++p) {
        const unsigned char *rec = r->data + (size_t)p * r->bytes;
        record_position(s, rec, &mine[3 * p]);
        width[p] = halo_width(s, record_flags(s, r, rec));
    }
    failed = dist_allgather(mine, failed ? 0 : 3 * r->count, &all, &total) || failed;
    failed = dist_allgather(width, failed ? 0 : r->count, &widths, &n) || failed;
    failed = failed || cut_domains(d, all, widths, n, s->dim);
    if (!failed)
        ++d->rebalances;
    free(mine), free(all), free(width), free(widths);
    return failed;
}

/* The ranks other than this one real p reaches (near: one per rank). */
static void halo_targets(const struct solver *s, const struct records *reals, int p, char *near)
{
    const unsigned char *rec = reals->data + (size_t)p * reals->bytes;
    double x[3];
    record_position(s, rec, x);
    reached_by(s, x, record_flags(s, reals, rec), near);
    near[s->domain.rank] = 0;
}

/* Halo send lists: each real within reach of another rank's domain goes to
 * that rank (a particle may go to several), grouped by rank; *send_ids
 * holds their local ids in the same order (ascending within each rank's
 * group). Received halos into `halo`. */
static int halo_records(struct solver *s, const struct records *reals, struct records *halo,
                        int **send_ids)
{
    struct domain *d = &s->domain;
    char *near = malloc((size_t)d->size);
    int *at = calloc((size_t)d->size + 1, sizeof(int)), total = 0;
    memset(d->send_count, 0, sizeof(int) * (size_t)d->size);
    for (int p = 0; near && at && p < reals->count; ++p) {
        halo_targets(s, reals, p, near);
        for (int r = 0; r < d->size; ++r)
            if (near[r])
                ++total, ++d->send_count[r];
    }
    struct records out = *reals;
    out.count = total;
    out.data = malloc((size_t)total * reals->bytes + 1);
    int *dest = calloc((size_t)total + 1, sizeof(int));
    *send_ids = malloc(sizeof(int) * (size_t)total + 1);
    int failed = !near || !at || !out.data || !dest || !*send_ids;
    for (int r = 1; !failed && r < d->size; ++r)
        at[r] = at[r - 1] + d->send_count[r - 1];
    for (int p = 0; !failed && p < reals->count; ++p) {
        halo_targets(s, reals, p, near);
        for (int r = 0; r < d->size; ++r) {
            if (!near[r])
                continue;
            const int q = at[r]++;
            memcpy(out.data + (size_t)q * reals->bytes, reals->data + (size_t)p * reals->bytes,
                   reals->bytes);
            (*send_ids)[q] = p;
            dest[q] = r;
        }
    }
    free(near), free(at);
    if (failed) /* every rank still takes part in the exchange */
        out.count = 0;
    failed = send_records(d, &out, dest, halo, d->recv_count) || failed;
    d->send_total = total;
    free(dest);
    free(out.data);
    return failed;
}

/* The fields of one refresh: those listed (all when NULL) that the
 * neighbour passes read across, their words per element, the record's. */
struct halo_record {
    int field[FIELD_COUNT], words[FIELD_COUNT], count, record_words;
};

static void halo_record_of(const struct solver *s, const enum field *fields, int count,
                           struct halo_record *h)
{
    h->count = h->record_words = 0;
    for (int k = 0; k < (fields ? count : FIELD_COUNT); ++k) {
        const int f = fields ? (int)fields[k] : k;
        if (!solver_field_mirrored(s, (enum field)f))
            continue;
        h->words[h->count] = (int)(s->element_size[field_table[f].kind] / 4);
        h->record_words += h->words[h->count];
        h->field[h->count++] = f;
    }
}

/* The halo's device side: the send ids and the staging buffers. */
static void halo_buffers(struct solver *s, const int *send_ids)
{
    struct domain *d = &s->domain;
    solver_release_buffer(&d->send_ids);
    d->send_ids = solver_create_buffer(s, sizeof(cl_int) * ((size_t)d->send_total + 1));
    if (d->send_total > 0)
        CL_CHECK(clEnqueueWriteBuffer(s->dev->queue, d->send_ids, CL_TRUE, 0,
                                      sizeof(cl_int) * (size_t)d->send_total, send_ids, 0, NULL,
                                      NULL));
    struct halo_record every; /* the largest refresh: every field read across */
    halo_record_of(s, NULL, 0, &every);
    const size_t words = (size_t)every.record_words *
                         (size_t)(d->send_total > d->halo_count ? d->send_total : d->halo_count);
    if (words <= d->staging_words && d->staging_out)
        return;
    d->staging_words = words + words / 4 + 64;
    solver_release_buffer(&d->staging_out);
    solver_release_buffer(&d->staging_in);
    d->staging_out = solver_create_buffer(s, 4 * d->staging_words);
    d->staging_in = solver_create_buffer(s, 4 * d->staging_words);
    /* the host's side of the exchange, kept between steps */
    free(d->host_out), free(d->host_in);
    d->host_out = CHECKED_CALLOC(d->staging_words, 4, "the halo exchange");
    d->host_in = CHECKED_CALLOC(d->staging_words, 4, "the halo exchange");
}

int solver_domain_exchange(struct solver *s, char *error, size_t error_size)
{
    struct domain *d = &s->domain;
    solver_compact(s); /* reals in slots 0 .. n_real - 1, slot = local id */
    struct records reals = {0}, received = {0}, merged = {0}, halo = {0};
    record_layout(s, &reals);
    int failed = read_records(s, &reals);
    failed = rebalance(s, &reals) || failed;
    int *dest = calloc((size_t)reals.count + 1, sizeof(int)), *send_ids = NULL;
    long leaving = 0;
    for (int p = 0; dest && p < reals.count; ++p) {
        double x[3];
        record_position(s, reals.data + (size_t)p * reals.bytes, x);
        dest[p] = owner_of(d, x);
        leaving += dest[p] != d->rank;
    }
    failed = !dest || failed;
    /* the particles that leave; failed ranks send nothing but take part */
    int *away = calloc((size_t)reals.count + 1, sizeof(int));
    for (int p = 0; away && p < reals.count; ++p)
        away[p] = failed || dest[p] == d->rank ? -1 : dest[p];
    failed = !away || send_records(d, &reals, away, &received, NULL) || failed;
    failed = failed || merge_records(&reals, dest, d->rank, &received, &merged);
    double moved = (double)leaving;
    dist_sum(&moved, 1);
    d->migrated += (long)moved;
    if (failed)
        merged.count = 0; /* the halo exchange still runs, empty */
    failed = halo_records(s, &merged, &halo, &send_ids) || failed;
    const int room = s->capacity - s->ghosts.capacity;
    if (!failed && merged.count + halo.count > room)
        failed = snprintf(error, error_size,
                          "its %d particles and %d halo particles outgrew the %d slots made for "
                          "them (the shares drifted apart faster than the domains were re-cut)",
                          merged.count, halo.count, room) > 0;
    else if (failed)
        snprintf(error, error_size, "out of host memory exchanging particles");
    if (!failed) {
        write_records(s, &merged, &halo);
        free(d->global_id);
        d->global_id = malloc(sizeof(int) * (size_t)merged.count + 1);
        for (int p = 0; d->global_id && p < merged.count; ++p)
            memcpy(&d->global_id[p], merged.data + (size_t)p * merged.bytes, sizeof(int));
        s->n_real = merged.count;
        d->halo_count = halo.count;
        s->n = s->n_real + d->halo_count;
        halo_buffers(s, send_ids);
    }
    free(dest), free(away), free(send_ids);
    free(reals.data), free(received.data), free(merged.data), free(halo.data);
    return failed;
}

/* ---- halo refresh */

static void pack_halo(struct solver *s, const struct halo_record *h)
{
    struct domain *d = &s->domain;
    for (int k = 0, offset = 0; k < h->count && d->send_total > 0; offset += h->words[k++]) {
        SET_ARGS(s, d->pack, MEM("source", s->field[h->field[k]]), INT("words", h->words[k]),
                 INT("record_words", h->record_words), INT("offset", offset),
                 MEM("send_ids", d->send_ids), MEM("index_of_id", s->ghosts.index_of_id),
                 MEM("staging", d->staging_out), INT("count", d->send_total));
        solver_launch(s, d->pack, (size_t)d->send_total, 0);
    }
}

/* staging_out -> host -> the ranks that share a halo -> staging_in. */
static void exchange_halo(struct solver *s, const struct halo_record *h)
{
    struct domain *d = &s->domain;
    const size_t out_bytes = 4 * (size_t)h->record_words * (size_t)d->send_total;
    const size_t in_bytes = 4 * (size_t)h->record_words * (size_t)d->halo_count;
    d->halo_bytes_sent += (double)out_bytes;
    if (!d->host_out || !d->host_in) { /* the other ranks wait on this one's messages */
        fprintf(stderr, "sph: rank %d: out of host memory for the halo exchange: %s\n", d->rank,
                cl_failure());
        dist_abort(2);
    }
    if (out_bytes > 0)
        CL_CHECK(clEnqueueReadBuffer(s->dev->queue, d->staging_out, CL_TRUE, 0, out_bytes,
                                     d->host_out, 0, NULL, NULL));
    for (int r = 0; r < d->size; ++r) {
        d->send_bytes[r] = 4 * h->record_words * d->send_count[r];
        d->recv_bytes[r] = 4 * h->record_words * d->recv_count[r];
    }
    /* sizes known since the re-sort */
    dist_exchange_known(d->host_out, d->send_bytes, d->host_in, d->recv_bytes);
    if (in_bytes > 0)
        CL_CHECK(clEnqueueWriteBuffer(s->dev->queue, d->staging_in, CL_TRUE, 0, in_bytes,
                                      d->host_in, 0, NULL, NULL));
}

static void unpack_halo(struct solver *s, const struct halo_record *h)
{
    struct domain *d = &s->domain;
    const cl_int first = s->n_real;
    for (int k = 0, offset = 0; k < h->count && d->halo_count > 0; offset += h->words[k++]) {
        const int flags = h->field[k] == FIELD_FLAGS;
        const cl_int keep = flags ? SPH_GHOST_KEEP_FLAGS : ~0, set = flags ? SPH_FLAG_GHOST : 0;
        SET_ARGS(s, d->unpack, MEM("target", s->field[h->field[k]]), INT("words", h->words[k]),
                 INT("record_words", h->record_words), INT("offset", offset),
                 MEM("staging", d->staging_in), MEM("index_of_id", s->ghosts.index_of_id),
                 INT("first_id", first), INT("count", d->halo_count), INT("keep", keep),
                 INT("set", set));
        solver_launch(s, d->unpack, (size_t)d->halo_count, 0);
    }
}

/* Copies the listed fields (all when fields is NULL) that the neighbour
 * passes read across from their owners into the halo slots: one record of
 * those fields per halo particle, packed on the device, exchanged, and
 * unpacked (kernels/halo.cl). */
void solver_domain_refresh(struct solver *s, const enum field *fields, int count)
{
    if (!s->domain.active)
        return;
    struct halo_record h;
    halo_record_of(s, fields, count, &h);
    if (h.count == 0)
        return;
    pack_halo(s, &h);
    exchange_halo(s, &h);
    unpack_halo(s, &h);
}

/* ---- checkpoints: this rank's share, the boxes and the halo's lists */

/* A tree read back: preorder (a child node comes after its parent, so the
 * descent ends), every leaf a rank, every axis a dimension. */
static int valid_tree(const struct domain *d, int dim)
{
    char *seen = calloc((size_t)d->size, 1);
    int valid = seen != NULL;
    for (int c = 0; valid && c < d->size - 1; ++c) {
        valid = d->split_axis[c] >= 0 && d->split_axis[c] < dim && !isnan(d->split_at[c]);
        for (int side = 0; valid && side < 2; ++side) {
            const int next = d->child[2 * c + side];
            valid = next >= -d->size && (next < 0 || (next > c && next < d->size - 1));
            if (valid && next < 0) /* each rank a leaf once */
                valid = !seen[-1 - next]++;
        }
    }
    free(seen);
    return valid;
}

void solver_domain_records(struct solver *s, struct checkpoint *k, int load)
{
    struct domain *d = &s->domain;
    CHECKPOINT_RECORD(k, "domain.", s->n_real, load);
    CHECKPOINT_RECORD(k, "domain.", d->halo_count, load);
    CHECKPOINT_RECORD(k, "domain.", d->send_total, load);
    CHECKPOINT_RECORD(k, "domain.", d->migrated, load);
    CHECKPOINT_RECORD(k, "domain.", d->rebalances, load);
    CHECKPOINT_RECORD(k, "domain.", d->halo_bytes_sent, load);
    const size_t ranks = (size_t)d->size;
    /* the bisection tree: size - 1 nodes */
    checkpoint_record(k, "domain.split_axis", d->split_axis, sizeof(int) * (ranks - 1), load);
    checkpoint_record(k, "domain.split_at", d->split_at, sizeof(double) * (ranks - 1), load);
    checkpoint_record(k, "domain.child", d->child, 2 * sizeof(int) * (ranks - 1), load);
    checkpoint_record(k, "domain.send_count", d->send_count, sizeof(int) * ranks, load);
    checkpoint_record(k, "domain.recv_count", d->recv_count, sizeof(int) * ranks, load);
    const int room = s->capacity - s->ghosts.capacity;
    if (load && !k->failed &&
        (s->n_real < 0 || d->halo_count < 0 || d->send_total < 0 ||
         s->n_real + d->halo_count > room))
        checkpoint_fail(k, "an impossible particle count in", "domain.s->n_real");
    if (load && !k->failed && !valid_tree(d, s->dim))
        checkpoint_fail(k, "an impossible bisection tree in", "domain.child");
    if (k->failed)
        return;
    int *ids = calloc((size_t)d->send_total + 1, sizeof(int));
    if (load) {
        free(d->global_id);
        d->global_id = calloc((size_t)s->n_real + 1, sizeof(int));
    } else if (ids && d->send_total > 0)
        CL_CHECK(clEnqueueReadBuffer(s->dev->queue, d->send_ids, CL_TRUE, 0,
                                     sizeof(int) * (size_t)d->send_total, ids, 0, NULL, NULL));
    if (!ids || !d->global_id) {
        free(ids);
        checkpoint_fail(k, "out of host memory for", "domain.global_id");
        return;
    }
    checkpoint_record(k, "domain.global_id", d->global_id, sizeof(int) * (size_t)s->n_real, load);
    checkpoint_record(k, "domain.send_ids", ids, sizeof(int) * (size_t)d->send_total, load);
    if (load && !k->failed)
        halo_buffers(s, ids);
    free(ids);
}

/* ---- the step's reductions over every rank */

void solver_domain_reduce(const struct solver *s, struct reduction *r, double *contact)
{
    const struct domain *d = &s->domain;
    if (!d->active)
        return;
    double sums[15 + SPH_CONTACT_SLOTS] = {r->load_power, r->kinetic,       r->internal,
                                           r->wall_power, r->viscous_power, r->hourglass_power};
    for (int a = 0; a < 3; ++a) {
        sums[6 + a] = r->probe_displacement[a];
        sums[9 + a] = r->momentum[a];
        sums[12 + a] = r->wall_force[a];
    }
    for (int k = 0; contact && k < SPH_CONTACT_SLOTS; ++k)
        sums[15 + k] = contact[k];
    /* with the scene index of the lowest unhealthy particle anywhere, as
     * its negative: one maximum takes all four */
    const double bad = r->bad_id >= 0 && r->bad_id < s->n_real ? d->global_id[r->bad_id] : HUGE_VAL;
    double maxima[4] = {r->max_signal, r->max_speed, r->max_drift_speed, -bad};
    /* one Allreduce for the step's figures */
    dist_sum_max(sums, contact ? 15 + SPH_CONTACT_SLOTS : 15, maxima, 4);
    for (int k = 0; contact && k < SPH_CONTACT_SLOTS; ++k)
        contact[k] = sums[15 + k];
    r->load_power = sums[0], r->kinetic = sums[1], r->internal = sums[2];
    r->wall_power = sums[3], r->viscous_power = sums[4], r->hourglass_power = sums[5];
    for (int a = 0; a < 3; ++a) {
        r->probe_displacement[a] = sums[6 + a];
        r->momentum[a] = sums[9 + a];
        r->wall_force[a] = sums[12 + a];
    }
    r->max_signal = maxima[0], r->max_speed = maxima[1], r->max_drift_speed = maxima[2];
    r->bad_id = isfinite(maxima[3]) ? (long)-maxima[3] : -1;
}

/* Scene index of each slot (-1: a ghost or halo slot) from the slots' ids. */
void solver_domain_rows(const struct solver *s, int *row_of_slot, int n)
{
    for (int k = 0; k < n; ++k) {
        const int id = row_of_slot[k];
        row_of_slot[k] = id >= s->n_real ? -1 : s->domain.active ? s->domain.global_id[id] : id;
    }
}

/* ---- set-up and release */

static void domain_kernels(struct solver *s, int make)
{
    struct domain *d = &s->domain;
    const struct kernel_slot list[] = {
        {&d->pack, d->active ? "halo_pack" : NULL, 0},
        {&d->unpack, d->active ? "halo_unpack" : NULL, 0},
    };
    solver_kernels(s, list, (int)(sizeof list / sizeof list[0]), make);
}

void solver_domain_create(struct solver *s)
{
    domain_kernels(s, 1);
}

void solver_domain_release(struct solver *s)
{
    struct domain *d = &s->domain;
    domain_kernels(s, 0);
    solver_release_buffer(&d->send_ids);
    solver_release_buffer(&d->staging_out);
    solver_release_buffer(&d->staging_in);
    free(d->split_axis), free(d->split_at), free(d->child);
    free(d->global_id), free(d->send_count), free(d->recv_count);
    free(d->send_bytes), free(d->recv_bytes), free(d->host_out), free(d->host_in);
    d->split_axis = d->child = NULL, d->split_at = NULL;
    d->global_id = NULL, d->send_count = d->recv_count = NULL;
    d->send_bytes = d->recv_bytes = NULL, d->host_out = d->host_in = NULL;
}

void solver_domain_figures(const struct solver *s, double *halo_particles, double *halo_bytes)
{
    const struct domain *d = &s->domain;
    double v[2] = {d->halo_count, d->halo_bytes_sent};
    dist_sum(v, 2); /* means over the ranks */
    *halo_particles = d->active ? v[0] / d->size : 0;
    *halo_bytes = d->active ? v[1] / d->size : 0;
}
