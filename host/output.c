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

int output_open(struct output *o, const char *folder, const struct sph_case *c, int particles,
                char *error, size_t error_size)
{
    memset(o, 0, sizeof *o);
    snprintf(o->folder, sizeof o->folder, "%s", folder);
    o->particle_count = particles;
    o->dim = c->dimension;
    snprintf(o->probe_name, sizeof o->probe_name, "%s", c->has_probe ? c->probe.name : "probe");
    if (make_folders(folder) != 0) {
        snprintf(error, error_size, "cannot create the output folder %s: %s", folder,
                 strerror(errno));
        return 1;
    }
    char path[SPH_PATH_MAX + 64];
    snprintf(path, sizeof path, "%s/case.resolved.yaml", folder);
    FILE *f = fopen(path, "w");
    if (!f || case_write_resolved(c, f) != 0) {
        snprintf(error, error_size, "cannot write %s: %s", path, strerror(errno));
        if (f)
            fclose(f);
        return 1;
    }
    fclose(f);
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
    o->snapshot_times = malloc(sizeof(double) * SPH_MAX_SNAPSHOTS);
    return o->snapshot_times ? 0 : 1;
}

void output_history(struct output *o, const struct history_row *r)
{
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
            "centre_x_m,centre_y_m,centre_z_m");
    for (int pass = 0; pass < 2; ++pass)
        for (int k = 0; k < p->probe_count; ++k)
            fprintf(o->ballistics, ",cavity_%s_m_at_%.4gum", pass ? "d2" : "d1",
                    1e6 * (k + 1) * p->probe_spacing);
    fputc('\n', o->ballistics);
    return 0;
}

void output_ballistics(struct output *o, const struct ballistics_row *r)
{
    const struct projectile_reading *p = &r->p;
    double force = 0;
    for (int a = 0; a < 3; ++a)
        force += p->force[a] * p->velocity[a];
    const double speed = sqrt(p->velocity[0] * p->velocity[0] + p->velocity[1] * p->velocity[1] +
                              p->velocity[2] * p->velocity[2]);
    fprintf(o->ballistics, "%.9e,%.9e,%.9e,%.6e,%d,%.9e,%.9e,%.6e,%.6e,%.9e,%.9e,%.9e", r->time,
            p->penetration, p->speed_along_axis, speed > 0 ? -force / speed : 0.0, p->contacts,
            r->system_momentum, r->projectile_kinetic, p->contact_energy, p->dissipated,
            p->position[0], p->position[1], p->position[2]);
    for (int k = 0; k < o->cavity_probes; ++k)
        fprintf(o->ballistics, ",%.6e", p->cavity_d1[k]);
    for (int k = 0; k < o->cavity_probes; ++k)
        fprintf(o->ballistics, ",%.6e", p->cavity_d2[k]);
    fputc('\n', o->ballistics);
}

static int write_dataset(hid_t file, const char *name, hid_t type, const void *data, hsize_t rows,
                         hsize_t cols)
{
    const hsize_t dims[2] = {rows, cols};
    hid_t space = H5Screate_simple(cols > 1 ? 2 : 1, dims, NULL);
    hid_t set = H5Dcreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    herr_t status = set >= 0 ? H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) : -1;
    if (set >= 0)
        H5Dclose(set);
    H5Sclose(space);
    return status < 0;
}

static const char *const scalar_names[] = {"density",          "pressure",       "internal_energy",
                                           "von_mises_stress", "plastic_strain", "temperature"};
#define SCALAR_COUNT (int)(sizeof scalar_names / sizeof scalar_names[0])

