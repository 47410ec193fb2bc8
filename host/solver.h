/* The solver on the device: particle buffers (state.c) and the fixed list of
 * kernel launches of a step (step.c). Inside the time loop the host
 * enqueues kernels and reads back small reductions; its one loop over
 * particles is the symmetry planes' ghost list, rebuilt at re-sorts only
 * (host/ghost.c, solver_ghosts_rebuild). */
#ifndef SPH_SOLVER_H
#define SPH_SOLVER_H

#include "device.h"
#include "domain.h"
#include "scene.h"
#include "sph_case.h"

/* The neighbour grid's margin over the support: cells are support (1 +
 * skin) wide and the grid is re-sorted once a particle has moved skin / 2
 * supports. */
#define SPH_GRID_SKIN 0.2

/* Host evaluations of the device's smoothing kernels (kernels/smoothing.cl
 * compiled as C, see host/smoothing.c). */
double sph_support_q(int kernel);
double sph_kernel_w_host(int kernel, int dim, double r, double h);

/* Element kinds of the particle fields (sizes depend on dimension and
 * precision; see kernels/common.cl). */
enum element_kind { ELEM_REAL, ELEM_INT, ELEM_VEC, ELEM_SYMT, ELEM_FULLT, ELEM_COUNT };

/* Per-particle fields: one row each of the registry, field_table
 * (host/fields.c), which says everything the host does with a field. */
enum field {
    FIELD_POS,
    FIELD_POS0,
    FIELD_DISPLACEMENT,
    FIELD_VEL,
    FIELD_VEL_HALF,
    FIELD_DENSITY_CHANGE,
    FIELD_ENERGY,
    FIELD_STRESS,
    FIELD_PLASTIC_STRAIN,
    FIELD_TEMPERATURE,
    FIELD_MASS,
    FIELD_FLAGS,
    FIELD_MATERIAL,
    FIELD_ID,
    FIELD_RHO,
    FIELD_PRESSURE,
    FIELD_SOUND_SPEED, /* m/s, at the current density (kernels/material.cl) */
    FIELD_ARTIFICIAL_STRESS,
    FIELD_CSPH,
    FIELD_DEFORMATION_GRADIENT, /* total Lagrangian only */
    FIELD_FIRST_PIOLA,          /* total Lagrangian only: P C^T */
    FIELD_REFERENCE_OFFSET,     /* total Lagrangian only: reference minus initial position, m */
    FIELD_REFERENCE_DENSITY,    /* total Lagrangian only: density of the reference, kg/m^3 */
    FIELD_VELOCITY_GRADIENT,    /* the limited viscosity (pass 1 -> pass 2) */
    FIELD_AV_ALPHA,             /* the switch viscosity's alpha per particle */
    FIELD_AV_DIVERGENCE,        /* cullen_dehnen: the last step's div v, 1/s */
    FIELD_VISCOUS_STRESS,       /* the physical viscosity's part of deviatoric_stress */
    FIELD_SMOOTHING_METRIC, /* numerics.smoothing tensor: h0^2 M (kernels/tensor_smoothing.cl) */
    FIELD_SMOOTHING_REACH,  /* ... and its longest semi-axis over h0 (the lane lists' reach) */
    FIELD_ACCELERATION,
    FIELD_ENERGY_RATE,
    FIELD_VISCOUS_HEATING, /* W/kg: the artificial viscosity's part of energy_rate */
    FIELD_HOURGLASS_POWER, /* W/kg: total Lagrangian hourglass work rate (not heat) */
    FIELD_XSPH_VELOCITY,
    FIELD_WALL_FORCE,
    FIELD_COUNT
};

/* How a ghost's copy of a field relates to its source's (kernels/ghost.cl). */
enum mirror_kind { MIRROR_NONE, MIRROR_COPY, MIRROR_REFLECT, MIRROR_POSITION, MIRROR_FLAGS };

