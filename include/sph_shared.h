/*
 * Layouts shared by the host (C11) and the device (OpenCL C 1.2).
 *
 * This header is the one source of truth for every struct and enum that
 * crosses the host/device boundary. It compiles both ways: the host sees
 * cl_* types, the device sees the native ones. Every struct holds only
 * 4-byte (float build) or 8-byte (double build) scalars and int, so host
 * and device layouts agree without packing pragmas.
 */
#ifndef SPH_SHARED_H
#define SPH_SHARED_H

#if defined(__OPENCL_VERSION__) || defined(__OPENCL_C_VERSION__)
#ifdef SPH_DOUBLE
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
typedef double real;
#else
typedef float real;
#endif
typedef int sph_int;
#else
#include <CL/cl.h>
#ifdef SPH_DOUBLE
typedef cl_double real;
#else
typedef cl_float real;
#endif
typedef cl_int sph_int;
#endif

/* Smoothing kernels (thesis Fig. 3.1, REFERENCES.md 4). Values are the -D
 * SPH_KERNEL numbers the program is built with. */
enum sph_kernel_type {
    SPH_KERNEL_CUBIC_SPLINE = 0,
    SPH_KERNEL_GAUSSIAN = 1,
    SPH_KERNEL_QUINTIC_SPLINE = 2,
    SPH_KERNEL_WENDLAND_C2 = 3,
    SPH_KERNEL_DOUBLE_COSINE = 4,
    SPH_KERNEL_HYPERBOLIC = 5,
    SPH_KERNEL_COUNT = 6
};

enum sph_eos_type { SPH_EOS_LINEAR = 0, SPH_EOS_MIE_GRUNEISEN = 1, SPH_EOS_POLYNOMIAL = 2 };

enum sph_strength_type {
    SPH_STRENGTH_ELASTIC = 0,
    SPH_STRENGTH_PERFECTLY_PLASTIC = 1,
    SPH_STRENGTH_JOHNSON_COOK = 2
};

/* Per-particle flag bits (the `flags` buffer). */
enum sph_flag {
    SPH_FLAG_FIXED = 1,   /* velocity held at zero: clamps */
    SPH_FLAG_LOADED = 2,  /* carries the time-law external force */
    SPH_FLAG_PROBE = 4,   /* member of the probe group (mean displacement) */
    SPH_FLAG_DAMAGED = 8, /* failed: no deviatoric stress, no tension */
    SPH_FLAG_BAD = 16,    /* NaN or runaway velocity seen here */
    SPH_FLAG_GHOST = 32   /* mirror image (symmetry planes) or MPI halo particle: not integrated */
};

/* Buckets per block of the sort's prefix sum (kernels/grid.cl,
 * host/launch.c solver_sort_keys). */
#define SPH_SCAN_BLOCK 256

/* Graded lattices (host/scene.c): bits 8-11 of a particle's flags hold its
 * spacing level k (spacing 2^k numerics.dx, smoothing length 2^k h) and
 * bits 12-19 how many grid cells its neighbour search reaches
 * (SPH_GRID_SPLIT on a uniform lattice). */
#define SPH_LEVEL_SHIFT 8
#define SPH_LEVEL_MASK 15
#define SPH_LEVEL_OF(flags) (((flags) >> SPH_LEVEL_SHIFT) & SPH_LEVEL_MASK)
/* Grid cells per support (1 + skin): a particle on a uniform lattice
 * searches SPH_GRID_SPLIT cells each way. Finer cells test fewer
 * candidates per neighbour (3-D, by volume: ((2 s + 1) 1.2 / s)^3 / (4 pi / 3)
 * for split s: 11 at 1, 6.4 at 2, 5.2 at 3) for
 * more cell lookups and, in the lane passes, wider boxes around a lane
 * block; measured on the 3-D Taylor bar, 1 is as fast as 2 and faster than
 * 3 (docs/performance.md). */
