/*
 * A validated case: what a case file (YAML) says, with every default filled
 * in, in SI units. Produced by case_load(); read by the scene builder, the
 * device layer and the run loop.
 */
#ifndef SPH_CASE_H
#define SPH_CASE_H

#include <stdio.h>

#include "sph_shared.h"

#define SPH_NAME_MAX 64
#define SPH_PATH_MAX 1024
#define SPH_MAX_MATERIALS 8
#define SPH_MAX_BODIES 16
#define SPH_MAX_WALLS 4
#define SPH_MAX_SETS 64
#define SPH_ERROR_MAX 1024

enum sph_plane_mode { SPH_PLANE_STRESS = 0, SPH_PLANE_STRAIN = 1, SPH_PLANE_AXISYMMETRIC = 2 };

enum sph_load_law {
    SPH_LOAD_CONSTANT = 0,       /* F(t) = F */
    SPH_LOAD_LINEAR_RAMP = 1,    /* F t / t_ramp until t_ramp, then F */
    SPH_LOAD_QUADRATIC_RAMP = 2, /* F (t / t_ramp)^2 until t_ramp, then F */
};

/* Passes 1 and 2: 8 particles per work-item (lanes, for CPUs), one (plain,
 * for GPUs), or by the device (auto: solver_choose_loop, host/state.c). */
enum sph_neighbour_loop { SPH_LOOP_LANES = 0, SPH_LOOP_PLAIN = 1, SPH_LOOP_AUTO = 2 };

enum sph_shape { SPH_SHAPE_BOX = 0, SPH_SHAPE_CYLINDER = 1 };

/* When a particle fails (kernels/material.cl): never, at first yield (the
 * thesis' soft-tissue criterion, 4.3.2), or past an equivalent plastic
 * strain. A failed particle carries no deviatoric stress and no tension. */
enum sph_failure { SPH_FAILURE_NONE = 0, SPH_FAILURE_YIELD = 1, SPH_FAILURE_PLASTIC_STRAIN = 2 };

enum sph_probe_quantity {
    SPH_PROBE_DISPLACEMENT_X = 0,
    SPH_PROBE_DISPLACEMENT_Y = 1,
    SPH_PROBE_DISPLACEMENT_Z = 2
};

/* Parameters of the Mie-Gruneisen and polynomial EOS (kernels/material_models.cl). */
struct case_eos_parameters {
    int enabled;   /* the map was given */
    double c0;     /* m/s, required */
    double s;      /* Hugoniot slope, required */
    double gamma0; /* Gruneisen Gamma0, required for mie_gruneisen, default 0 for polynomial */
    double p0;     /* Pa, polynomial only, default 0 */
};

struct case_johnson_cook {
    int enabled;
    double b, n;             /* hardening B (Pa) and n, required */
    double c;                /* strain-rate C, default 0 */
    double reference_rate;   /* 1/s, default 1 */
    double m;                /* thermal softening exponent, default 0 (off) */
    double melt_temperature; /* K, required when m > 0 */
};

struct case_material {
    char name[SPH_NAME_MAX];
    double density;        /* kg/m^3, > 0, required */
    double youngs_modulus; /* Pa, > 0, required */
    double poisson_ratio;  /* (-1, 0.5), required */
    enum sph_eos_type eos; /* "linear" (default), "mie_gruneisen", "polynomial" */
    struct case_eos_parameters mie_gruneisen, polynomial;
    enum sph_strength_type strength; /* "elastic" (default), "perfectly_plastic", "johnson_cook" */
    double yield_stress;             /* Pa (Johnson-Cook A), required unless elastic */
    struct case_johnson_cook johnson_cook;
    double room_temperature;    /* K, initial temperature, default 293 */
    double heat_capacity;       /* J/(kg K), required for johnson_cook */
    double taylor_quinney;      /* fraction of plastic work that heats, default 0.9 */
    enum sph_failure failure;   /* default none */
    double failure_strain;      /* required with failure plastic_strain */
    double viscosity;           /* Pa s, Newtonian shear viscosity, default 0 (none) */
    double cavitation_pressure; /* Pa, tension a failed particle carries, default 0 */
    double failure_stretch;     /* rho0/rho - 1 at which a particle fails, default 0 (never) */
};