/* The configurations a field exists in (solver_configuration): a field is
 * used when its `used` mask shares a bit with the run's. */
enum field_use {
    USED_ALWAYS = 1 << 0,
    USED_TOTAL_LAGRANGIAN = 1 << 1,
    USED_CSPH = 1 << 2,
    USED_AV_LIMITED = 1 << 3,
    USED_AV_SWITCH = 1 << 4,
    USED_ARTIFICIAL_STRESS = 1 << 5,
    USED_WALLS = 1 << 6,
    USED_VISCOSITY = 1 << 7,
    USED_AV_CULLEN_DEHNEN = 1 << 8,
    USED_TENSOR_SMOOTHING = 1 << 9,
};

struct field_info {
    const char *name; /* what the field is, in words: memory breakdown, snapshot dataset */
    const char *arg;  /* the kernels' name for it: SET_ARGS binds the field by it */
    enum element_kind kind;
    /* read by some stage of a step before that step writes it: every sort
     * reorders it and a checkpoint holds it; the others are written before
     * they are read within a step */
    int persistent;
    unsigned used;           /* configurations it exists in (enum field_use) */
    unsigned read_across;    /* ... and those whose neighbour passes read it of a
                                neighbour j: symmetry ghosts (and halos) carry it */
    enum mirror_kind mirror; /* how a ghost's copy is made from its source */
    const char *units;       /* written to snapshots with these units; NULL: not written */
};
extern const struct field_info field_table[FIELD_COUNT];

struct grid {
    double origin[3];
    double cell_size; /* support * (1 + skin), m */
    int dims[3];
    cl_int4 dims4; /* dims as the kernels take them (grid_dims) */
    int cell_count;
    int cell_capacity;
};

/* Mirror particles of the symmetry planes (host/ghost.c). */
struct ghosts {
    int plane_count;
    int reflected[3]; /* 1 where a plane is normal to that axis */
    double plane[3];  /* its coordinate, m */
    double side[3];   /* +1 or -1: the side of the plane the real particles stay on */
    double width;     /* particles this close to a plane get images, m (times
                         solver_reach_scale on graded lattices) */
    int count;        /* ghosts in use */
    int capacity;     /* slots for ghosts in every field buffer */
    cl_mem source_id, mask, index_of_id;
    cl_kernel index_kernel, id_keys, init, refresh[ELEM_COUNT];
};

struct kernels {
    cl_kernel cell_keys, fill_int, cell_ranges, bounds;
    cl_kernel bucket_count, bucket_block_total, bucket_block_offsets, bucket_block_scan,
        bucket_scatter, bucket_order; /* the sort */
    cl_kernel gather[ELEM_COUNT], copy[ELEM_COUNT];
    cl_kernel pass1, pass2, kick, drift, reduce, neighbour_count;
    cl_kernel tl_correction, tl_deformation, tl_momentum, tl_reference_reset;
    cl_kernel health_pairs, health;
    cl_kernel projectile_contact, projectile_advance, projectile_cavity;
    cl_kernel neighbour_reach, cell_max_level, coarser_seed, coarser_spread,
        apply_reach;           /* graded */
    cl_kernel lane_list_build; /* the lane passes' candidate lists */
    cl_kernel contact_cell_keys, contact_cell_ranges, contact_cell_parts,
        tl_part_contact; /* total Lagrangian contact between parts */
};

/* The rigid projectile (host/ballistics.c, kernels/projectile.cl). */
struct projectile {
    int enabled;
    int prescribed;          /* held at its initial velocity (projectile.motion) */
    int no_slip;             /* projectile.contact: no_slip */
    cl_mem state;            /* SPH_PROJ_SLOTS reals */
    cl_mem contact_partials; /* SPH_CONTACT_SLOTS per reduce group */
    double radius, mass;     /* m, kg */
    double stiffness_speed;  /* m/s: the contact spring's wave speed */
    double scale;            /* particle sums to whole-model force */
    double mask[3];          /* 0 for components normal to a symmetry plane */
    double axis[3];          /* unit impact direction (initial velocity) */
    double origin[3];        /* initial centre: the track is origin + s axis */
    double surface;          /* where the track enters the target: x.axis of its face, m */
    double exit_face;        /* where it leaves the target's initial shape, m along axis */
    double momentum_scale;   /* particle momentum sums to whole-model momentum */
    double probe_spacing;
    int probe_count;
};