#define SPH_GRID_SPLIT 1
/* numerics.smoothing tensor: the longest semi-axis of a particle's kernel
 * over h0, so the search reaches this many isotropic supports
 * (kernels/tensor_smoothing.cl; 2.5: the copper Taylor face's in-plane
 * stretch reaches about 2.2, docs/design_asph.md) */
#define SPH_TENSOR_AXIS_MAX 2.5
#define SPH_REACH_SHIFT 12
#define SPH_REACH_MASK 255
/* Bits 20-27: the particle's part (bodies[].part). Bodies of one part are
 * one continuum where they touch; particles of different parts meet by
 * contact only (kernels/pass2.cl, SPH_PART_CONTACT). */
#define SPH_PART_SHIFT 20
#define SPH_PART_MASK 255
#define SPH_PART_OF(flags) (((flags) >> SPH_PART_SHIFT) & SPH_PART_MASK)
/* The flag bits a ghost (mirror image or MPI halo particle) keeps of its
 * source: what a neighbour reads of it (spacing level, search reach, part,
 * damage); it gets SPH_FLAG_GHOST besides. */
#define SPH_GHOST_KEEP_FLAGS                                                                       \
    ((SPH_LEVEL_MASK << SPH_LEVEL_SHIFT) | (SPH_REACH_MASK << SPH_REACH_SHIFT) |                   \
     (SPH_PART_MASK << SPH_PART_SHIFT) | SPH_FLAG_DAMAGED)

/* The rigid projectile (a sphere; kernels/projectile.cl): its state on the
 * device, one real per slot. Position and velocity are the leap-frog's
 * (x^n, v^(n-1/2)); force and contact energy are those of the last step. */
enum sph_projectile_slot {
    SPH_PROJ_X = 0,               /* centre, m (x, y, z) */
    SPH_PROJ_V = 3,               /* velocity, m/s */
    SPH_PROJ_F = 6,               /* force of the target on the sphere, N (whole model) */
    SPH_PROJ_CONTACT_ENERGY = 9,  /* energy stored in the contact springs, J */
    SPH_PROJ_CONTACTS = 10,       /* particles in contact */
    SPH_PROJ_DISSIPATED = 11,     /* work of the contact dampers since t = 0, J */
    SPH_PROJ_DRIVER_WORK = 12,    /* prescribed motion: work of the force holding it, J */
    SPH_PROJ_DRIVER_IMPULSE = 13, /* prescribed motion: impulse of that force, N s (x, y, z) */
    SPH_PROJ_SLOTS = 16
};
/* Per-work-group partials of the contact kernel. */
enum sph_contact_slot {
    SPH_CONTACT_FX = 0, /* sum of contact forces on the particles, N (per m or radian in 2-D) */
    SPH_CONTACT_ENERGY = 3,
    SPH_CONTACT_COUNT = 4,
    SPH_CONTACT_DISSIPATION = 5, /* power of the contact dampers, W (per m or radian) */
    SPH_CONTACT_SLOTS = 8
};
/* Cavity probes (kernels/projectile.cl, projectile_cavity): per probe
 * depth, the smallest distance of any particle from the track and the
 * largest of a damaged one. */
#define SPH_MAX_CAVITY_PROBES 8