/* A region: an axis-aligned box [min, max] (m). In 2-D the z entries are 0. */
struct case_box {
    double min[3];
    double max[3];
};

/* The most --set overrides a command takes (sph run, check, bench). */
#define CASE_MAX_SETS 128

struct case_load {
    int enabled;
    double force[3];       /* total force on the group, N; divided evenly */
    enum sph_load_law law; /* default constant */
    double ramp_time;      /* s, > 0 for ramps */
};

struct case_body {
    char name[SPH_NAME_MAX];
    int material;         /* index into case.materials */
    enum sph_shape shape; /* "box" or "cylinder" (the box cut to a cylinder; a disk in 2-D) */
    struct case_box box;  /* the shape's extent; filled on a lattice of numerics.dx */
    int axis;             /* cylinder axis: 0 x, 1 y, 2 z (default; the only one in 2-D) */
    double radius;        /* cylinder radius, m */
    double inner_radius;  /* hollow cylinder (tube, ring), m, default 0 */
    double centre[3];     /* a point of the axis, m; default the box centre */
    int has_centre;
    int fixed; /* every particle of the body has zero velocity */
    /* 0-255, default 0: bodies of one part are one continuum where they
     * touch (a clamp and its beam); bodies of different parts meet by
     * contact only, push without pulling and can part (colliding rings) */
    int part;
    double velocity[3]; /* initial velocity, m/s, default 0 */
    /* initial velocity gradient G, 1/s, row-major (dv_x/dx, dv_x/dy,
     * dv_x/dz, dv_y/dx, ...): a particle at x starts at velocity +
     * G (x - centre); default 0 */
    double velocity_gradient[9];
    /* Graded lattice (host/scene.c): spacing dx inside the fine box, then
     * shells of `layers` particles at 2 dx, 4 dx, ... up to 2^levels dx,
     * which fills the rest of the body. */
    struct case_grading {
        int enabled;
        struct case_box fine; /* the finest region, m (the box form) */
        /* the track form: the finest region is every point within track_radius
         * of the segment track_from - track_to (m); the shells follow it */
        double track_from[3], track_to[3], track_radius;
        int layers; /* particle layers per shell, default 6 */
        int levels; /* coarsest level k (spacing 2^k dx), default 3 */
    } grading;
};

/* A rigid sphere shot into the target (kernels/projectile.cl), with the
 * ballistic outputs: penetration, velocity, force, cavity diameters at
 * probe depths along the track (host/ballistics.c). */
struct case_projectile {
    int enabled;
    double diameter;             /* m, required */
    double density;              /* kg/m^3, required */
    double centre[3];            /* initial centre, m, required */
    double velocity[3];          /* initial velocity, m/s, required (not zero) */
    double cavity_probe_spacing; /* m, default the diameter */
    int cavity_probe_count;      /* probe depths k spacing, k = 1..count; default 8 */
    int prescribed;              /* motion: 0 free (default), 1 held at `velocity` */
    int no_slip;                 /* contact: 0 free_slip (default), 1 no_slip */
    int boundary_integral;       /* boundary: 0 penalty (default), 1 integral */
    int embedded;                /* start inside the target: its particles there are removed */
};

/* A named group of particles: those of `body` (or any body if body < 0)
 * whose initial position lies inside `region`. */
struct case_group {
    char name[SPH_NAME_MAX];
    int body;
    struct case_box region;
    int fixed;
    struct case_load load;
};