/* What the history reads of the projectile. */
struct projectile_reading {
    double position[3], velocity[3], force[3]; /* m, m/s, N */
    double contact_energy;                     /* J */
    double dissipated;                         /* work of the contact dampers so far, J */
    double driver_work;                        /* prescribed motion: work done holding it, J */
    double driver_impulse_along_axis;          /* prescribed motion: that force's impulse, N s */
    int contacts;
    double penetration;        /* nose depth below the surface along the axis, m */
    double speed_along_axis;   /* m/s, positive into the target */
    double lateral_deflection; /* centre's distance from the initial shot line, m */
    int through; /* the whole sphere is past the target's initial exit face on the track */
    double cavity_d1[SPH_MAX_CAVITY_PROBES], cavity_d2[SPH_MAX_CAVITY_PROBES]; /* m */
};

/* What the per-step reduction returns, combined in double. */
struct reduction {
    double max_signal, max_speed, max_drift_speed; /* m/s */
    long bad_id;                                   /* -1 when every particle is healthy */
    double load_power, kinetic, internal;
    double probe_displacement[3];
    double momentum[3];
    double
        wall_force[3]; /* on the particles from the walls, N (per m of thickness in 2-D: scaled) */
    double wall_power; /* wall forces . velocities, W */
    double viscous_power;   /* heating by the artificial viscosity (in `internal`), W */
    double hourglass_power; /* work rate the hourglass forces take out of the motion, W */
    double max_distortion;  /* total Lagrangian: largest |E| against the reference, 1 */
};

struct solver {
    struct sph_device *dev;
    int dim, n, double_precision;
    int n_real;   /* real particles (this rank's); n = n_real + domain.halo_count
                     + ghosts.count slots in use */
    int n_scene;  /* particles of the whole case (n_real on one process) */
    int capacity; /* slots in every field buffer */
    struct ghosts ghosts;
    struct domain domain;        /* MPI: this rank's box and halo (host/domain.c) */
    int total_lagrangian;        /* numerics.formulation; the grid is then sorted once */
    int part_contact;            /* bodies of different parts (bodies[].part) meet by contact */
    int graded;                  /* some body has a graded lattice (SPH_GRADED) */
    int coarsest_level;          /* of the graded bodies (solver_case_coarsest_level) */
    int lanes;                   /* particles per work-item of passes 1 and 2 (solver_lanes) */
    int lane_lists;              /* the lanes visit candidate lists (solver_uses_lane_lists) */
    int csph, artificial_stress; /* the corrections in use: their fields exist */
    int tensor_smoothing;        /* numerics.smoothing: tensor (kernels/tensor_smoothing.cl) */
    int viscosity;               /* some material has a physical viscosity */
    int av_scheme;               /* enum sph_av_scheme: its fields exist */
    double dx;                   /* lattice spacing, m */
    double dt_viscous;           /* the physical viscosity's time step limit, s */
    size_t element_size[ELEM_COUNT];
    cl_mem field[FIELD_COUNT];
    cl_mem gather_spare; /* one field of the largest element: the gather target */
    cl_mem sort_keys, cell_start, cell_end, partials, bounds_partials, materials, run_params;
    cl_mem cell_level;                      /* graded lattices: the coarsest level in each cell */
    cl_mem sort_buckets, sort_block_totals; /* the sort's counts (solver_sort_keys) */
    /* the total Lagrangian form's contact search on current positions, on
     * the reference grid's cells (kernels/contact_current.cl) */
    cl_mem contact_keys, contact_cell_start, contact_cell_end, contact_cell_part_bits;
    int sort_bucket_capacity;
    /* the lane passes' candidates: block b's are lane_list[range[2 b] ..
     * range[2 b + 1]) (solver_lane_lists_build); claim: the build's counters */
    cl_mem lane_list_range, lane_list, lane_list_claim;
    long lane_list_range_capacity, lane_list_claim_capacity,
        lane_list_capacity;    /* ints each has room for */
    long lane_list_entries;    /* entries of the last build */
    long sorts;                /* grid sorts by this process since it started */
    size_t lane_list_estimate; /* solver_lane_list_estimate of the case, B per particle */
    /* graded lattices, scratch of each sort: per cell, the levels L with a
     * coarser cell in the window a particle of level L searches (bit L) */
    cl_mem cell_coarser[2];
    cl_mem walls; /* struct sph_wall[wall_count] (at least one entry's worth) */
    int wall_count;
    int reduce_groups;
    struct grid grid;
    struct kernels k;
    struct sph_run_params run;
    double skin;             /* grid margin as a fraction of the support */
    double moved_since_sort; /* bound on any particle's drift since the last sort, m */
    /* ... since the total Lagrangian contact search (HUGE_VAL: none yet) */
    double moved_since_contact_search;
    /* total Lagrangian: the |E| that makes the current configuration the
     * reference (numerics.reference_update; 0 never), and how many times
     * this run has done so */
    double reference_update;
    long reference_updates;
    double thickness_scale; /* 2-D: thickness, so energies come out in J */
    int probe_count;
    struct projectile projectile;
};

