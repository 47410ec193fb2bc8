/* HDF5 snapshots with an XDMF index, CSV history and summary.json. The XDMF
 * index is rewritten after every snapshot so that a run that stops early
 * leaves a complete, openable series. */
#include "output.h"

#include <errno.h>
#include <hdf5.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "domain.h"

#include "checkpoint.h"

int make_folders(const char *path)
{
    char buffer[SPH_PATH_MAX];
    snprintf(buffer, sizeof buffer, "%s", path);
    for (char *p = buffer + 1;; ++p) {
        const char saved = *p;
        if (saved == '/' || saved == '\0') {
            *p = '\0';
            if (mkdir(buffer, 0755) != 0 && errno != EEXIST)
                return -1;
            *p = saved;
        }
        if (saved == '\0')
            break;
    }
    return 0;
}

void output_temporary_name(const char *path, char *temporary, size_t size)
{
    const char *slash = strrchr(path, '/');
    const int folder = slash ? (int)(slash - path + 1) : 0;
    snprintf(temporary, size, "%.*s.%s.tmp", folder, path, path + folder);
}

FILE *output_file_begin(const char *path, char *temporary, size_t size)
{
    output_temporary_name(path, temporary, size);
    return fopen(temporary, "w");
}

/* Flushes the CSV files; non-zero when a write to them failed (the disk,
 * a file size limit). */
static int flush_csv(struct output *o)
{
    return fflush(o->history) != 0 || ferror(o->history) ||
           (o->ballistics && (fflush(o->ballistics) != 0 || ferror(o->ballistics)));
}

int output_file_commit(FILE *f, const char *temporary, const char *path)
{
    const int failed = ferror(f) | (fclose(f) != 0);
    if (failed || rename(temporary, path) != 0) {
        remove(temporary);
        return 1;
    }
    return 0;
}

/* What the outputs take from the case. */
static int output_setup(struct output *o, const char *folder, const struct sph_case *c,
                        int particles, char *error, size_t error_size)
{
    memset(o, 0, sizeof *o);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* our messages name the file and the cause */
    snprintf(o->folder, sizeof o->folder, "%s", folder);
    o->particle_count = particles;
    o->dim = c->dimension;
    snprintf(o->probe_name, sizeof o->probe_name, "%s", c->has_probe ? c->probe.name : "probe");
    o->projectile_radius = c->projectile.enabled ? 0.5 * c->projectile.diameter : 0;
    o->wall_count = c->wall_count;
    for (int w = 0; w < c->wall_count; ++w) {
        memcpy(o->wall_point[w], c->walls[w].point, sizeof o->wall_point[w]);
        memcpy(o->wall_normal[w], c->walls[w].normal, sizeof o->wall_normal[w]);
    }
    o->snapshot_times = CHECKED_CALLOC(SPH_MAX_SNAPSHOTS, sizeof(double), "snapshot index");
    if (!o->snapshot_times)
        return snprintf(error, error_size, "out of host memory for the snapshot index") > 0;
    return 0;
}

int output_open(struct output *o, const char *folder, const struct sph_case *c, int particles,
                char *error, size_t error_size)
{
    if (output_setup(o, folder, c, particles, error, error_size))
        return 1;
    o->silent = dist_rank() != 0; /* over several processes rank 0 writes */
    if (o->silent)
        return 0;
    if (make_folders(folder) != 0) {
        snprintf(error, error_size, "cannot create the output folder %s: %s", folder,
                 strerror(errno));
        return 1;
    }
    char path[SPH_PATH_MAX + 64], temporary[SPH_PATH_MAX + 80];
    snprintf(path, sizeof path, "%s/case.resolved.yaml", folder);
    FILE *f = output_file_begin(path, temporary, sizeof temporary);
    if (!f || (case_write_resolved(c, f) != 0) | output_file_commit(f, temporary, path)) {
        snprintf(error, error_size, "cannot write %s: %s", path, strerror(errno));
        return 1;
    }
    snprintf(path, sizeof path, "%s/history.csv", folder);
    o->history = fopen(path, "w");
    if (!o->history) {
        snprintf(error, error_size, "cannot write %s: %s", path, strerror(errno));
        return 1;
    }
    fprintf(o->history,
            "time_s,step,dt_s,%s_m,kinetic_energy_J,internal_energy_J,external_work_J,"
            "total_energy_J,momentum_x_kg_m_s,momentum_y_kg_m_s,momentum_z_kg_m_s,max_speed_m_s,"
            "wall_force_x_N,wall_force_y_N,wall_force_z_N,wall_work_J,min_pair_distance_over_dx,"
            "clumped_fraction,swegle_fraction,neighbours_min,neighbours_mean,neighbours_max,"
            "energy_error,artificial_viscosity_work_J,hourglass_work_J\n",
            o->probe_name);
    return 0;
}

/* A CSV file of a resumed run, cut back to what it held at the checkpoint
 * (rows written after it are written again) and opened for appending. */