static int write_snapshot_file(const char *path, const struct host_fields *f)
{
    hid_t file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (file < 0)
        return 1;
    const hsize_t n = (hsize_t)f->n;
    const double *scalars[] = {f->rho,       f->pressure,       f->energy,
                               f->von_mises, f->plastic_strain, f->temperature};
    int bad = write_dataset(file, "position", H5T_NATIVE_DOUBLE, f->pos, n, 3);
    bad |= write_dataset(file, "velocity", H5T_NATIVE_DOUBLE, f->vel, n, 3);
    bad |= write_dataset(file, "displacement", H5T_NATIVE_DOUBLE, f->disp, n, 3);
    bad |= write_dataset(file, "stress", H5T_NATIVE_DOUBLE, f->stress, n, 6);
    for (int k = 0; k < SCALAR_COUNT; ++k)
        bad |= write_dataset(file, scalar_names[k], H5T_NATIVE_DOUBLE, scalars[k], n, 1);
    bad |= write_dataset(file, "flags", H5T_NATIVE_INT, f->flags, n, 1);
    bad |= write_dataset(file, "material", H5T_NATIVE_INT, f->material, n, 1);
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

static int write_xdmf(const struct output *o)
{
    char path[SPH_PATH_MAX + 64], tmp[SPH_PATH_MAX + 64];
    snprintf(path, sizeof path, "%s/snapshots.xdmf", o->folder);
    snprintf(tmp, sizeof tmp, "%s/.snapshots.xdmf.tmp", o->folder);
    FILE *x = fopen(tmp, "w");
    if (!x)
        return 1;
    const int n = o->particle_count;
    fprintf(x, "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n"
               "    <Grid Name=\"particles\" GridType=\"Collection\" "
               "CollectionType=\"Temporal\">\n");
    for (int s = 0; s < o->snapshot_count; ++s) {
        char file[64];
        snprintf(file, sizeof file, "snap_%05d.h5", s);
        fprintf(x, "    <Grid Name=\"snap_%05d\" GridType=\"Uniform\">\n", s);
        fprintf(x, "      <Time Value=\"%.9e\"/>\n", o->snapshot_times[s]);
        fprintf(x,
                "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%d\" "
                "NodesPerElement=\"1\"/>\n      <Geometry GeometryType=\"XYZ\">\n",
                n);
        xdmf_item(x, file, "position", n, 3, 0);
        fprintf(x, "      </Geometry>\n");
        xdmf_attribute(x, file, "velocity", "Vector", n, 3, 0);
        xdmf_attribute(x, file, "displacement", "Vector", n, 3, 0);
        xdmf_attribute(x, file, "stress", "Tensor6", n, 6, 0);
        for (int k = 0; k < SCALAR_COUNT; ++k)
            xdmf_attribute(x, file, scalar_names[k], "Scalar", n, 1, 0);
        xdmf_attribute(x, file, "flags", "Scalar", n, 1, 1);
        xdmf_attribute(x, file, "material", "Scalar", n, 1, 1);
        fprintf(x, "    </Grid>\n");
    }
    fprintf(x, "    </Grid>\n  </Domain>\n</Xdmf>\n");
    if (fclose(x) != 0)
        return 1;
    return rename(tmp, path) != 0;
}

int output_snapshot(struct output *o, const struct host_fields *f, double time, long step,
                    char *error, size_t error_size)
{
    (void)step;
    if (o->snapshot_count >= SPH_MAX_SNAPSHOTS)
        return 0;
    char path[SPH_PATH_MAX + 64];
    snprintf(path, sizeof path, "%s/snap_%05d.h5", o->folder, o->snapshot_count);
    if (write_snapshot_file(path, f) != 0) {
        snprintf(error, error_size, "cannot write snapshot %s", path);
        return 1;
    }
    o->snapshot_times[o->snapshot_count++] = time;
    if (write_xdmf(o) != 0) {
        snprintf(error, error_size, "cannot write %s/snapshots.xdmf: %s", o->folder,
                 strerror(errno));
        return 1;
    }
    fflush(o->history);
    if (o->ballistics)
        fflush(o->ballistics);
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

int output_summary(struct output *o, const struct run_summary *s)
{
    char path[SPH_PATH_MAX + 64];
    snprintf(path, sizeof path, "%s/summary.json", o->folder);
    FILE *f = fopen(path, "w");
    if (!f)
        return 1;
    fprintf(f, "{\n");
    json_string(f, "case", s->case_name);
    json_string(f, "device", s->device);
    json_string(f, "status", s->status);
    json_string(f, "message", s->message);
    json_string(f, "precision", s->precision);
    fprintf(f, "  \"dimension\": %d,\n  \"particles\": %d,\n  \"steps\": %ld,\n", s->dimension,
            s->particles, s->steps);
    fprintf(f, "  \"bytes_per_particle\": %zu,\n", s->bytes_per_particle);
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
    if (s->has_projectile) {
        json_number(f, "max_penetration_m", s->max_penetration_m, 0);
        json_number(f, "time_of_max_penetration_s", s->time_of_max_penetration_s, 0);
        json_number(f, "final_penetration_m", s->final_penetration_m, 0);
        json_number(f, "final_projectile_velocity_m_per_s", s->final_projectile_velocity_m_per_s,
                    0);
        fprintf(f, "  \"rebound\": %s,\n",
                s->final_projectile_velocity_m_per_s < 0 ? "true" : "false");
        json_number(f, "max_cavity_diameter_m", s->max_cavity_diameter_m, 0);
        json_number(f, "max_damaged_diameter_m", s->max_damaged_diameter_m, 0);
        json_number(f, "momentum_error", s->momentum_error, 0);
        json_number(f, "damaged_fraction", s->damaged_fraction, 0);
        if (s->left_fine_region_time_s >= 0)
            json_number(f, "nose_left_fine_region_time_s", s->left_fine_region_time_s, 0);
    }
    if (s->has_plasticity) {
        json_number(f, "max_plastic_strain", s->max_plastic_strain, 0);
        json_number(f, "max_temperature_K", s->max_temperature_K, 0);
    }
    const int healthy = strcmp(s->status, "completed") == 0 &&
                        !(s->max_neighbour_loss_fraction > 0) && s->first_unhealthy_time < 0;
    fprintf(f, "  \"healthy\": %s\n}\n", healthy ? "true" : "false");
    return fclose(f) != 0;
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