/* The largest longitudinal sound speed over the case's materials, m/s. */
double solver_max_sound_speed(const struct sph_case *c);

/* Particles per work-item of passes 1 and 2 and of the total Lagrangian
 * form's tl_deformation and tl_momentum (kernels/lanes.cl): 1, the plain
 * loop, for numerics.neighbour_loop plain; SPH_LANES_DEFAULT elsewhere
 * (graded and axisymmetric lattices too). */
#define SPH_LANES_DEFAULT 8
int solver_lanes(const struct sph_case *c);
/* Whether the lane passes visit candidate lists (numerics.lane_lists) or
 * walk the cells (kernels/lanes.cl). */
int solver_uses_lane_lists(const struct sph_case *c);
/* The search reach over the isotropic support: SPH_TENSOR_AXIS_MAX with
 * numerics.smoothing tensor, else 1. */
double solver_reach_factor(const struct sph_case *c);
/* numerics.lane_lists auto: true, unless `particles` fit `device_bytes`
 * only without the lists (said on stderr unless quiet). */
void solver_choose_lane_lists(struct sph_case *c, double particles, double device_bytes, int quiet);
/* numerics.neighbour_loop auto: lanes on a CPU, plain on a GPU (whose
 * work-items want one particle each); the resolved case says which. */
void solver_choose_loop(struct sph_case *c, const struct sph_device *dev);
/* Whether some body of the case has a graded lattice (SPH_GRADED). */
int solver_case_graded(const struct sph_case *c);
/* (Re)makes the cell buffers of `bytes` each: cell ranges, and on graded
 * lattices the level scratch (host/step.c). */
void solver_make_cell_buffers(struct solver *s, size_t bytes);
/* The coarsest level of the case's graded bodies (spacing 2^level dx), 0 without. */
int solver_case_coarsest_level(const struct sph_case *c);
/* What a solver takes from the case before any buffer: dimension,
 * precision, the options that decide its fields, the element sizes. */
void solver_configure(struct solver *s, const struct sph_case *c);
/* solver_bytes_per_particle of the case, before a scene or a device
 * exists (the registry's fields in use). */
size_t solver_case_bytes_per_particle(const struct sph_case *c);
/* The lane lists' device memory per particle, estimated from the case
 * (0 without them). */