/* numerics.artificial_viscosity.scheme */
enum sph_av_scheme {
    SPH_AV_MONAGHAN = 0,     /* the pair's velocity difference (Monaghan 1992) */
    SPH_AV_LIMITED = 1,      /* the limited linear reconstruction of the jump (pass2.cl) */
    SPH_AV_SWITCH = 2,       /* per-particle alpha driven by compression (material.cl) */
    SPH_AV_CULLEN_DEHNEN = 3 /* per-particle alpha driven by the rate of compression */
};

#define SPH_LANE_LISTS_AUTO 2 /* numerics.lane_lists: auto */

struct case_numerics {
    double dx;                   /* lattice spacing, m, required */
    enum sph_kernel_type kernel; /* default wendland_c2 */
    double h_over_dx;            /* default 1.2 */
    double av_alpha, av_beta;    /* default 1.5, 1.5 (the one numerics block) */
    int av_scheme;               /* enum sph_av_scheme, default switch */
    double av_alpha_min;         /* switch: the floor alpha decays to, default 0.1 */
    int av_balsara;              /* the floor times Balsara's factor (material.cl), default 0 */
    double as_epsilon;           /* default 0 (off) */
    int as_exponent;             /* default 4 */
    int as_lattice_weight;       /* weight: 0 relative (default), 1 lattice (Monaghan 2000) */
    double xsph_epsilon;         /* default 0 (off) */
    int csph;                    /* default 0 */
    int tensor_smoothing;        /* smoothing: 0 isotropic (default), 1 tensor (an ellipsoid per
                                    particle, kernels/tensor_smoothing.cl) */
    int total_lagrangian;        /* formulation: 0 updated_lagrangian (default), 1 total */
    double hourglass;            /* total Lagrangian hourglass control coefficient, default 0.1 */
    double reference_update;     /* total Lagrangian: the Green strain |E| at which the current
                                    configuration becomes the reference; 0 never (default) */
    double cfl;                  /* default 0.3 */
    double end_time;             /* s, required */
    double damping;              /* 1/s, default 0 */
    int double_precision;        /* default 0 */
    int neighbour_loop; /* enum sph_neighbour_loop; auto (default) is resolved for the device */
    int lane_lists;     /* lanes: candidate lists per block (kernels/lanes.cl): 0 false, 1 true,
                           SPH_LANE_LISTS_AUTO (default: true where the case fits with them) */
};

/* A rigid plane: particles stay on the side the normal points to, their
 * centres at least dx/2 from the plane (kernels/integrate.cl). */
struct case_wall {
    char name[SPH_NAME_MAX];
    double point[3];  /* m, a point of the plane (Taylor summary: where the bar's axis meets it) */
    double normal[3]; /* towards the material; normalised on load */
    double friction;  /* Coulomb coefficient, default 0 (frictionless) */
    int hold;         /* the body's face stays on the plane, free to slide along it: a
                         symmetry plane stands in for the wall (host/case.c, held_walls) */
};

/* A symmetry plane normal to a coordinate axis: mirror-image (ghost)
 * particles stand in for the material beyond it (host/ghost.c). */
struct case_symmetry {
    int axis;        /* 0 x, 1 y, 2 z */
    double position; /* the plane's coordinate on that axis, m, default 0 */
};

/* Snapshots a run may write (the XDMF index lists them all); history rows
 * and checkpoints are bounded alike (host/case.c check_output). */
#define SPH_MAX_SNAPSHOTS 100000
#define SPH_MAX_HISTORY_ROWS 10000000

struct case_output {
    double snapshot_interval;        /* s; default end_time / 20 */
    double history_interval;         /* s; default end_time / 1000 */
    double checkpoint_interval;      /* s of simulated time between checkpoints; 0: none */
    double checkpoint_wall_interval; /* s of wall-clock time between checkpoints; 0: none */
};

/* Thresholds past which a run is marked unhealthy (host/run.c). */
struct case_health {
    double min_pair_distance; /* over dx; default 0 (off) */
    double clumped_fraction;  /* default 0.01, 0.001 in the total Lagrangian form */
    double energy_error;      /* default 0.05; undamped runs only */
    int stop;                 /* stop the run when unhealthy; default false */
};