/* Material constants, SI units, one entry per material, indexed by the
 * particle's material id. The real members are listed once, here, so that
 * the host can build the same layout in double for a double-precision
 * device build (host/state.c):
 *   density            rho0, kg/m^3
 *   bulk_modulus       K, Pa: linear EOS p = K (rho/rho0 - 1)
 *   shear_modulus      G, Pa
 *   sound_speed        longitudinal wave speed sqrt((K0 + 4G/3)/rho0), m/s,
 *                      K0 the EOS's bulk modulus at rho0
 *   yield_stress       sigma_y (perfectly plastic) or Johnson-Cook A, Pa
 *   hardening_b        Johnson-Cook B, Pa
 *   hardening_n        Johnson-Cook n
 *   plane_stress_nu    nu/(1 - nu): eps_zz rate factor in plane stress
 *   eos_c0, eos_s      Mie-Gruneisen / polynomial C (m/s) and S
 *   eos_gamma0         Gruneisen Gamma0
 *   eos_p0             polynomial EOS p0, Pa
 *   jc_rate_c          Johnson-Cook C
 *   jc_reference_rate  Johnson-Cook reference strain rate, 1/s
 *   jc_thermal_m       Johnson-Cook m (0: no thermal softening)
 *   melt_temperature   T_melt, K
 *   room_temperature   T_room (initial temperature), K
 *   heat_capacity      c_p, J/(kg K)
 *   taylor_quinney     fraction of plastic work that heats
 *   failure_strain     equivalent plastic strain past which the particle
 *                      fails (0: at first yield, the thesis' soft-tissue
 *                      criterion); negative: no failure
 *   viscosity          Newtonian shear viscosity eta, Pa s: the deviatoric
 *                      stress carries 2 eta D' on top of the elastic part
 *                      (kernels/material.cl); 0: none
 *   cavitation_pressure  the most tension a failed particle carries, Pa
 *                      (kernels/material.cl, failed_pressure)
 *   failure_stretch    volumetric stretch rho0/rho - 1 past which a particle
 *                      fails whatever its plastic strain; 0: never */
/* clang-format off */
#define SPH_MATERIAL_REALS(X)                                                                      \
    X(density) X(bulk_modulus) X(shear_modulus) X(sound_speed) X(yield_stress) X(hardening_b)     \
    X(hardening_n) X(plane_stress_nu) X(eos_c0) X(eos_s) X(eos_gamma0) X(eos_p0) X(jc_rate_c)     \
    X(jc_reference_rate) X(jc_thermal_m) X(melt_temperature) X(room_temperature)                  \
    X(heat_capacity) X(taylor_quinney) X(failure_strain) X(viscosity) X(cavitation_pressure) X(failure_stretch)
/* clang-format on */
#define SPH_DECLARE_REAL(name) real name;
struct sph_material {
    SPH_MATERIAL_REALS(SPH_DECLARE_REAL)
    sph_int eos;      /* enum sph_eos_type */
    sph_int strength; /* enum sph_strength_type */
    sph_int pad0, pad1;
};

/* A rigid wall (plane) as the kick sees it: point and unit normal (towards
 * the material), Coulomb friction coefficient, and the distance from the
 * plane below which a particle centre is pushed back (dx / 2, m). */
/* clang-format off */
#define SPH_WALL_REALS(X)                                                                          \
    X(point_x) X(point_y) X(point_z) X(normal_x) X(normal_y) X(normal_z) X(friction) X(gap)
/* clang-format on */
struct sph_wall {
    SPH_WALL_REALS(SPH_DECLARE_REAL)
};

/* Run constants that do not change during a run. */
struct sph_run_params {
    real h;              /* smoothing length, m */
    real support;        /* kernel support radius kappa h, m */
    real av_alpha;       /* Monaghan artificial viscosity alpha */
    real av_beta;        /* Monaghan artificial viscosity beta */
    real av_eta_crit;    /* limited viscosity: pair distance / h below which the
                            reconstruction fades out, dx / h (kernels/pass2.cl) */
    real av_alpha_min;   /* switch viscosity: the alpha it decays to (kernels/pass1.cl) */
    real as_epsilon;     /* Monaghan-Gray artificial stress epsilon */
    real as_inv_w_dx;    /* 1 / W(dx, h): normalises f_ij = W(r)/W(dx) */
    real xsph_epsilon;   /* XSPH velocity smoothing factor */
    real damping;        /* velocity damping for quasi-static runs, 1/s */
    real thickness;      /* out-of-plane thickness in 2-D, m */
    real velocity_limit; /* |v| above this marks a particle bad, m/s */
    real hourglass;      /* total Lagrangian hourglass control coefficient alpha */
    real axis_radius;    /* axisymmetric: smallest radius the 1/r terms use, dx / 4, m */
    real sphere_radius;  /* the rigid projectile's radius R, m (0 without one) */
    sph_int as_exponent; /* n in f_ij^n */
    sph_int material_count;
};