size_t solver_lane_list_estimate(const struct sph_case *c);
/* The error of a case that does not fit the device's memory: `bytes` for
 * `particles` of `per_particle` (an estimate before the scene is built),
 * and what to change. */
void solver_memory_error(const struct sph_case *c, const struct sph_device *dev, double bytes,
                         size_t per_particle, double particles, int estimate, char *error,
                         size_t size);
/* -D options for the program from the case. */
void solver_build_options(const struct sph_case *c, char *options, size_t size);

/* Creates buffers, uploads the scene and creates the kernels. Returns 0, or
 * non-zero with a sentence in `error` (e.g. not enough device memory). */
int solver_create(struct solver *s, struct sph_device *dev, const struct sph_case *c,
                  const struct sph_scene *scene, char *error, size_t error_size);
void solver_release(struct solver *s);

/* The run's configuration as enum field_use bits. */
unsigned solver_configuration(const struct solver *s);
/* Whether the formulation uses field f (others get a token buffer). */
int solver_field_used(const struct solver *s, enum field f);
/* Whether the ghosts must carry field f: a neighbour pass reads it of a
 * mirror particle (field_table's mirror kind, in use, and read across). */
int solver_field_mirrored(const struct solver *s, enum field f);
/* bytes per slot of the gather spare: the largest persistent field's element */
size_t solver_spare_element(const struct solver *s);

/* A device buffer of `bytes` (a failure is recorded, host/device.h), and
 * `count` device reals read back as doubles. */
cl_mem solver_create_buffer(struct solver *s, size_t bytes);
void solver_read_reals(struct solver *s, cl_mem m, size_t count, double *out);

/* Bytes of device memory per particle, over all per-particle buffers. */
size_t solver_bytes_per_particle(const struct solver *s);
/* The same, buffer by buffer (fields by name, the gather spare, the sort
 * keys); buffers this formulation does not use are left out. */
#define SOLVER_MAX_BUFFERS (FIELD_COUNT + 3) /* the fields, the gather spare, keys, lists */
struct solver_memory {
    int count;
    const char *name[SOLVER_MAX_BUFFERS];
    size_t bytes[SOLVER_MAX_BUFFERS]; /* per particle slot */
};
void solver_memory_breakdown(const struct solver *s, struct solver_memory *out);

/* Re-sorts particles by cell and rebuilds the cell ranges. Returns non-zero
 * with `error` when the particles spread over more cells than the device can
 * hold (a particle left the domain). */
int solver_sort(struct solver *s, char *error, size_t error_size);
/* Pressure, sound speed and artificial stress of the initial state (before
 * step 1 and its time step). */
void solver_prime(struct solver *s);
/* The next time step (s) from the last reduction's largest signal speed
 * (m/s): cfl h / max_signal, or the physical viscosity's limit when that is
 * smaller (case_viscous_time_step). */
double solver_time_step(const struct solver *s, double cfl, double max_signal);
/* One leap-frog step of the particles (see kernels/integrate.cl): pass 2,
 * the projectile's contact, kick, pass 1, material update, drift. `load`
 * is the force per loaded particle at t^n. */
void solver_step(struct solver *s, double dt, double dt_prev, const double load[3]);
void solver_reduce(struct solver *s, const double load[3], struct reduction *out);
/* A step as `sph run` and `sph bench` take it: re-sort when a particle may
 * have moved half the grid's skin since the last sort (moved_since_sort,
 * the sum of the steps' largest drift x dt), solver_step, the reduction
 * into `red` and the projectile's advance. Returns non-zero with `error`
 * when the sort fails. */
int solver_advance(struct solver *s, double dt, double dt_prev, const double load[3],
                   struct reduction *red, char *error, size_t error_size);

/* Host copies of the fields a snapshot writes (field_table's units) and of
 * what is derived from them for output, in the scene's particle order.
 * Vectors have 3 components (z = 0 in 2-D), symmetric tensors 6 in
 * ParaView's Tensor6 order (XX, YY, ZZ, XY, YZ, XZ). One process, or
 * several that gather: every particle, row = id. Several writing
 * collectively (parallel HDF5): `distributed`, this rank's particles only,
 * rows in ascending scene index `id[row]`; whatever is measured on them
 * is reduced over the ranks. */