static FILE *reopen_csv(const char *folder, const char *name, long length, char *error,
                        size_t error_size)
{
    char path[SPH_PATH_MAX + 64];
    snprintf(path, sizeof path, "%s/%s", folder, name);
    FILE *f = fopen(path, "r+");
    struct stat st;
    if (f && fstat(fileno(f), &st) == 0 && st.st_size < (off_t)length) {
        snprintf(error, error_size,
                 "%s holds %lld bytes, fewer than the %ld it had at the checkpoint (cut or "
                 "replaced since?)",
                 path, (long long)st.st_size, length);
        fclose(f);
        return NULL;
    }
    if (!f || ftruncate(fileno(f), (off_t)length) != 0 || fseek(f, 0, SEEK_END) != 0 ||
        ftell(f) != length) {
        snprintf(error, error_size, "cannot reopen %s at the checkpoint's %ld bytes: %s", path,
                 length, strerror(errno));
        if (f)
            fclose(f);
        return NULL;
    }
    return f;
}

/* The outputs' records in a checkpoint, one list for both ways; the
 * snapshot times follow, their count long. */
static void output_records(struct output *o, struct checkpoint *k, int load)
{
    CHECKPOINT_RECORD(k, "output.", o->resume_history_bytes, load);
    CHECKPOINT_RECORD(k, "output.", o->resume_ballistics_bytes, load);
    CHECKPOINT_RECORD(k, "output.", o->snapshot_count, load);
    CHECKPOINT_RECORD(k, "output.", o->wall_centre, load);
    CHECKPOINT_RECORD(k, "output.", o->wall_half_width, load);
    CHECKPOINT_RECORD(k, "output.", o->cavity_probes, load);
    if (load && !k->failed && (o->snapshot_count < 1 || o->snapshot_count > SPH_MAX_SNAPSHOTS)) {
        snprintf(k->error, sizeof k->error, "%s: impossible snapshot count %d", k->path,
                 o->snapshot_count);
        k->failed = 1;
    }
    checkpoint_record(k, "output.snapshot_times", o->snapshot_times,
                      sizeof(double) * (size_t)o->snapshot_count, load);
}

void output_checkpoint_save(struct output *o, struct checkpoint *k)
{
    /* a length the files never reached would be cut to on resume (rank 0
     * writes them: the others record zeros) */
    if (!o->silent && flush_csv(o)) {
        snprintf(k->error, sizeof k->error, "history.csv or ballistics.csv could not be written");
        k->failed = 1;
        return;
    }
    o->resume_history_bytes = o->history ? ftell(o->history) : 0;
    o->resume_ballistics_bytes = o->ballistics ? ftell(o->ballistics) : 0;
    output_records(o, k, 0);
}

int output_resume(struct output *o, const char *folder, const struct sph_case *c, int particles,
                  struct checkpoint *k, char *error, size_t error_size)
{
    if (output_setup(o, folder, c, particles, error, error_size))
        return 1;
    o->silent = dist_rank() != 0;
    output_records(o, k, 1);
    if (k->failed)
        return snprintf(error, error_size, "%s", k->error) > 0;
    return 0;
}

int output_resume_files(struct output *o, int with_ballistics, char *error, size_t error_size)
{
    if (o->silent)
        return 0;
    o->history = reopen_csv(o->folder, "history.csv", o->resume_history_bytes, error, error_size);
    if (!o->history)
        return 1;
    if (with_ballistics) {
        o->ballistics =
            reopen_csv(o->folder, "ballistics.csv", o->resume_ballistics_bytes, error, error_size);
        if (!o->ballistics)
            return 1;
    }
    return 0;
}

void output_history(struct output *o, const struct history_row *r)
{
    if (o->silent)
        return;
    fprintf(o->history,
            "%.9e,%ld,%.6e,%.9e,%.9e,%.9e,%.9e,%.9e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.9e,",
            r->time, r->step, r->dt, r->probe, r->kinetic, r->internal, r->external_work,
            r->total_energy, r->momentum[0], r->momentum[1], r->momentum[2], r->max_speed,
            r->wall_force[0], r->wall_force[1], r->wall_force[2], r->wall_work);
    fprintf(o->history, "%.6e,%.6e,%.6e,%.0f,%.3f,%.0f,%.6e,%.9e,%.9e\n",
            r->health.min_pair_distance / r->dx, r->health.clumped_fraction,
            r->health.swegle_fraction, r->health.neighbours_min, r->health.neighbours_mean,
            r->health.neighbours_max, r->energy_error, r->viscous_work, r->hourglass_work);
}

int output_ballistics_open(struct output *o, const struct projectile *p, char *error,
                           size_t error_size)
{
    if (o->silent)
        return 0;
    char path[SPH_PATH_MAX + 64];
    snprintf(path, sizeof path, "%s/ballistics.csv", o->folder);
    o->ballistics = fopen(path, "w");
    if (!o->ballistics) {
        snprintf(error, error_size, "cannot write %s: %s", path, strerror(errno));
        return 1;
    }
    o->cavity_probes = p->probe_count;
    fprintf(o->ballistics,
            "time_s,penetration_m,velocity_m_per_s,decelerating_force_N,contact_particles,"
            "system_momentum_kg_m_per_s,projectile_kinetic_energy_J,contact_energy_J,"
            "contact_dissipated_J,"
            "centre_x_m,centre_y_m,centre_z_m,lateral_deflection_m");
    for (int pass = 0; pass < 2; ++pass)
        for (int k = 0; k < p->probe_count; ++k)
            fprintf(o->ballistics, ",cavity_%s_m_at_%.4gum", pass ? "d2" : "d1",
                    1e6 * (k + 1) * p->probe_spacing);
    fputc('\n', o->ballistics);
    return 0;
}

