/* The `sph` command: run, check, info. */
#include <hdf5.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "device.h"
#include "domain.h"
#include "run.h"
#include "scene.h"
#include "solver.h"
#include "sph_case.h"

static const char *const usage_main =
    "usage: sph <command> [options]\n"
    "\n"
    "commands:\n"
    "  run CASE    run a case file (YAML) and write a run folder\n"
    "  resume DIR  continue an interrupted run from its folder's checkpoint\n"
    "  check CASE  validate a case file without running it\n"
    "  info        list OpenCL platforms and devices\n"
    "  bench       time a fixed suite of scenes: throughput and per-kernel profile\n"
    "\n"
    "'sph <command> --help' describes each command.\n";

static const char *const usage_run =
    "usage: sph run CASE [--out DIR] [--device D] [--set key.path=value ...] [--quiet]\n"
    "               [--profile]\n"
    "\n"
    "  --out DIR      run folder (default runs/<case name>-<date>-<time>)\n"
    "  --device D     device index from 'sph info' or a substring of its name\n"
    "                 (default: the first GPU, else the first CPU)\n"
    "  --set K=V      override a case key, e.g. --set numerics.dx=0.5e-3\n"
    "                 --set materials.steel.density=7850 --set bodies.beam.max=[0.1,0.005]\n"
    "  --quiet        no progress line\n"
    "  --profile      time every kernel launch (OpenCL events): a per-kernel table\n"
    "                 on stdout and profile.json in the run folder\n"
    "\n"
    "Writes case.resolved.yaml, snap_NNNNN.h5 + snapshots.xdmf (open in ParaView),\n"
    "history.csv and summary.json. Exit status: 0 completed, 1 bad input, 2 device\n"
    "error, 3 the run went unstable or was stopped unhealthy (health.stop; the last\n"
    "state is still written), 130 / 143 interrupted by SIGINT / SIGTERM (Ctrl-C):\n"
    "the step is finished and a checkpoint, a snapshot and summary.json written;\n"
    "'sph resume DIR' goes on from there. A second signal stops at once.\n";

static const char *const usage_resume =
    "usage: sph resume RUN_DIR [--device D] [--quiet] [--profile]\n"
    "\n"
    "Continues the run in RUN_DIR from its checkpoint (checkpoint.h5, written every\n"
    "output.checkpoint_interval of simulated time, every checkpoint_wall_interval of\n"
    "wall-clock time, and on SIGINT / SIGTERM) with the folder's case.resolved.yaml;\n"
    "history.csv, ballistics.csv and the snapshots go on from the checkpoint, and the\n"
    "result is the same, to the bit, as a run that was never interrupted.\n"
    "Exit status as for 'sph run'.\n";

static const char *const usage_check =
    "usage: sph check CASE [--set key.path=value ...]\n"
    "\n"
    "Validates CASE (and the overrides) and prints the resolved case with every\n"
    "default filled in. Exit status 0 when valid, 1 otherwise.\n";

static const char *const usage_info = "usage: sph info\n\nLists OpenCL platforms and devices "
                                      "with their index for --device.\n";

static const char *const usage_bench =
    "usage: sph bench [--quick | --large] [--only NAME] [--steps N] [--repeats R]\n"
    "                 [--warmup W] [--json FILE] [--device D] [--set key.path=value ...]\n"
    "\n"
    "Steps each scene of the suite N times (default 20; --quick 5) after W warm-up\n"
    "steps (default 5; --quick 2), R times over (default 3), with every kernel\n"
    "launch timed by OpenCL events, and prints per scene: the median time per step,\n"
    "particle-steps/s, pair interactions/s, device memory per particle and the\n"
    "per-kernel table (time per call, share, GB/s and GFLOP/s against the device's\n"
    "measured ceilings, cached in the user cache folder).\n"
    "\n"
    "  --quick      small sizes only: a smoke test that runs in well under a minute\n"
    "  --large      add the large sizes (3-D Taylor bar and 3-D penetration at 1M particles)\n"
    "  --only NAME  the scenes whose name contains NAME (e.g. taylor3d-200k)\n"
    "  --json FILE  write every figure as JSON (tools/bench_plot.py plots it)\n"
    "  --set K=V    override a case key in every scene, e.g. to compare\n"
    "               --set numerics.neighbour_loop=plain or --set numerics.precision=double\n"
    "\n"
    "Suite: taylor3d-10k (quick), taylor3d-50k, taylor3d-200k, taylor3d-1m (large):\n"
    "cases/taylor_3d_4340.yaml at h = 1.2 dx; gelatin-axi: cases/gelatin_silica.yaml;\n"
    "gelatin3d-120k, gelatin3d-1m (large), gelatin3d-10m (only as --only gelatin3d-10m):\n"
    "cases/gelatin_silica_3d.yaml;\n"
    "beam2d-1k (quick), beam2d-16k: cases/beam_2d.yaml.\n";

