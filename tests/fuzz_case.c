/* libFuzzer target: case loading (host/case.c), validation, the resolved
 * case writer and the scene size estimates and fill (host/scene.c,
 * host/grading.c). No OpenCL device is opened: state.c, device.c and
 * fields.c are linked only for solver_max_sound_speed and what they call.
 * Built and run by tests/fuzz_case.sh.
 *
 * Each input is a case file, written to a temporary file (TMPDIR, else
 * /dev/shm, else /tmp) that is created once per process and rewritten per
 * input. --set overrides come from two places:
 *   - leading control bytes (0x01-0x1f but tab, newline and carriage
 *     return; never valid at the start of a YAML file) each pick one entry
 *     of fixed_sets[] and are stripped before the file is written;
 *   - comment lines "#set key.path=value" anywhere in the file each give
 *     one override (the line stays in the file: YAML reads it as a comment).
 *
 * Oracles besides the sanitizers (each aborts with a message):
 *   - case_load fails with an empty error message, or succeeds with one, or
 *     leaves it unterminated (one input in 32 gets a buffer of 1-24 bytes);
 *   - a material of a valid case has a sound speed that is not positive
 *     (NaN or 0: case_material_sound_speed);
 *   - a valid case's case_write_resolved output (documented as YAML that
 *     case_load accepts) does not load back, or loads back to a case that
 *     writes a different text;
 *   - a graded body's grading_points is below its coarsest lattice's
 *     cells (the levels must fill the whole body);
 *   - scene_estimate accepts a case with fewer lattice points than bodies
 *     or more than its limit (a negative or NaN estimate);
 *   - scene_build returns a particle count outside 1 .. the scene_estimate
 *     upper bound. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scene.h"
#include "solver.h"
#include "sph_case.h"

/* Scenes up to this many lattice points are also built (the fill loops are
 * linear in it: a few ms). */
#define FUZZ_BUILD_POINTS 200000.0
#define FUZZ_MAX_SETS 8
#define FUZZ_SET_MAX 512

static const char *const fixed_sets[] = {
    "numerics.dx=1e-9",
    "numerics.precision=double",
    "output.snapshot_interval=1e-300",
    "numerics.precision=float",
    "numerics.dx=1e-3",
    "dimension=3",
    "dimension=2",
    "plane=axisymmetric",
    "numerics.end_time=1e300",
    "numerics.formulation=total_lagrangian",
    "bodies.0.shape=cylinder",
    "bodies.0.grading={fine_min: [0, 0, 0], fine_max: [1e-3, 1e-3, 1e-3], levels: 6}",
    "bodies.0.grading={track_from: [0, 0, 0], track_to: [1, 1, 1], track_radius: 1e-3}",
    "bodies.0.velocity=[1e300, -1e300, 0]",
    "materials.0.density=1e-320",
    "groups.0.load={force: [1, 2, 3], law: linear_ramp, ramp_time: 1e-3}",
    "walls=[{name: w, point: [0, 0, 0], normal: [1e-310, 0, 0]}]",
    "symmetry=[{axis: x}, {axis: y}, {axis: z}]",
    "projectile={diameter: 1e-3, density: 1, centre: [0, 0, 0], velocity: [0, -1, 0]}",
    "name=&a [*a, *a]",
    "numerics=",
    "bodies.missing.min=[0, 0]",
    "a.b.c.d.e.f.g.h.i.j.k.l.m.n.o.p.q.r=1",
};

#define FIXED_SET_COUNT ((int)(sizeof fixed_sets / sizeof *fixed_sets))

static char case_path[4096], resolved_path[4096];
static int case_fd = -1, resolved_fd = -1;

static void remove_temporaries(void)
{
    if (case_fd >= 0)
        unlink(case_path);
    if (resolved_fd >= 0)
        unlink(resolved_path);
}