void output_ballistics(struct output *o, const struct ballistics_row *r)
{
    if (o->silent)
        return;
    const struct projectile_reading *p = &r->p;
    double force = 0;
    for (int a = 0; a < 3; ++a)
        force += p->force[a] * p->velocity[a];
    const double speed = sqrt(p->velocity[0] * p->velocity[0] + p->velocity[1] * p->velocity[1] +
                              p->velocity[2] * p->velocity[2]);
    fprintf(o->ballistics, "%.9e,%.9e,%.9e,%.6e,%d,%.9e,%.9e,%.6e,%.6e,%.9e,%.9e,%.9e,%.6e",
            r->time, p->penetration, p->speed_along_axis, speed > 0 ? -force / speed : 0.0,
            p->contacts, r->system_momentum, r->projectile_kinetic, p->contact_energy,
            p->dissipated, p->position[0], p->position[1], p->position[2], p->lateral_deflection);
    for (int k = 0; k < o->cavity_probes; ++k)
        fprintf(o->ballistics, ",%.6e", p->cavity_d1[k]);
    for (int k = 0; k < o->cavity_probes; ++k)
        fprintf(o->ballistics, ",%.6e", p->cavity_d2[k]);
    fputc('\n', o->ballistics);
}

/* The rows of a dataset this process writes: all of them (`id` NULL), or,
 * when the ranks write one file together, its share: `count` rows whose
 * scene indices `id` ascend, placed by runs of consecutive indices. */
struct rows {
    hsize_t total; /* rows of the dataset */
    int count;     /* rows held here */
    const int *id;
    hid_t transfer; /* H5P_DEFAULT, or collective MPI-IO */
    int writes;     /* this process writes its rows (0: it only takes part in creating) */
};

/* Selects this process's rows of `file_space` and returns the matching
 * memory space. */
static hid_t select_rows(hid_t file_space, const struct rows *r, hsize_t cols)
{
    if (!r->id)
        return H5S_ALL;
    const hsize_t mem_dims[2] = {r->count > 0 ? (hsize_t)r->count : 1, cols};
    hid_t memory = H5Screate_simple(cols > 1 ? 2 : 1, mem_dims, NULL);
    if (r->count == 0) {
        H5Sselect_none(memory);
        H5Sselect_none(file_space);
        return memory;
    }
    for (int k = 0, run; k < r->count; k += run) {
        for (run = 1; k + run < r->count && r->id[k + run] == r->id[k] + run; ++run)
            ;
        const hsize_t start[2] = {(hsize_t)r->id[k], 0}, count[2] = {(hsize_t)run, cols};
        H5Sselect_hyperslab(file_space, k == 0 ? H5S_SELECT_SET : H5S_SELECT_OR, start, NULL, count,
                            NULL);
    }
    return memory;
}