/* Parses a positive integer option value; prints the problem and returns 0
 * when it is not one. */
static int positive_int(const char *option, const char *text, int max, int *out)
{
    char *end = NULL;
    const long v = strtol(text, &end, 10);
    if (!end || *end || v < 1 || v > max) {
        fprintf(stderr, "sph bench: %s expects a whole number from 1 to %d, got '%s'\n", option,
                max, text);
        return 0;
    }
    *out = (int)v;
    return 1;
}

/* Appends a --set override; 0 (with the message) past CASE_MAX_SETS. */
static int push_set(char **sets, int *count, char *value)
{
    if (*count >= CASE_MAX_SETS) {
        fprintf(stderr, "sph: more than %d --set options\n", CASE_MAX_SETS);
        return 0;
    }
    sets[(*count)++] = value;
    return 1;
}

static int command_bench(int argc, char **argv)
{
    char *sets[CASE_MAX_SETS];
    struct bench_options o = {.warmup = -1, .steps = -1, .repeats = 3, .sets = sets};
    for (int i = 0; i < argc; ++i) {
        const char *a = argv[i];
        const char *value = i + 1 < argc ? argv[i + 1] : NULL;
        int ok = 1;
        if (strcmp(a, "--quick") == 0)
            o.quick = 1;
        else if (strcmp(a, "--large") == 0)
            o.large = 1;
        else if (strcmp(a, "--only") == 0 && value)
            o.only = argv[++i];
        else if (strcmp(a, "--json") == 0 && value)
            o.json_path = argv[++i];
        else if (strcmp(a, "--device") == 0 && value)
            o.device = argv[++i];
        else if (strcmp(a, "--set") == 0 && value)
            ok = push_set(sets, &o.set_count, argv[++i]);
        else if (strcmp(a, "--steps") == 0 && value)
            ok = positive_int(a, argv[++i], 1000000, &o.steps);
        else if (strcmp(a, "--warmup") == 0 && value)
            ok = positive_int(a, argv[++i], 1000000, &o.warmup);
        else if (strcmp(a, "--repeats") == 0 && value)
            ok = positive_int(a, argv[++i], BENCH_MAX_REPEATS, &o.repeats);
        else {
            fprintf(stderr, "sph bench: unknown or incomplete option '%s'\n\n%s", a, usage_bench);
            return 1;
        }
        if (!ok)
            return 1;
    }
    if (o.quick && o.large) {
        fprintf(stderr, "sph bench: --quick and --large exclude each other\n");
        return 1;
    }
    if (o.steps < 0)
        o.steps = o.quick ? 5 : 20;
    if (o.warmup < 0)
        o.warmup = o.quick ? 2 : 5;
    if (dist_size() > 1) {
        fprintf(stderr, "sph bench: runs as one process (time a run over several processes with "
                        "sph run --profile)\n");
        return 1;
    }
    return bench_main(&o);
}

static int wants_help(int argc, char **argv)
{
    for (int i = 0; i < argc; ++i)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
            return 1;
    return 0;
}

/* Parses run/check options; returns 0 or prints the problem and returns 1. */
static int parse_options(int argc, char **argv, struct run_options *o, char **sets, int allow_run,
                         const char *usage)
{
    for (int i = 0; i < argc; ++i) {
        const char *a = argv[i];
        const int has_value = i + 1 < argc;
        if (strcmp(a, "--set") == 0 && has_value) {
            if (!push_set(sets, &o->set_count, argv[++i]))
                return 1;
        } else if (allow_run && strcmp(a, "--out") == 0 && has_value) {
            o->out_dir = argv[++i];
        } else if (allow_run && strcmp(a, "--device") == 0 && has_value) {
            o->device = argv[++i];
        } else if (allow_run && strcmp(a, "--quiet") == 0) {
            o->quiet = 1;
        } else if (allow_run && strcmp(a, "--profile") == 0) {
            o->profile = 1;
        } else if (a[0] == '-' && a[1] == '-') {
            fprintf(stderr, "sph: unknown or incomplete option '%s'\n\n%s", a, usage);
            return 1;
        } else if (!o->case_path) {
            o->case_path = a;
        } else {
            fprintf(stderr, "sph: unexpected argument '%s' (one case file expected)\n\n%s", a,
                    usage);
            return 1;
        }
    }
    if (!o->case_path) {
        fprintf(stderr, "sph: no case file given\n\n%s", usage);
        return 1;
    }
    o->sets = sets;
    return 0;
}

