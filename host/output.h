/* Run folder outputs: resolved case, HDF5 snapshots + XDMF index (ParaView,
 * VisIt), CSV history, summary.json. */
#ifndef SPH_OUTPUT_H
#define SPH_OUTPUT_H

#include <stdio.h>

#include "solver.h"
#include "sph_case.h"

struct output {
    char folder[SPH_PATH_MAX];
    int silent; /* a rank other than 0 of a run over several processes: writes nothing */
    FILE *history;
    int snapshot_count;
    double *snapshot_times;
    int particle_count;
    int dim;
    char probe_name[SPH_NAME_MAX];
    FILE *ballistics; /* ballistics.csv, with a projectile */
    int cavity_probes;
    double projectile_radius; /* m; 0 without a projectile */
    int wall_count;           /* walls drawn in the XDMF (a square or segment each) */
    double wall_point[SPH_MAX_WALLS][3], wall_normal[SPH_MAX_WALLS][3];
    double wall_centre[SPH_MAX_WALLS][3], wall_half_width; /* placed at the first snapshot */
    long resume_history_bytes, resume_ballistics_bytes;    /* the CSVs' lengths at a checkpoint */
    int column_count; /* the particle datasets of a snapshot, for the XDMF index */
    struct snapshot_column {
        const char *name;
        int components, is_int;
    } columns[HOST_COLUMNS];
};

/* What a snapshot file records beside the particles. */
struct snapshot_meta {
    double time; /* s */
    long step;
    double projectile_centre[3], projectile_velocity[3]; /* m, m/s; with a projectile */
};

/* One row of ballistics.csv (with a projectile). */
struct ballistics_row {
    double time;
    struct projectile_reading p;
    double system_momentum;    /* target + projectile along the impact axis, kg m/s */
    double projectile_kinetic; /* J */
};

/* One row of history.csv. */
struct history_row {
    double time, dt;
    long step;
    double probe;
    double kinetic, internal, external_work;
    double momentum[3];
    double max_speed;
    double dx; /* lattice spacing, m (the pair distance is written over it) */
    struct health_reading health;
    double energy_error;   /* (E - E0) / energy scale */
    double wall_force[3];  /* on the walls, mean since the previous row, N */
    double wall_work;      /* work of the wall forces on the particles so far, J */
    double viscous_work;   /* heat made by the artificial viscosity so far, J */
    double hourglass_work; /* work the hourglass forces took out of the motion so far, J */
    double total_energy;   /* the run's energy ledger (host/run.c, total_energy), J */
};

/* The figures a run ends with (summary line and summary.json). */
struct run_summary {
    const char *case_name, *device, *status, *message, *precision;
    const char *neighbour_loop;  /* "lanes" or "plain": the passes that ran */
    int neighbour_lanes;         /* particles per work-item of passes 1 and 2 (SPH_LANES) */
    long grid_sorts;             /* re-sorts of the neighbour grid by this process (rank 0) */
    double lane_list_candidates; /* lanes: the last lists' entries per lane block */
    double lane_list_bytes;      /* lanes: their device memory per particle, B */
    int particles, dimension;
    long steps;
    double end_time, wall_time_s, steps_per_s;
    size_t bytes_per_particle;  /* of this rank's slots (rank 0 over several processes) */
    int processes;              /* MPI ranks (1: the serial run) */
    long migrated_particles;    /* over several processes: changes of rank, whole run */
    int rebalances;             /* times the domains were cut again */
    double halo_particles;      /* per rank, mean over the ranks, at the end */
    double halo_bytes_per_step; /* sent by each rank's halo refreshes, mean */
    int has_probe;
    const char *probe_name;
    double probe_final, probe_mean;
    int has_reference;
    double reference, reference_error_final, reference_e_av;
    double energy_drift; /* max over steps of |E_total(t) - E_total(0)| / max(external work,
                            kinetic + internal) */
    double max_neighbour_loss_fraction; /* particles that lost over a third of their initial
                                           neighbours, largest over the snapshots */
    double viscous_work_J, viscous_work_fraction; /* artificial viscosity's heat, and over the
                                                     initial kinetic (or largest) energy */
    int has_hourglass;                            /* total Lagrangian: hourglass work reported */
    double hourglass_work_J, hourglass_work_fraction;
    long reference_updates;    /* total Lagrangian: numerics.reference_update's updates */
    int has_wall;              /* impact figures against walls[0] */
    double final_length_m;     /* extent along the wall normal + dx/2 */
    double footprint_radius_m; /* largest distance from the axis in the first layer */
    int has_plasticity;
    double max_plastic_strain, max_temperature_K;
    /* health indicators over the history rows */
    double min_pair_distance_over_dx, max_clumped_fraction, max_swegle_fraction;
    double first_unhealthy_time; /* s, < 0 while healthy */
    const char *unhealthy_reason;
    /* with a projectile (host/run.c) */
    int has_projectile;
    double max_penetration_m, time_of_max_penetration_s, final_penetration_m;
    double final_projectile_velocity_m_per_s; /* along the impact axis; negative: rebound */
    double max_cavity_diameter_m, max_damaged_diameter_m;
    double momentum_error; /* largest |p(t) - p(0)| / |p(0)| along the impact axis */
    double damaged_fraction;
    double left_fine_region_time_s; /* nose first in a graded body's coarse shells; < 0 never */
    double max_lateral_deflection_m, final_lateral_deflection_m; /* off the shot line */
    double exit_time_s; /* the sphere first through the target (perforated); < 0 never */
};

/* Creates the folder (and parents), writes case.resolved.yaml and opens
 * history.csv. Returns 0, or non-zero with a sentence in `error`. */
int output_open(struct output *o, const char *folder, const struct sph_case *c, int particles,
                char *error, size_t error_size);
int output_snapshot(struct output *o, const struct host_fields *f, const struct snapshot_meta *meta,
                    char *error, size_t error_size);
void output_history(struct output *o, const struct history_row *row);
/* ballistics.csv: opened when the case has a projectile. */
int output_ballistics_open(struct output *o, const struct projectile *p, char *error,
                           size_t error_size);
void output_ballistics(struct output *o, const struct ballistics_row *row);
int output_summary(struct output *o, const struct run_summary *s);
void output_close(struct output *o);

/* Checkpoints (host/checkpoint.h): the snapshot index, the walls' placement
 * and how long the CSV files were; output_resume reads them back (touching
 * no file: output_open's counterpart for `sph resume`) and, once the whole
 * checkpoint has loaded, output_resume_files cuts the CSV files back to
 * those lengths and opens them for appending. */
struct checkpoint;
void output_checkpoint_save(struct output *o, struct checkpoint *k);
int output_resume(struct output *o, const char *folder, const struct sph_case *c, int particles,
                  struct checkpoint *k, char *error, size_t error_size);
int output_resume_files(struct output *o, int with_ballistics, char *error, size_t error_size);

/* A file written through a temporary name (.NAME.tmp beside it) and renamed
 * when complete, so a full disk or a crash leaves the previous file, never
 * a truncated one: begin, write, commit (non-zero: not written, the
 * temporary removed). */
FILE *output_file_begin(const char *path, char *temporary, size_t size);
/* The temporary name alone, for writers that open the file themselves
 * (HDF5: snapshots, checkpoints). */
void output_temporary_name(const char *path, char *temporary, size_t size);
int output_file_commit(FILE *f, const char *temporary, const char *path);

/* mkdir -p */
int make_folders(const char *path);

#endif