static int make_temporary(char *path, size_t size, const char *stem)
{
    const char *dir = getenv("TMPDIR");
    if (!dir || !*dir)
        dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    snprintf(path, size, "%s/%s_%ld_XXXXXX.yaml", dir, stem, (long)getpid());
    const int fd = mkstemps(path, 5);
    if (fd < 0) {
        perror(path);
        abort();
    }
    return fd;
}

/* Replaces the temporary file's contents with `size` bytes of `data`. */
static void rewrite(int fd, const char *path, const void *data, size_t size)
{
    if (ftruncate(fd, 0) != 0 || (size && pwrite(fd, data, size, 0) != (ssize_t)size)) {
        perror(path);
        abort();
    }
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    case_fd = make_temporary(case_path, sizeof case_path, "fuzz_case");
    resolved_fd = make_temporary(resolved_path, sizeof resolved_path, "fuzz_case_resolved");
    atexit(remove_temporaries);
    return 0;
}

/* The "#set key=value" comment lines of the input, copied NUL-terminated. */
static int comment_sets(const uint8_t *data, size_t size, char texts[][FUZZ_SET_MAX], int count)
{
    static const char marker[] = "#set ";
    const size_t marker_len = sizeof marker - 1;
    for (size_t i = 0; i + marker_len <= size && count < FUZZ_MAX_SETS; ++i) {
        if ((i > 0 && data[i - 1] != '\n') || memcmp(data + i, marker, marker_len) != 0)
            continue;
        size_t n = 0;
        for (size_t k = i + marker_len;
             k < size && data[k] != '\n' && data[k] != '\0' && n + 1 < FUZZ_SET_MAX; ++k)
            texts[count][n++] = (char)data[k];
        texts[count][n] = '\0';
        ++count;
    }
    return count;
}

static int is_selector(uint8_t b)
{
    return b >= 0x01 && b < 0x20 && b != '\t' && b != '\n' && b != '\r';
}

/* The resolved case in memory (case_resolved_text); aborts when it cannot
 * be written. */
static char *resolved_text(const struct sph_case *c, size_t *length)
{
    char *text = case_resolved_text(c, length);
    if (!text) {
        fprintf(stderr, "fuzz_case: case_resolved_text failed\n");
        abort();
    }
    return text;
}

static void check_round_trip(const struct sph_case *c)
{
    static struct sph_case again;
    char error[SPH_ERROR_MAX];
    size_t length = 0, length2 = 0;
    char *text = resolved_text(c, &length);
    rewrite(resolved_fd, resolved_path, text, length);
    if (case_load(resolved_path, 0, NULL, &again, error, sizeof error) != 0) {
        fprintf(stderr,
                "fuzz_case: the resolved case does not load back: %s\n--- resolved case ---\n%s",
                error, text);
        abort();
    }
    char *text2 = resolved_text(&again, &length2);
    if (length != length2 || memcmp(text, text2, length) != 0) {
        fprintf(stderr,
                "fuzz_case: the resolved case changes when loaded and written again\n"
                "--- first ---\n%s--- second ---\n%s",
                text, text2);
        abort();
    }
    free(text);
    free(text2);
}

/* Every material of a valid case has a real, positive sound speed
 * (case_material_sound_speed; case_load refuses others): the time step, the velocity limit and
 * scene_estimate's step count divide by it. */
static void check_sound_speeds(const struct sph_case *c)
{
    for (int m = 0; m < c->material_count; ++m) {
        const double speed = case_material_sound_speed(&c->materials[m]);
        if (!(speed > 0)) {
            fprintf(stderr, "fuzz_case: material '%s' of a valid case has sound speed %g m/s\n",
                    c->materials[m].name, speed);
            abort();
        }
    }
}

/* The most particles scene_estimate lets through (host/scene.c). */
#define FUZZ_SCENE_LIMIT 200e6

/* A graded body's levels tile it, the coarsest (spacing 2^levels dx)
 * filling what the finer ones leave: grading_points is at least the
 * coarsest lattice's whole cells, or past the limit where those are. */
