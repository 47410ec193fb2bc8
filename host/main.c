/* The `sph` command: run, check, info. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "device.h"
#include "run.h"
#include "sph_case.h"

#define MAX_SETS 128

static const char *const usage_main =
    "usage: sph <command> [options]\n"
    "\n"
    "commands:\n"
    "  run CASE    run a case file (YAML) and write a run folder\n"
    "  check CASE  validate a case file without running it\n"
    "  info        list OpenCL platforms and devices\n"
    "\n"
    "'sph <command> --help' describes each command.\n";

static const char *const usage_run =
    "usage: sph run CASE [--out DIR] [--device D] [--set key.path=value ...] [--quiet]\n"
    "\n"
    "  --out DIR      run folder (default runs/<case name>-<date>-<time>)\n"
    "  --device D     device index from 'sph info' or a substring of its name\n"
    "                 (default: the first GPU, else the first CPU)\n"
    "  --set K=V      override a case key, e.g. --set numerics.dx=0.5e-3\n"
    "                 --set materials.steel.density=7850 --set bodies.beam.max=[0.1,0.005]\n"
    "  --quiet        no progress line\n"
    "\n"
    "Writes case.resolved.yaml, snap_NNNNN.h5 + snapshots.xdmf (open in ParaView),\n"
    "history.csv and summary.json. Exit status: 0 completed, 1 bad input, 2 device\n"
    "error, 3 the run went unstable or was stopped unhealthy (health.stop; the last\n"
    "state is still written).\n";

static const char *const usage_check =
    "usage: sph check CASE [--set key.path=value ...]\n"
    "\n"
    "Validates CASE (and the overrides) and prints the resolved case with every\n"
    "default filled in. Exit status 0 when valid, 1 otherwise.\n";

static const char *const usage_info = "usage: sph info\n\nLists OpenCL platforms and devices "
                                      "with their index for --device.\n";

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
            if (o->set_count >= MAX_SETS) {
                fprintf(stderr, "sph: more than %d --set options\n", MAX_SETS);
                return 1;
            }
            sets[o->set_count++] = argv[++i];
        } else if (allow_run && strcmp(a, "--out") == 0 && has_value) {
            o->out_dir = argv[++i];
        } else if (allow_run && strcmp(a, "--device") == 0 && has_value) {
            o->device = argv[++i];
        } else if (allow_run && strcmp(a, "--quiet") == 0) {
            o->quiet = 1;
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
    char *sets[MAX_SETS];
    if (parse_options(argc, argv, &o, sets, 0, usage_check))
        return 1;
    struct sph_case *c = calloc(1, sizeof *c);
    char error[SPH_ERROR_MAX];
    int code = 0;
    if (case_load(o.case_path, o.set_count, o.sets, c, error, sizeof error)) {
        fprintf(stderr, "sph: %s\n", error);
        code = 1;
    } else {
        case_write_resolved(c, stdout);
        fprintf(stderr, "sph: %s is valid\n", o.case_path);
    }
    free(c);
    return code;
}

int main(int argc, char **argv)
{
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
        char *sets[MAX_SETS];
        if (parse_options(argc - 2, argv + 2, &o, sets, 1, usage_run))
            return 1;
        return run_case(&o);
    }
    if (strcmp(command, "check") == 0) {
        if (wants_help(argc - 2, argv + 2)) {
            fputs(usage_check, stdout);
            return 0;
        }
        return command_check(argc - 2, argv + 2);
    }
    if (strcmp(command, "info") == 0) {
        if (wants_help(argc - 2, argv + 2)) {
            fputs(usage_info, stdout);
            return 0;
        }
        return device_list(stdout) > 0 ? 0 : 2;
    }
    fprintf(stderr, "sph: unknown command '%s'\n\n%s", command, usage_main);
    return 1;
}