enum derived_output {
    DERIVED_STRESS,
    DERIVED_VON_MISES,
    DERIVED_SMOOTHING_LENGTH,
    DERIVED_PART,
    DERIVED_COUNT
};
#define HOST_COLUMNS                                                                               \
    (FIELD_COUNT + DERIVED_COUNT) /* column f: field f; FIELD_COUNT + d: derived d */
struct host_column {
    const char *name, *units; /* units NULL: read for a derived column, not written */
    int components, is_int;
    void *data; /* NULL: not read (not written, or not used by this formulation) */
};
struct host_fields {
    int n;           /* rows held here */
    int n_total;     /* particles of the whole case */
    int distributed; /* rows are this rank's share */
    int *id;         /* scene index of each row; NULL when row = id */
    struct host_column column[HOST_COLUMNS];
};
#define HOST_REALS(fields, f) ((const double *)(fields)->column[f].data)
#define HOST_INTS(fields, f) ((const int *)(fields)->column[f].data)
int solver_read_fields(struct solver *s, struct host_fields *out);

/* Symmetry-plane ghosts (host/ghost.c). solver_ghosts_setup sizes them from
 * the scene before the buffers exist; solver_ghosts_rebuild regenerates
 * them (compaction, images, first copy) before a cell sort and
 * solver_ghosts_reindex maps ids to slots after it; solver_ghosts_refresh
 * copies the fields listed (or all mirrored fields when fields is NULL). */
void solver_ghosts_setup(struct solver *s, const struct sph_case *c, const struct sph_scene *scene);
void solver_ghosts_create(struct solver *s);
int solver_ghosts_rebuild(struct solver *s, char *error, size_t error_size);
void solver_ghosts_reindex(struct solver *s);
void solver_ghosts_refresh(struct solver *s, const enum field *fields, int count);
void solver_ghosts_release(struct solver *s);
/* Puts every slot in id order: reals in slots 0 .. n_real - 1. */
void solver_compact(struct solver *s);
/* A particle's pair reach over the support (1 + skin), from its flags:
 * 1, or 1.5 x 2^level on graded lattices. */
double solver_reach_scale(const struct solver *s, int flags);

/* One case over many processes (host/domain.c). solver_domain_setup cuts
 * the domains and selects this rank's particles of the scene into `local`
 * (they come first, then those of its initial halo); solver_domain_size
 * makes room after the mirrors' set-up; solver_domain_exchange migrates
 * particles and rebuilds the halo at a re-sort; solver_domain_refresh
 * copies fields into the halo (solver_ghosts_refresh calls it);
 * solver_domain_reduce makes a step's reduction global (with the
 * projectile's SPH_CONTACT_SLOTS contact sums in the same Allreduce when
 * `contact` is not NULL); solver_domain_rows
 * turns slot ids into scene indices (-1: not a real of this rank). */
int solver_domain_setup(struct solver *s, const struct sph_scene *scene, struct sph_scene *local,
                        char *error, size_t error_size);
void solver_domain_size(struct solver *s);
void solver_domain_create(struct solver *s);
void solver_domain_release(struct solver *s);
int solver_domain_exchange(struct solver *s, char *error, size_t error_size);
void solver_domain_refresh(struct solver *s, const enum field *fields, int count);
void solver_domain_reduce(const struct solver *s, struct reduction *r, double *contact);
void solver_domain_rows(const struct solver *s, int *row_of_slot, int n);
/* Means over the ranks (collective): halo particles now, and bytes each
 * rank's halo refreshes sent over the run. */
void solver_domain_figures(const struct solver *s, double *halo_particles, double *halo_bytes);