struct case_probe {
    char name[SPH_NAME_MAX]; /* column name in history.csv */
    int group;               /* index into case.groups */
    enum sph_probe_quantity quantity;
};

/* What the summary compares the probe to. */
struct case_reference {
    int enabled;
    double value;     /* the reference value of the probe, m */
    double window[2]; /* time window (s) over which the mean is taken */
    char source[SPH_NAME_MAX * 2];
};

struct sph_case {
    char path[SPH_PATH_MAX];
    char name[SPH_NAME_MAX];
    int dimension;             /* 2 or 3 */
    enum sph_plane_mode plane; /* 2-D only; default stress */
    double thickness;          /* 2-D out-of-plane thickness, m; default 1 */
    int material_count;
    struct case_material materials[SPH_MAX_MATERIALS];
    int body_count;
    struct case_body bodies[SPH_MAX_BODIES];
    int group_count;
    struct case_wall walls[SPH_MAX_WALLS];
    int wall_count;
    struct case_symmetry symmetry[3];
    int symmetry_count;
    struct case_health health;
    struct case_group groups[SPH_MAX_BODIES];
    struct case_numerics numerics;
    struct case_output output;
    int has_probe;
    struct case_probe probe;
    struct case_reference reference;
    struct case_projectile projectile;
};

/* Loads and validates `path`, then applies `set_count` overrides of the form
 * "key.path=value" (e.g. "numerics.dx=0.5e-3", "materials.0.density=7850",
 * "bodies.beam.max=[0.1, 0.005]"). On failure returns non-zero and writes one
 * sentence into `error` naming the file, the line and what was expected. */
int case_load(const char *path, int set_count, char *const *sets, struct sph_case *out, char *error,
              size_t error_size);

/* Writes the resolved case (every default filled in) as YAML that case_load
 * accepts. */
int case_write_resolved(const struct sph_case *c, FILE *f);
/* The same text in memory (malloc'd, `length` bytes), or NULL when out of
 * memory. A checkpoint holds it; `sph resume` compares it with the reloaded
 * case's. */
char *case_resolved_text(const struct sph_case *c, size_t *length);

/* A material's longitudinal sound speed at its reference density, from its
 * EOS's bulk modulus and its shear modulus, m/s (case_load refuses a
 * material where it is not positive and finite). */
double case_material_sound_speed(const struct case_material *m);
/* Whether some material has a physical viscosity (materials[].viscosity). */
int case_has_viscosity(const struct sph_case *c);
/* Whether two bodies are of different parts (bodies[].part): they then
 * meet by contact (kernels/pass2.cl, SPH_PART_CONTACT). */
int case_has_part_contact(const struct sph_case *c);
/* Prints a note for every two bodies of one part that start at different
 * velocities: they weld where they meet (in the total Lagrangian form they
 * pass through each other), which is rarely what was meant. */
void case_note_welding(const struct sph_case *c, FILE *out);
/* The coordinate axis a wall's normal lies along (0-2), -1 if none. */
int case_wall_axis(const struct case_wall *w);
/* Bit a set when a held wall's normal lies along axis a. */
unsigned case_held_wall_axes(const struct sph_case *c);
/* The explicit time step's limit from the physical viscosity for a smoothing
 * length h (m): 0.125 h^2 min(rho0 / eta) (Morris, Fox & Zhu 1997, J.
 * Comput. Phys. 136:214, their viscous step limit), s; HUGE_VAL without
 * viscosity. */
double case_viscous_time_step(const struct sph_case *c, double h);
/* The fastest initial body speed (and the projectile's, with_projectile),
 * m/s. */
double case_fastest_speed(const struct sph_case *c, int with_projectile);

const char *case_kernel_name(enum sph_kernel_type k);

#endif /* SPH_CASE_H */