static void check_grading_points(const struct sph_case *c, const struct case_body *b)
{
    const double spacing = c->numerics.dx * (1 << b->grading.levels);
    double coarse = 1;
    for (int a = 0; a < c->dimension; ++a)
        coarse *= floor((b->box.max[a] - b->box.min[a]) / spacing);
    const double points = grading_points(c, b);
    if (coarse <= FUZZ_SCENE_LIMIT ? !(points >= coarse) : !(points > FUZZ_SCENE_LIMIT)) {
        fprintf(stderr,
                "fuzz_case: grading_points gives %g lattice points for body '%s', whose "
                "coarsest lattice (spacing %g m) alone has %g\n",
                points, b->name, spacing, coarse);
        abort();
    }
}

static void check_scene(const struct sph_case *c)
{
    char error[SPH_ERROR_MAX] = "";
    double points = -1;
    for (int b = 0; b < c->body_count; ++b)
        if (c->bodies[b].grading.enabled)
            check_grading_points(c, &c->bodies[b]);
    if (scene_estimate(c, &points, error, sizeof error) != 0) {
        if (!error[0]) {
            fprintf(stderr, "fuzz_case: scene_estimate refused the case without a message\n");
            abort();
        }
        return;
    }
    /* every body has at least one lattice point */
    if (!(points >= c->body_count && points <= FUZZ_SCENE_LIMIT)) {
        fprintf(stderr, "fuzz_case: scene_estimate accepted %d bodies spanning %g lattice points\n",
                c->body_count, points);
        abort();
    }
    if (points > FUZZ_BUILD_POINTS)
        return;
    struct sph_scene scene;
    error[0] = '\0';
    if (scene_build(c, &scene, error, sizeof error) != 0) {
        if (!error[0]) {
            fprintf(stderr, "fuzz_case: scene_build failed without a message\n");
            abort();
        }
        return;
    }
    if (scene.count < 1 || scene.count > points) {
        fprintf(stderr,
                "fuzz_case: scene_build made %d particles, scene_estimate said at most %g\n",
                scene.count, points);
        abort();
    }
    scene_free(&scene);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static struct sph_case c; /* large: not on the stack */
    static char texts[FUZZ_MAX_SETS][FUZZ_SET_MAX];
    char *sets[FUZZ_MAX_SETS];
    int set_count = 0;
    for (; size > 0 && is_selector(data[0]) && set_count < FUZZ_MAX_SETS; ++data, --size) {
        snprintf(texts[set_count], FUZZ_SET_MAX, "%s", fixed_sets[data[0] % FIXED_SET_COUNT]);
        ++set_count;
    }
    set_count = comment_sets(data, size, texts, set_count);
    for (int i = 0; i < set_count; ++i)
        sets[i] = texts[i];

    rewrite(case_fd, case_path, data, size);
    /* One input in 32 gets an error buffer of 1 to 24 bytes, allocated to
     * its size so that ASan sees any write past it. */
    const size_t error_size = size % 32 == 31 ? 1 + (size / 32) % 24 : SPH_ERROR_MAX;
    char *error = malloc(error_size);
    if (!error)
        abort();
    memset(error, 'x', error_size); /* case_load must write it either way */
    const int rc = case_load(case_path, set_count, sets, &c, error, error_size);
    if (memchr(error, '\0', error_size) == NULL) {
        fprintf(stderr, "fuzz_case: case_load left its error message unterminated\n");
        abort();
    }
    if (rc != 0 && !error[0] && error_size > 1) {
        fprintf(stderr, "fuzz_case: case_load failed without a message\n");
        abort();
    }
    if (rc == 0 && error[0]) {
        fprintf(stderr, "fuzz_case: case_load succeeded with an error message: %s\n", error);
        abort();
    }
    free(error);
    if (rc != 0)
        return 0;
    check_sound_speeds(&c);
    check_round_trip(&c);
    check_scene(&c);
    return 0;
}