/* Per-work-group partial results of the per-step reduction. The host sums
 * the partials in double. */
enum sph_reduce_slot {
    SPH_RED_MAX_SIGNAL = 0,   /* max (c + |v|), m/s */
    SPH_RED_MAX_SPEED = 1,    /* max |v|, m/s */
    SPH_RED_MAX_DRIFT = 2,    /* max drift speed |v_half + v_xsph|, m/s */
    SPH_RED_BAD_INDEX = 3,    /* smallest original id of a bad particle, INT_MAX if none;
                                 carried as real: exact below 2^24 ids in float */
    SPH_RED_LOAD_POWER = 4,   /* sum f_ext . v over loaded particles, W (per m in 2-D) */
    SPH_RED_KINETIC = 5,      /* sum m v^2 / 2, J */
    SPH_RED_INTERNAL = 6,     /* sum m e, J */
    SPH_RED_PROBE_DISP_X = 7, /* sum of probe displacement x, m */
    SPH_RED_PROBE_DISP_Y = 8,
    SPH_RED_PROBE_DISP_Z = 9,
    SPH_RED_PROBE_COUNT = 10,
    SPH_RED_MOMENTUM_X = 11, /* sum m v, kg m/s */
    SPH_RED_MOMENTUM_Y = 12,
    SPH_RED_MOMENTUM_Z = 13,
    SPH_RED_WALL_FORCE_X = 14, /* sum of the wall forces on the particles, N */
    SPH_RED_WALL_FORCE_Y = 15,
    SPH_RED_WALL_FORCE_Z = 16,
    SPH_RED_WALL_POWER = 17,      /* sum f_wall . v, W */
    SPH_RED_VISCOUS_POWER = 18,   /* sum m (artificial-viscosity heating), W */
    SPH_RED_HOURGLASS_POWER = 19, /* sum m (hourglass power taken from the motion), W */
    SPH_RED_MAX_DISTORTION = 20,  /* total Lagrangian: max Frobenius norm of the Green strain
                                     E = (F^T F - I) / 2 against the reference, 1 */
    SPH_RED_SLOTS = 21
};

/* Slots of the health-indicator reduction (kernels/health.cl,
 * health_indicators). */
enum sph_health_slot {
    SPH_HEALTH_MIN_DISTANCE = 0, /* smallest pair distance, m (min) */
    SPH_HEALTH_CLUMPED = 1,      /* particles with a neighbour closer than dx / 2 (sum) */
    SPH_HEALTH_SWEGLE = 2,       /* particles whose nearest pair has W'' sigma_n > 0 (sum) */
    SPH_HEALTH_NEIGHBOURS_MIN = 3,
    SPH_HEALTH_NEIGHBOURS_MAX = 4,
    SPH_HEALTH_NEIGHBOURS_SUM = 5,
    SPH_HEALTH_PARTICLES = 6, /* real particles counted (sum) */
    SPH_HEALTH_SLOTS = 8
};

/* A particle's health record (kernels/health.cl, health_pairs): a real, the
 * nearest neighbour's distance, then an int, its neighbour count within
 * the support (the low bits) and these marks; the host reads the counts
 * back for the integrity measure (host/step.c solver_neighbour_counts), so
 * the record is two reals wide. */
#define SPH_HEALTH_COUNTED (1 << 28) /* a real particle, neither ghost nor fixed */
#define SPH_HEALTH_CLUMPED_MARK (1 << 29)
#define SPH_HEALTH_SWEGLE_MARK (1 << 30)
#define SPH_HEALTH_COUNT_MASK ((1 << 28) - 1)

#endif /* SPH_SHARED_H */