static int command_check(int argc, char **argv)
{
    struct run_options o = {0};
    char *sets[CASE_MAX_SETS];
    if (parse_options(argc, argv, &o, sets, 0, usage_check))
        return 1;
    struct sph_case *c = calloc(1, sizeof *c);
    char error[SPH_ERROR_MAX];
    int code = 0;
    if (!c) {
        fprintf(stderr, "sph: out of host memory\n");
        return 1;
    }
    struct sph_scene scene = {0};
    /* the scene too: what `sph run` refuses before it opens a device
     * (a projectile overlapping the target, a shot that misses it) */
    if (case_load(o.case_path, o.set_count, o.sets, c, error, sizeof error) ||
        scene_build(c, &scene, error, sizeof error) ||
        projectile_check_scene(c, &scene, error, sizeof error)) {
        fprintf(stderr, "sph: %s\n", error);
        code = 1;
    } else {
        case_note_welding(c, stderr);
        case_write_resolved(c, stdout);
        fprintf(stderr,
                "sph: %s is valid (%d particles, %.3g GiB of device memory without "
                "symmetry-plane ghosts)\n",
                o.case_path, scene.count,
                (double)scene.count * (double)solver_case_bytes_per_particle(c) / (1 << 30));
    }
    scene_free(&scene);
    free(c);
    return code;
}

static int sph_main(int argc, char **argv)
{
    /* past a file size limit a write fails (EFBIG) and the run says so,
     * instead of being killed without a word */
    signal(SIGXFSZ, SIG_IGN);
    /* HDF5's exit handler closes what is still open, and crashes on a file
     * whose close failed (a full disk: the flush fails and the file stays
     * open). Every file this program opens is closed on its own paths. */
    H5dont_atexit();
    if (argc < 2) {
        fputs(usage_main, stderr);
        return 1;
    }
    const char *command = argv[1];
    if (strcmp(command, "--help") == 0 || strcmp(command, "-h") == 0 ||
        strcmp(command, "help") == 0) {
        fputs(usage_main, stdout);
        return 0;
    }
    if (strcmp(command, "run") == 0) {
        if (wants_help(argc - 2, argv + 2)) {
            fputs(usage_run, stdout);
            return 0;
        }
        struct run_options o = {0};
        char *sets[CASE_MAX_SETS];
        if (parse_options(argc - 2, argv + 2, &o, sets, 1, usage_run))
            return 1;
        o.quiet |= dist_rank() != 0; /* rank 0 reports for the job */
        return run_case(&o);
    }
    if (strcmp(command, "resume") == 0) {
        if (wants_help(argc - 2, argv + 2)) {
            fputs(usage_resume, stdout);
            return 0;
        }
        struct run_options o = {0};
        char *sets[CASE_MAX_SETS];
        if (parse_options(argc - 2, argv + 2, &o, sets, 1, usage_resume))
            return 1;
        if (o.out_dir || o.set_count) {
            fprintf(stderr,
                    "sph resume: no --out or --set: the run folder's case.resolved.yaml "
                    "is the case\n\n%s",
                    usage_resume);
            return 1;
        }
        o.out_dir = o.case_path;
        o.resume = 1;
        return run_case(&o);
    }
    if (strcmp(command, "check") == 0) {
        if (wants_help(argc - 2, argv + 2)) {
            fputs(usage_check, stdout);
            return 0;
        }
        return command_check(argc - 2, argv + 2);
    }
    if (strcmp(command, "bench") == 0) {
        if (wants_help(argc - 2, argv + 2)) {
            fputs(usage_bench, stdout);
            return 0;
        }
        return command_bench(argc - 2, argv + 2);
    }
    if (strcmp(command, "info") == 0) {
        if (wants_help(argc - 2, argv + 2)) {
            fputs(usage_info, stdout);
            return 0;
        }
        const int devices = device_list(stdout);
        if (cl_failed())
            fprintf(stderr, "sph: %s\n", cl_failure());
        return devices > 0 && !cl_failed() ? 0 : 2;
    }
    fprintf(stderr, "sph: unknown command '%s'\n\n%s", command, usage_main);
    return 1;
}

int main(int argc, char **argv)
{
    dist_start(&argc, &argv); /* MPI under mpirun (host/domain.h) */
    const int code = sph_main(argc, argv);
    dist_stop();
    return code;
}