/* The rigid projectile (host/ballistics.c): set-up from the case and the
 * scene, the two launches of a step (the advance after the step's
 * reduction, so that over several processes the contact sums ride in its
 * Allreduce: solver_projectile_sums reads this rank's, _share writes the
 * whole model's back), and the history's reading. */
int solver_projectile_create(struct solver *s, const struct sph_case *c,
                             const struct sph_scene *scene, char *error, size_t error_size);
void solver_projectile_contact(struct solver *s, double dt, double dt_prev);
void solver_projectile_sums(struct solver *s, double sum[SPH_CONTACT_SLOTS]);
void solver_projectile_share(struct solver *s, const double sum[SPH_CONTACT_SLOTS]);
void solver_projectile_advance(struct solver *s, double dt, double dt_prev);
void solver_projectile_read(struct solver *s, struct projectile_reading *out);
/* Centre (m) and velocity (m/s) only, without the cavity probes. */
void solver_projectile_motion(struct solver *s, double centre[3], double velocity[3]);
void solver_projectile_release(struct solver *s);
/* Before any device work: the sphere must not overlap the target at t = 0. */
int projectile_check_scene(const struct sph_case *c, const struct sph_scene *scene, char *error,
                           size_t error_size);

/* Shared launch helpers (host/launch.c). */
void solver_launch(struct solver *s, cl_kernel k, size_t global, size_t local);
/* The kernels a module owns, listed once for making and releasing them:
 * where the handle lives and the kernel's name (NULL: not used in this
 * configuration; the handle stays NULL). per_element: a family of one
 * kernel per element kind, name_real .. name_fullt, into kernel[0 ..
 * ELEM_COUNT - 1]. */
struct kernel_slot {
    cl_kernel *kernel;
    const char *name;
    int per_element;
};
/* Makes (make != 0) or releases the kernels of a slot list. */
void solver_kernels(struct solver *s, const struct kernel_slot *slots, int count, int make);
/* Releases a buffer (if any) and clears its handle. */
void solver_release_buffer(cl_mem *m);
/* Sorts `keys` (n of them: sort_keys, or the contact search's) by their
 * high half, every one below `buckets`, then the slot (kernels/grid.cl,
 * counting sort). */
void solver_sort_keys(struct solver *s, cl_mem keys, int buckets);
/* counts[0 .. count) to their exclusive prefix sum, in blocks of
 * SPH_SCAN_BLOCK (kernels/grid.cl); block_totals holds count /
 * SPH_SCAN_BLOCK + 1 ints. */
void solver_exclusive_scan(struct solver *s, cl_mem counts, int count, cl_mem block_totals);
void solver_gather_persistent(struct solver *s);
/* The lane passes' candidate lists (kernels/lanes.cl, lane_list_build) for
 * the grid of the last sort, or a checkpoint's; token buffers for the
 * plain loop, which walks the cells. */
void solver_lane_lists_build(struct solver *s);
/* Work-items of the lane passes: particle slots over SPH_LANES, rounded up. */
long solver_lane_blocks(const struct solver *s);
/* The lane lists' device memory as allocated, B (0 without them). */
size_t solver_lane_list_bytes(const struct solver *s);

/* Health indicators (kernels/health.cl: health_pairs, health_indicators) over the real,
 * free particles. */
struct health_reading {
    double min_pair_distance; /* m */
    double clumped_fraction;  /* particles with a neighbour closer than dx / 2 */
    double swegle_fraction;   /* particles whose nearest pair has W'' sigma_n > 0 */
    double neighbours_min, neighbours_mean, neighbours_max;
};
void solver_health(struct solver *s, struct health_reading *out);

/* Neighbours within the support per particle, in original order (by id).
 * Total Lagrangian form: its reference neighbours not torn apart, or with
 * reference_baseline every reference neighbour (kernels/health.cl). */
void solver_neighbour_counts(struct solver *s, int *count_by_id, int reference_baseline);
void host_fields_free(struct host_fields *f);

#endif