/* Writes one dataset, this process's rows of it, with a "units" attribute. */
static int write_rows(hid_t where, const char *name, hid_t type, const void *data,
                      const struct rows *r, hsize_t cols, const char *units)
{
    const hsize_t dims[2] = {r->total, cols};
    hid_t space = H5Screate_simple(cols > 1 ? 2 : 1, dims, NULL);
    hid_t set = H5Dcreate2(where, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    herr_t status = set >= 0 ? 0 : -1;
    if (set >= 0 && r->writes) {
        hid_t memory = select_rows(space, r, cols);
        status =
            H5Dwrite(set, type, memory, memory == H5S_ALL ? H5S_ALL : space, r->transfer, data);
        if (memory != H5S_ALL)
            H5Sclose(memory);
    }
    if (set >= 0) {
        hid_t text = H5Tcopy(H5T_C_S1), scalar = H5Screate(H5S_SCALAR);
        H5Tset_size(text, strlen(units) + 1);
        hid_t attr = H5Acreate2(set, "units", text, scalar, H5P_DEFAULT, H5P_DEFAULT);
        if (attr < 0 || H5Awrite(attr, text, units) < 0)
            status = -1;
        if (attr >= 0)
            H5Aclose(attr);
        H5Sclose(scalar), H5Tclose(text);
        H5Dclose(set);
    }
    H5Sclose(space);
    return status < 0;
}

/* A small dataset of the whole run (the projectile, the walls): rank 0's
 * rows, written by it alone. */
static int write_dataset(hid_t where, const char *name, hid_t type, const void *data, hsize_t rows,
                         hsize_t cols, const char *units, int writes)
{
    const struct rows all = {rows, (int)rows, NULL, H5P_DEFAULT, writes};
    return write_rows(where, name, type, data, &all, cols, units);
}

static int write_attribute(hid_t where, const char *name, hid_t type, const void *value,
                           hsize_t count)
{
    hid_t space = H5Screate_simple(1, &count, NULL);
    hid_t attr = H5Acreate2(where, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    const int bad = attr < 0 || H5Awrite(attr, type, value) < 0;
    if (attr >= 0)
        H5Aclose(attr);
    H5Sclose(space);
    return bad;
}

/* XDMF's attribute type of a column of `components` per particle. */
static const char *xdmf_type(int components)
{
    return components == 1 ? "Scalar" : components == 3 ? "Vector" : "Tensor6";
}

/* The columns a snapshot writes: those read (host/fields.c) that have
 * units; remembered for the XDMF index. */
static void note_columns(struct output *o, const struct host_fields *f)
{
    o->column_count = 0;
    for (int k = 0; k < HOST_COLUMNS; ++k)
        if (f->column[k].data && f->column[k].units)
            o->columns[o->column_count++] = (struct snapshot_column){
                f->column[k].name, f->column[k].components, f->column[k].is_int};
}

/* The projectile's surface at its snapshot position: a latitude-longitude
 * sphere of triangles in 3-D, a circle of segments in 2-D (the x-y plane;
 * axisymmetric: the meridian section). */
#define SPHERE_RINGS 8
#define SPHERE_SECTORS 16
#define CIRCLE_SEGMENTS 48

static int write_projectile_shape(hid_t file, int dim, double radius, const double centre[3],
                                  int writes)
{
    double points[3 * (SPHERE_SECTORS * (SPHERE_RINGS - 1) + 2)];
    int cells[3 * 2 * SPHERE_SECTORS * (SPHERE_RINGS - 1)];
    int np = 0, nc = 0, width = 3;
    if (dim == 2) {
        width = 2;
        for (int k = 0; k < CIRCLE_SEGMENTS; ++k) {
            const double a = 2 * M_PI * k / CIRCLE_SEGMENTS;
            const double p[3] = {centre[0] + radius * cos(a), centre[1] + radius * sin(a), 0};
            memcpy(&points[3 * np++], p, sizeof p);
            cells[nc * 2] = k, cells[nc * 2 + 1] = (k + 1) % CIRCLE_SEGMENTS, ++nc;
        }
    } else {
        const double poles[2][3] = {{0, 0, 1}, {0, 0, -1}};
        for (int r = 1; r < SPHERE_RINGS; ++r)
            for (int k = 0; k < SPHERE_SECTORS; ++k) {
                const double polar = M_PI * r / SPHERE_RINGS, az = 2 * M_PI * k / SPHERE_SECTORS;
                const double u[3] = {sin(polar) * cos(az), sin(polar) * sin(az), cos(polar)};
                for (int a = 0; a < 3; ++a)
                    points[3 * np + a] = centre[a] + radius * u[a];
                ++np;
            }
        for (int e = 0; e < 2; ++e, ++np)
            for (int a = 0; a < 3; ++a)
                points[3 * np + a] = centre[a] + radius * poles[e][a];
        const int north = np - 2, south = np - 1, last = SPHERE_RINGS - 2;
        for (int k = 0; k < SPHERE_SECTORS; ++k) {
            const int next = (k + 1) % SPHERE_SECTORS;
            int *t = &cells[3 * nc];
            t[0] = north, t[1] = k, t[2] = next, t += 3, ++nc;
            t[0] = south, t[1] = last * SPHERE_SECTORS + next, t[2] = last * SPHERE_SECTORS + k,
            ++nc;
            for (int r = 0; r < last; ++r) {
                const int a0 = r * SPHERE_SECTORS + k, a1 = r * SPHERE_SECTORS + next;
                t = &cells[3 * nc];
                t[0] = a0, t[1] = a0 + SPHERE_SECTORS, t[2] = a1 + SPHERE_SECTORS, ++nc;
                t = &cells[3 * nc];
                t[0] = a0, t[1] = a1 + SPHERE_SECTORS, t[2] = a1, ++nc;
            }
        }
    }
    hid_t group = H5Gcreate2(file, "projectile", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (group < 0)
        return 1;
    int bad =
        write_dataset(group, "points", H5T_NATIVE_DOUBLE, points, (hsize_t)np, 3, "m", writes);
    bad |= write_dataset(group, "cells", H5T_NATIVE_INT, cells, (hsize_t)nc, (hsize_t)width,
                         "point indices", writes);
    return (H5Gclose(group) < 0) | bad;
}

/* Walls are planes: each drawn as a square (a segment in 2-D) about the
 * plane's point nearest the first snapshot's centre, as wide as that
 * snapshot's diagonal; written to every snapshot so that ParaView shows them
 * at every time. */
static int write_walls(hid_t file, const struct output *o)
{
    double points[4 * SPH_MAX_WALLS * 3];
    int cells[4 * SPH_MAX_WALLS];
    const int corners = o->dim == 2 ? 2 : 4;
    const double su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
    for (int w = 0; w < o->wall_count; ++w) {
        const double *n = o->wall_normal[w], *c = o->wall_centre[w];
        double u[3] = {-n[1], n[0], 0}, v[3];
        if (o->dim == 3 && fabs(n[2]) > 0.9)
            u[0] = 0, u[1] = -n[2], u[2] = n[1];
        const double un = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        for (int a = 0; a < 3; ++a)
            u[a] *= o->wall_half_width / un;
        v[0] = n[1] * u[2] - n[2] * u[1], v[1] = n[2] * u[0] - n[0] * u[2];
        v[2] = n[0] * u[1] - n[1] * u[0];
        for (int k = 0; k < corners; ++k) {
            cells[w * corners + k] = w * corners + k;
            for (int a = 0; a < 3; ++a)
                points[3 * (w * corners + k) + a] =
                    c[a] + su[k] * u[a] + (o->dim == 2 ? 0 : sv[k] * v[a]);
        }
    }
    hid_t group = H5Gcreate2(file, "walls", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (group < 0)
        return 1;
    const hsize_t count = (hsize_t)(o->wall_count * corners);
    const int writes = !o->silent;
    int bad = write_dataset(group, "points", H5T_NATIVE_DOUBLE, points, count, 3, "m", writes);
    bad |= write_dataset(group, "cells", H5T_NATIVE_INT, cells, (hsize_t)o->wall_count,
                         (hsize_t)corners, "point indices", writes);
    return (H5Gclose(group) < 0) | bad;
}

/* The file's access and transfer properties: one process's file, or
 * (distributed rows) one file every rank writes with collective MPI-IO. */
static int snapshot_properties(const struct host_fields *f, hid_t *access, hid_t *transfer)
{
    /* a failed write still closes every object (strong close degree), so
     * nothing is left open for HDF5's exit handler */
    *access = H5Pcreate(H5P_FILE_ACCESS);
    *transfer = H5P_DEFAULT;
    int bad = H5Pset_fclose_degree(*access, H5F_CLOSE_STRONG) < 0;
#ifdef SPH_PARALLEL_HDF5
    if (f->distributed) {
        *transfer = H5Pcreate(H5P_DATASET_XFER);
        bad |= dist_hdf5_collective(*access, *transfer);
    }
#endif
    return bad;
}

static int write_snapshot_file(const struct output *o, const char *path,
                               const struct host_fields *f, const struct snapshot_meta *m)
{
    hid_t access, transfer;
    int bad = snapshot_properties(f, &access, &transfer);
    /* every rank goes on to the collective calls, or none */
    if (f->distributed ? dist_any(bad) : bad) {
        H5Pclose(access);
        if (transfer != H5P_DEFAULT)
            H5Pclose(transfer);
        return 1;
    }
    hid_t file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, access);
    H5Pclose(access);
    if (f->distributed ? dist_any(file < 0) : file < 0) {
        if (file >= 0)
            H5Fclose(file);
        if (transfer != H5P_DEFAULT)
            H5Pclose(transfer);
        return 1;
    }
    const struct rows mine = {(hsize_t)f->n_total, f->n, f->id, transfer, 1};
    for (int k = 0; k < HOST_COLUMNS; ++k) {
        const struct host_column *col = &f->column[k];
        if (col->data && col->units)
            bad |= write_rows(file, col->name, col->is_int ? H5T_NATIVE_INT : H5T_NATIVE_DOUBLE,
                              col->data, &mine, (hsize_t)col->components, col->units);
    }
    if (transfer != H5P_DEFAULT)
        H5Pclose(transfer);
    const long long step = m->step;
    const int dim = o->dim;
    bad |= write_attribute(file, "time_s", H5T_NATIVE_DOUBLE, &m->time, 1);
    bad |= write_attribute(file, "step", H5T_NATIVE_LLONG, &step, 1);
    bad |= write_attribute(file, "dimension", H5T_NATIVE_INT, &dim, 1);
    if (o->projectile_radius > 0) {
        bad |= write_attribute(file, "projectile_centre_m", H5T_NATIVE_DOUBLE, m->projectile_centre,
                               3);
        bad |= write_attribute(file, "projectile_velocity_m_per_s", H5T_NATIVE_DOUBLE,
                               m->projectile_velocity, 3);
        bad |= write_projectile_shape(file, o->dim, o->projectile_radius, m->projectile_centre,
                                      !o->silent);
    }
    if (o->wall_count > 0)
        bad |= write_walls(file, o);
    return (H5Fclose(file) < 0) | bad;
}

static void xdmf_item(FILE *x, const char *file, const char *name, int n, int cols, int is_int)
{
    if (cols > 1)
        fprintf(x, "        <DataItem Dimensions=\"%d %d\" ", n, cols);
    else
        fprintf(x, "        <DataItem Dimensions=\"%d\" ", n);
    fprintf(x, "NumberType=\"%s\" Precision=\"%d\" Format=\"HDF\">%s:/%s</DataItem>\n",
            is_int ? "Int" : "Float", is_int ? 4 : 8, file, name);
}

static void xdmf_attribute(FILE *x, const char *file, const char *name, const char *type, int n,
                           int cols, int is_int)
{
    fprintf(x, "      <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\">\n", name, type);
    xdmf_item(x, file, name, n, cols, is_int);
    fprintf(x, "      </Attribute>\n");
}

/* One vertex cell per particle, its connectivity the id column (rows are in
 * id order): ParaView's default Xdmf3 reader draws a Polyvertex topology
 * only when it is given its connectivity. */
static void xdmf_particles(FILE *x, const char *file, const struct output *o)
{
    const int n = o->particle_count;
    fprintf(x,
            "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%d\" "
            "NodesPerElement=\"1\">\n",
            n);
    xdmf_item(x, file, "id", n, 1, 1);
    fprintf(x, "      </Topology>\n      <Geometry GeometryType=\"XYZ\">\n");
    xdmf_item(x, file, "position", n, 3, 0);
    fprintf(x, "      </Geometry>\n");
    for (int k = 0; k < o->column_count; ++k) {
        const struct snapshot_column *c = &o->columns[k];
        if (strcmp(c->name, field_table[FIELD_POS].name) != 0) /* the geometry */
            xdmf_attribute(x, file, c->name, xdmf_type(c->components), n, c->components, c->is_int);
    }
}

static void xdmf_projectile(FILE *x, const char *file, int dim)
{
    const int points = dim == 2 ? CIRCLE_SEGMENTS : SPHERE_SECTORS * (SPHERE_RINGS - 1) + 2;
    const int cells = dim == 2 ? CIRCLE_SEGMENTS : 2 * SPHERE_SECTORS * (SPHERE_RINGS - 1);
    if (dim == 2)
        fprintf(x,
                "      <Topology TopologyType=\"Polyline\" NumberOfElements=\"%d\" "
                "NodesPerElement=\"2\">\n",
                cells);
    else
        fprintf(x, "      <Topology TopologyType=\"Triangle\" NumberOfElements=\"%d\">\n", cells);
    xdmf_item(x, file, "projectile/cells", cells, dim == 2 ? 2 : 3, 1);
    fprintf(x, "      </Topology>\n      <Geometry GeometryType=\"XYZ\">\n");
    xdmf_item(x, file, "projectile/points", points, 3, 0);
    fprintf(x, "      </Geometry>\n");
}

static void xdmf_walls(FILE *x, const char *file, const struct output *o)
{
    const int corners = o->dim == 2 ? 2 : 4;
    fprintf(x, "      <Topology TopologyType=\"%s\" NumberOfElements=\"%d\">\n",
            o->dim == 2 ? "Polyline\" NodesPerElement=\"2" : "Quadrilateral", o->wall_count);
    xdmf_item(x, file, "walls/cells", o->wall_count, corners, 1);
    fprintf(x, "      </Topology>\n      <Geometry GeometryType=\"XYZ\">\n");
    xdmf_item(x, file, "walls/points", o->wall_count * corners, 3, 0);
    fprintf(x, "      </Geometry>\n");
}

enum series { SERIES_PARTICLES, SERIES_PROJECTILE, SERIES_WALLS };

static void xdmf_series(FILE *x, const struct output *o, const char *name, enum series what)
{
    fprintf(x, "    <Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
            name);
    for (int s = 0; s < o->snapshot_count; ++s) {
        char file[64];
        snprintf(file, sizeof file, "snap_%05d.h5", s);
        fprintf(x, "    <Grid Name=\"%s_%05d\" GridType=\"Uniform\">\n", name, s);
        fprintf(x, "      <Time Value=\"%.9e\"/>\n", o->snapshot_times[s]);
        if (what == SERIES_PROJECTILE)
            xdmf_projectile(x, file, o->dim);
        else if (what == SERIES_WALLS)
            xdmf_walls(x, file, o);
        else
            xdmf_particles(x, file, o);
        fprintf(x, "    </Grid>\n");
    }
    fprintf(x, "    </Grid>\n");
}

/* One XDMF index, written to a temporary name and renamed. The particles
 * and the rigid bodies are separate files: in one file ParaView reads them
 * as blocks of one data set, and a field only the particles carry is then
 * not drawn in colour at all (ParaView 5.11). */
static int write_xdmf_file(const struct output *o, const char *name, int bodies)
{
    char path[SPH_PATH_MAX + 64], tmp[SPH_PATH_MAX + 80];
    snprintf(path, sizeof path, "%s/%s", o->folder, name);
    FILE *x = output_file_begin(path, tmp, sizeof tmp);
    if (!x)
        return 1;
    fprintf(x, "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n");
    if (!bodies)
        xdmf_series(x, o, "particles", SERIES_PARTICLES);
    if (bodies && o->projectile_radius > 0)
        xdmf_series(x, o, "projectile", SERIES_PROJECTILE);
    if (bodies && o->wall_count > 0)
        xdmf_series(x, o, "walls", SERIES_WALLS);
    fprintf(x, "  </Domain>\n</Xdmf>\n");
    return output_file_commit(x, tmp, path);
}

static int write_xdmf(const struct output *o)
{
    const int bodies = o->projectile_radius > 0 || o->wall_count > 0;
    return write_xdmf_file(o, "snapshots.xdmf", 0) |
           (bodies ? write_xdmf_file(o, "bodies.xdmf", 1) : 0);
}

/* Where each wall is drawn: the plane's point nearest the centre of the
 * first snapshot's particles. */
static void place_walls(struct output *o, const struct host_fields *f)
{
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    const double *pos = HOST_REALS(f, FIELD_POS);
    for (int i = 0; i < f->n; ++i)
        for (int a = 0; a < 3; ++a)
            lo[a] = fmin(lo[a], pos[3 * i + a]), hi[a] = fmax(hi[a], pos[3 * i + a]);
    if (f->distributed)
        dist_min(lo, 3), dist_max(hi, 3);
    double diagonal = 0, centre[3];
    for (int a = 0; a < 3; ++a) {
        centre[a] = f->n_total ? 0.5 * (lo[a] + hi[a]) : 0;
        diagonal += f->n_total ? (hi[a] - lo[a]) * (hi[a] - lo[a]) : 0;
    }
    o->wall_half_width = fmax(0.5 * sqrt(diagonal), 1e-6);
    for (int w = 0; w < o->wall_count; ++w) {
        double height = 0;
        for (int a = 0; a < 3; ++a)
            height += (centre[a] - o->wall_point[w][a]) * o->wall_normal[w][a];
        for (int a = 0; a < 3; ++a)
            o->wall_centre[w][a] = centre[a] - height * o->wall_normal[w][a];
    }
}

int output_snapshot(struct output *o, const struct host_fields *f, const struct snapshot_meta *meta,
                    char *error, size_t error_size)
{
    if (o->snapshot_count >= SPH_MAX_SNAPSHOTS)
        return 0;
    if (o->silent && !f->distributed) { /* rank 0 writes what it gathered */
        o->snapshot_times[o->snapshot_count++] = meta->time;
        return 0;
    }
    if (o->snapshot_count == 0)
        place_walls(o, f);
    note_columns(o, f);
    char path[SPH_PATH_MAX + 64], temporary[SPH_PATH_MAX + 80];
    snprintf(path, sizeof path, "%s/snap_%05d.h5", o->folder, o->snapshot_count);
    output_temporary_name(path, temporary, sizeof temporary);
    int bad = write_snapshot_file(o, temporary, f, meta);
    if (f->distributed) /* every rank wrote its share */
        bad = dist_any(bad);
    if (bad || (!o->silent && rename(temporary, path) != 0)) {
        if (!o->silent)
            remove(temporary);
        snprintf(error, error_size, "cannot write snapshot %s (disk full, or a file size limit?)",
                 path);
        return 1;
    }
    o->snapshot_times[o->snapshot_count++] = meta->time;
    if (o->silent)
        return 0;
    if (write_xdmf(o) != 0) {
        snprintf(error, error_size, "cannot write %s/snapshots.xdmf or bodies.xdmf: %s", o->folder,
                 strerror(errno));
        return 1;
    }
    if (flush_csv(o)) {
        snprintf(error, error_size, "cannot write %s/history.csv or ballistics.csv: %s", o->folder,
                 strerror(errno));
        return 1;
    }
    return 0;
}

static void json_string(FILE *f, const char *key, const char *v)
{
    fprintf(f, "  \"%s\": \"", key);
    for (const char *p = v ? v : ""; *p; ++p) {
        if (*p == '"' || *p == '\\')
            fputc('\\', f);
        if ((unsigned char)*p >= 0x20)
            fputc(*p, f);
    }
    fputs("\",\n", f);
}

static void json_number(FILE *f, const char *key, double v, int last)
{
    if (isfinite(v))
        fprintf(f, "  \"%s\": %.9g%s\n", key, v, last ? "" : ",");
    else
        fprintf(f, "  \"%s\": null%s\n", key, last ? "" : ",");
}

/* summary.json's projectile figures (README, outputs). */
static void summary_projectile(FILE *f, const struct run_summary *s)
{
    json_number(f, "max_penetration_m", s->max_penetration_m, 0);
    json_number(f, "time_of_max_penetration_s", s->time_of_max_penetration_s, 0);
    json_number(f, "final_penetration_m", s->final_penetration_m, 0);
    json_number(f, "final_projectile_velocity_m_per_s", s->final_projectile_velocity_m_per_s, 0);
    fprintf(f, "  \"rebound\": %s,\n", s->final_projectile_velocity_m_per_s < 0 ? "true" : "false");
    json_number(f, "max_cavity_diameter_m", s->max_cavity_diameter_m, 0);
    json_number(f, "max_damaged_diameter_m", s->max_damaged_diameter_m, 0);
    json_number(f, "momentum_error", s->momentum_error, 0);
    json_number(f, "damaged_fraction", s->damaged_fraction, 0);
    json_number(f, "max_lateral_deflection_m", s->max_lateral_deflection_m, 0);
    json_number(f, "final_lateral_deflection_m", s->final_lateral_deflection_m, 0);
    fprintf(f, "  \"perforated\": %s,\n", s->exit_time_s >= 0 ? "true" : "false");
    if (s->exit_time_s >= 0) {
        json_number(f, "exit_time_s", s->exit_time_s, 0);
        json_number(f, "residual_velocity_m_per_s", s->final_projectile_velocity_m_per_s, 0);
    }
    if (s->left_fine_region_time_s >= 0)
        json_number(f, "nose_left_fine_region_time_s", s->left_fine_region_time_s, 0);
}

int output_summary(struct output *o, const struct run_summary *s)
{
    if (o->silent)
        return 0;
    /* through a temporary name: a full disk leaves the previous file, not an empty one */
    char path[SPH_PATH_MAX + 64], temporary[SPH_PATH_MAX + 80];
    snprintf(path, sizeof path, "%s/summary.json", o->folder);
    FILE *f = output_file_begin(path, temporary, sizeof temporary);
    if (!f)
        return 1;
    fprintf(f, "{\n");
    json_string(f, "case", s->case_name);
    json_string(f, "device", s->device);
    json_string(f, "status", s->status);
    json_string(f, "message", s->message);
    json_string(f, "precision", s->precision);
    json_string(f, "neighbour_loop", s->neighbour_loop);
    fprintf(f, "  \"neighbour_lanes\": %d,\n", s->neighbour_lanes);
    fprintf(f, "  \"grid_sorts\": %ld,\n", s->grid_sorts);
    if (s->lane_list_candidates > 0)
        fprintf(f,
                "  \"lane_list_candidates_per_block\": %.2f,\n  \"lane_list_bytes_per_particle\": "
                "%.1f,\n",
                s->lane_list_candidates, s->lane_list_bytes);
    fprintf(f, "  \"dimension\": %d,\n  \"particles\": %d,\n  \"steps\": %ld,\n", s->dimension,
            s->particles, s->steps);
    fprintf(f, "  \"bytes_per_particle\": %zu,\n", s->bytes_per_particle);
    fprintf(f, "  \"processes\": %d,\n", s->processes);
    if (s->processes > 1)
        fprintf(f,
                "  \"migrated_particles\": %ld,\n  \"rebalances\": %d,\n"
                "  \"halo_particles_per_rank\": %.1f,\n  \"halo_bytes_per_step_per_rank\": %.6g,\n",
                s->migrated_particles, s->rebalances, s->halo_particles, s->halo_bytes_per_step);
    json_number(f, "end_time_s", s->end_time, 0);
    json_number(f, "wall_time_s", s->wall_time_s, 0);
    json_number(f, "steps_per_s", s->steps_per_s, 0);
    json_number(f, "energy_drift", s->energy_drift, 0);
    json_number(f, "max_neighbour_loss_fraction", s->max_neighbour_loss_fraction, 0);
    json_number(f, "artificial_viscosity_work_J", s->viscous_work_J, 0);
    json_number(f, "artificial_viscosity_work_fraction", s->viscous_work_fraction, 0);
    if (s->has_hourglass) {
        json_number(f, "hourglass_work_J", s->hourglass_work_J, 0);
        json_number(f, "hourglass_work_fraction", s->hourglass_work_fraction, 0);
        fprintf(f, "  \"reference_updates\": %ld,\n", s->reference_updates);
    }
    if (s->has_probe) {
        char key[SPH_NAME_MAX + 16];
        snprintf(key, sizeof key, "%s_final_m", s->probe_name);
        json_number(f, key, s->probe_final, 0);
        snprintf(key, sizeof key, "%s_mean_m", s->probe_name);
        json_number(f, key, s->probe_mean, 0);
    }
    if (s->has_reference) {
        json_number(f, "reference_m", s->reference, 0);
        json_number(f, "error_final", s->reference_error_final, 0);
        json_number(f, "e_av", s->reference_e_av, 0);
    }
    if (s->has_wall) {
        json_number(f, "final_length_m", s->final_length_m, 0);
        json_number(f, "footprint_radius_m", s->footprint_radius_m, 0);
    }
    json_number(f, "min_pair_distance_over_dx", s->min_pair_distance_over_dx, 0);
    json_number(f, "max_clumped_fraction", s->max_clumped_fraction, 0);
    json_number(f, "max_swegle_fraction", s->max_swegle_fraction, 0);
    if (s->first_unhealthy_time >= 0) {
        json_number(f, "first_unhealthy_time_s", s->first_unhealthy_time, 0);
        json_string(f, "unhealthy_reason", s->unhealthy_reason);
    }
    if (s->has_projectile)
        summary_projectile(f, s);
    if (s->has_plasticity) {
        json_number(f, "max_plastic_strain", s->max_plastic_strain, 0);
        json_number(f, "max_temperature_K", s->max_temperature_K, 0);
    }
    const int healthy = strcmp(s->status, "completed") == 0 &&
                        !(s->max_neighbour_loss_fraction > 0) && s->first_unhealthy_time < 0;
    fprintf(f, "  \"healthy\": %s\n}\n", healthy ? "true" : "false");
    return output_file_commit(f, temporary, path);
}

void output_close(struct output *o)
{
    if (o->history)
        fclose(o->history);
    if (o->ballistics)
        fclose(o->ballistics);
    free(o->snapshot_times);
    memset(o, 0, sizeof *o);
}
