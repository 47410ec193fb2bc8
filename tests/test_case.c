/* Case files: the example case loads, bad input is reported with the right
 * file:line and key, --set overrides work, and the resolved case reloads to
 * the same struct. Inputs are written to temp files from the literals below,
 * so their line numbers are the ones the tests expect. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "sph_case.h"
#include "solver.h"

#ifndef SPH_SOURCE_DIR
#define SPH_SOURCE_DIR "."
#endif

#define BEAM SPH_SOURCE_DIR "/cases/beam_2d.yaml"

/* Writes `text` to a new temp file; the caller removes and frees the path. */
static char *temp_file(const char *text)
{
    const char *dir = getenv("TMPDIR");
    if (!dir || !*dir)
        dir = "/tmp";
    char *path = malloc(strlen(dir) + 32);
    assert_non_null(path);
    sprintf(path, "%s/test_case_XXXXXX", dir);
    const int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    assert_non_null(f);
    fputs(text, f);
    assert_int_equal(fclose(f), 0);
    return path;
}

static void drop_file(char *path)
{
    remove(path);
    free(path);
}

static int load_text(const char *text, int set_count, char *const *sets, struct sph_case *c,
                     char *error, size_t size)
{
    char *path = temp_file(text);
    const int rc = case_load(path, set_count, sets, c, error, size);
    drop_file(path);
    return rc;
}

/* ---- the example case -------------------------------------------------- */

static void test_beam_loads(void **state)
{
    (void)state;
    static struct sph_case c;
    char error[SPH_ERROR_MAX];
    const int rc = case_load(BEAM, 0, NULL, &c, error, sizeof error);
    if (rc)
        fail_msg("%s", error);
    assert_string_equal(c.name, "beam_2d");
    assert_int_equal(c.dimension, 2);
    assert_int_equal(c.plane, SPH_PLANE_STRESS);
    assert_true(c.thickness == 1.0e-3);
    assert_int_equal(c.material_count, 1);
    assert_string_equal(c.materials[0].name, "steel");
    assert_true(c.materials[0].density == 7800);
    assert_true(c.materials[0].youngs_modulus == 210.0e9);
    assert_true(c.materials[0].poisson_ratio == 0.3);
    assert_int_equal(c.materials[0].eos, SPH_EOS_LINEAR);
    assert_int_equal(c.materials[0].strength, SPH_STRENGTH_ELASTIC);

    assert_int_equal(c.body_count, 2);
    assert_string_equal(c.bodies[0].name, "beam");
    assert_int_equal(c.bodies[0].material, 0);
    assert_int_equal(c.bodies[0].fixed, 0);
    assert_true(c.bodies[0].box.min[1] == -0.005 && c.bodies[0].box.max[0] == 0.1);
    assert_true(c.bodies[0].box.min[2] == 0 && c.bodies[0].box.max[2] == 0);
    assert_string_equal(c.bodies[1].name, "clamp");
    assert_int_equal(c.bodies[1].fixed, 1);
    assert_true(c.bodies[1].box.min[0] == -0.004);

    assert_int_equal(c.group_count, 1);
    const struct case_group *tip = &c.groups[0];
    assert_string_equal(tip->name, "tip");
    assert_int_equal(tip->body, 0);
    assert_true(tip->region.min[0] == 0.099 && tip->region.max[1] == 0.006);
    assert_int_equal(tip->load.enabled, 1);
    assert_int_equal(tip->load.law, SPH_LOAD_QUADRATIC_RAMP);
    assert_true(tip->load.ramp_time == 1.5e-3);
    assert_true(tip->load.force[0] == 0 && tip->load.force[1] == -1750 && tip->load.force[2] == 0);

    const struct case_numerics *n = &c.numerics;
    assert_true(n->dx == 1e-3);
    assert_int_equal(n->kernel, SPH_KERNEL_WENDLAND_C2);
    assert_string_equal(case_kernel_name(n->kernel), "wendland_c2");
    assert_true(n->h_over_dx == 1.2);
    /* the one numerics block (the case gives no viscosity) */
    assert_int_equal(n->av_scheme, SPH_AV_SWITCH);
    assert_true(n->av_alpha == 1.5 && n->av_beta == 1.5 && n->av_alpha_min == 0.1);
    assert_true(n->as_epsilon == 0.5);
    assert_int_equal(n->as_exponent, 4);
    assert_true(n->xsph_epsilon == 0.5);
    assert_int_equal(n->csph, 1);
    assert_true(n->cfl == 0.3);
    assert_true(n->end_time == 3.0e-3);
    assert_true(n->damping == 0);
    assert_int_equal(n->double_precision, 0);
    assert_true(c.output.snapshot_interval == 1.5e-4);
    assert_true(c.output.history_interval == 1.0e-6);

    assert_int_equal(c.has_probe, 1);
    assert_string_equal(c.probe.name, "tip_deflection");
    assert_int_equal(c.probe.group, 0);
    assert_int_equal(c.probe.quantity, SPH_PROBE_DISPLACEMENT_Y);
    assert_int_equal(c.reference.enabled, 1);
    assert_true(c.reference.value == -30.4e-3);
    assert_true(c.reference.window[0] == 1.5e-3 && c.reference.window[1] == 3.0e-3);
    assert_non_null(strstr(c.reference.source, "elastica"));
    assert_string_equal(c.path, BEAM);
}

/* Defaults of a case that gives only what is required. */
#define MINIMAL                                                                                    \
    "dimension: 2\n"                                                                               \
    "materials:\n"                                                                                 \
    "  - name: steel\n"                                                                            \
    "    density: 7800\n"                                                                          \
    "    youngs_modulus: 210.0e9\n"                                                                \
    "    poisson_ratio: 0.3\n"                                                                     \
    "bodies:\n"                                                                                    \
    "  - name: beam\n"                                                                             \
    "    material: steel\n"                                                                        \
    "    min: [0.0, -0.005]\n"                                                                     \
    "    max: [0.1, 0.005]\n" /* line 11 */

static void test_defaults(void **state)
{
    (void)state;
    static struct sph_case c;
    char error[SPH_ERROR_MAX];
    char *path = temp_file(MINIMAL "numerics:\n"
                                   "  dx: 1e-3\n"
                                   "  end_time: 2e-3\n");
    const int rc = case_load(path, 0, NULL, &c, error, sizeof error);
    if (rc)
        fail_msg("%s", error);
    const char *base = strrchr(path, '/') + 1;
    assert_string_equal(c.name, base);
    drop_file(path);
    assert_int_equal(c.plane, SPH_PLANE_STRESS);
    assert_true(c.thickness == 1.0);
    assert_int_equal(c.materials[0].eos, SPH_EOS_LINEAR);
    assert_int_equal(c.materials[0].strength, SPH_STRENGTH_ELASTIC);
    assert_true(c.materials[0].yield_stress == 0);
    assert_int_equal(c.bodies[0].shape, SPH_SHAPE_BOX);
    assert_int_equal(c.bodies[0].fixed, 0);
    assert_true(c.bodies[0].velocity[0] == 0 && c.bodies[0].velocity[1] == 0);
    assert_int_equal(c.group_count, 0);
    assert_int_equal(c.numerics.kernel, SPH_KERNEL_WENDLAND_C2);
    assert_true(c.numerics.h_over_dx == 1.2);
    assert_int_equal(c.numerics.av_scheme, SPH_AV_SWITCH);
    assert_true(c.numerics.av_alpha == 1.5 && c.numerics.av_beta == 1.5);
    assert_true(c.numerics.av_alpha_min == 0.1);
    assert_true(c.numerics.cfl == 0.3);
    assert_true(c.numerics.as_epsilon == 0);
    assert_int_equal(c.numerics.as_exponent, 4);
    assert_true(c.numerics.xsph_epsilon == 0);
    assert_true(c.numerics.cfl == 0.3);
    assert_true(c.numerics.damping == 0);
    assert_int_equal(c.numerics.double_precision, 0);
    assert_true(c.output.snapshot_interval == 2e-3 / 20);
    assert_true(c.output.history_interval == 2e-3 / 1000);
    assert_int_equal(c.has_probe, 0);
    assert_int_equal(c.reference.enabled, 0);
}

static void test_kernel_names(void **state)
{
    (void)state;
    static const char *const names[SPH_KERNEL_COUNT] = {
        "cubic_spline", "gaussian", "quintic_spline", "wendland_c2", "double_cosine", "hyperbolic"};
    for (int k = 0; k < SPH_KERNEL_COUNT; ++k) {
        assert_string_equal(case_kernel_name((enum sph_kernel_type)k), names[k]);
        char text[512], error[SPH_ERROR_MAX];
        static struct sph_case c;
        snprintf(text, sizeof text, MINIMAL "numerics: {dx: 1e-3, end_time: 1e-3, kernel: %s}\n",
                 names[k]);
        const int rc = load_text(text, 0, NULL, &c, error, sizeof error);
        if (rc)
            fail_msg("%s", error);
        assert_int_equal(c.numerics.kernel, k);
    }
}

/* ---- bad input --------------------------------------------------------- */

struct bad_input {
    const char *name;
    const char *text;
    int line;          /* the error must start "<file>:<line>: " */
    const char *words; /* ... and contain this */
};

static const struct bad_input bad_inputs[] = {
    {"unknown key", MINIMAL "numerics:\n  dx: 1.0e-3\n  end_time: 3.0e-3\n  foo: 1\n", 15,
     "unknown key 'foo' in numerics; expected one of: dx, kernel"},
    {"unknown top-level key", "dimension: 2\nbogus: 1\n", 2, "unknown key 'bogus' at top level"},
    {"snapshot every step",
     MINIMAL "numerics:\n  dx: 1.0e-3\n  end_time: 3.0e-3\noutput:\n"
             "  snapshot_interval: 1e-300\n",
     16, "output.snapshot_interval: expected at least end_time / 99998"},
    {"bad UTF-8 byte", MINIMAL "numerics:\n  dx: 1.0e-3 # \xff\n  end_time: 3.0e-3\n", 13,
     "invalid leading UTF-8 octet"},
    {"string where a number goes", MINIMAL "numerics:\n  dx: fine\n  end_time: 3.0e-3\n", 13,
     "numerics.dx: expected a positive number (m), got 'fine'"},
    {"negative dx", MINIMAL "numerics:\n  dx: -1\n  end_time: 3.0e-3\n", 13,
     "numerics.dx: expected a positive number (m), got '-1'"},
    {"missing required key", MINIMAL "numerics:\n  dx: 1.0e-3\n", 12,
     "numerics: missing required key 'end_time'"},
    {"missing numerics", MINIMAL, 1, "missing required key 'numerics'"},
    {"unknown material",
     "dimension: 2\n"
     "materials:\n"
     "  - name: steel\n"
     "    density: 7800\n"
     "    youngs_modulus: 210.0e9\n"
     "    poisson_ratio: 0.3\n"
     "bodies:\n"
     "  - name: beam\n"
     "    material: aluminium\n"
     "    min: [0.0, -0.005]\n"
     "    max: [0.1, 0.005]\n"
     "numerics: {dx: 1e-3, end_time: 1e-3}\n",
     9, "bodies.0.material: unknown material 'aluminium'; expected one of: steel"},
    {"bad kernel", MINIMAL "numerics:\n  dx: 1.0e-3\n  end_time: 3.0e-3\n  kernel: foo\n", 15,
     "numerics.kernel: expected one of cubic_spline, gaussian"},
    {"three numbers in 2-D",
     "dimension: 2\n"
     "materials:\n"
     "  - name: steel\n"
     "    density: 7800\n"
     "    youngs_modulus: 210.0e9\n"
     "    poisson_ratio: 0.3\n"
     "bodies:\n"
     "  - name: beam\n"
     "    material: steel\n"
     "    min: [0.0, -0.005, 0.0]\n"
     "    max: [0.1, 0.005]\n"
     "numerics: {dx: 1e-3, end_time: 1e-3}\n",
     10, "bodies.0.min: expected a sequence of 2 numbers [x, y] (m), got a sequence of 3 items"},
    {"bad indentation", MINIMAL "numerics:\n  dx: 1.0e-3\n   end_time: 3.0e-3\n", 14,
     "malformed YAML: mapping values are not allowed"},
    {"unclosed flow sequence", MINIMAL "numerics:\n  dx: [1.0e-3\n  end_time: 3.0e-3\n", 14,
     "malformed YAML"},
    {"duplicate material name",
     "dimension: 2\n"
     "materials:\n"
     "  - name: steel\n"
     "    density: 7800\n"
     "    youngs_modulus: 210.0e9\n"
     "    poisson_ratio: 0.3\n"
     "  - name: steel\n"
     "    density: 2700\n"
     "    youngs_modulus: 70e9\n"
     "    poisson_ratio: 0.33\n",
     7, "materials.1.name: duplicate name 'steel'"},
    {"duplicate key", MINIMAL "numerics:\n  dx: 1.0e-3\n  end_time: 3.0e-3\n  dx: 2.0e-3\n", 15,
     "numerics.dx: duplicate key 'dx'"},
    {"ramp law without ramp_time",
     MINIMAL "groups:\n"
             "  - name: tip\n"
             "    min: [0.099, -0.006]\n"
             "    max: [0.101, 0.006]\n"
             "    load:\n"
             "      force: [0.0, -1750.0]\n"
             "      law: linear_ramp\n"
             "numerics: {dx: 1e-3, end_time: 1e-3}\n",
     16, "groups.0.load: missing required key 'ramp_time' (law is linear_ramp)"},
    {"ramp_time with a constant load",
     MINIMAL "groups:\n"
             "  - name: tip\n"
             "    min: [0.099, -0.006]\n"
             "    max: [0.101, 0.006]\n"
             "    load:\n"
             "      force: [0.0, -1750.0]\n"
             "      ramp_time: 1e-3\n"
             "numerics: {dx: 1e-3, end_time: 1e-3}\n",
     18, "groups.0.load.ramp_time: only allowed with law linear_ramp or quadratic_ramp"},
    {"reference without probe",
     MINIMAL "numerics: {dx: 1e-3, end_time: 1e-3}\n"
             "reference:\n"
             "  value: -30.4e-3\n",
     13, "reference: needs a probe"},
    {"unknown probe group",
     MINIMAL "numerics: {dx: 1e-3, end_time: 1e-3}\n"
             "probe:\n"
             "  name: tip_deflection\n"
             "  group: tip\n"
             "  quantity: displacement_y\n",
     15, "probe.group: unknown group 'tip'"},
    {"displacement_z in 2-D",
     MINIMAL "groups:\n"
             "  - name: tip\n"
             "    min: [0.099, -0.006]\n"
             "    max: [0.101, 0.006]\n"
             "numerics: {dx: 1e-3, end_time: 1e-3}\n"
             "probe:\n"
             "  name: tip_deflection\n"
             "  group: tip\n"
             "  quantity: displacement_z\n",
     20, "probe.quantity: expected displacement_x or displacement_y in 2-D"},
    {"unknown eos",
     "dimension: 2\n"
     "materials:\n"
     "  - name: steel\n"
     "    density: 7800\n"
     "    youngs_modulus: 210.0e9\n"
     "    poisson_ratio: 0.3\n"
     "    eos: tillotson\n",
     7, "materials.0.eos: expected one of linear, mie_gruneisen, polynomial, got 'tillotson'"},
    {"mie_gruneisen without its parameters",
     "dimension: 2\n"
     "materials:\n"
     "  - name: steel\n"
     "    density: 7800\n"
     "    youngs_modulus: 210.0e9\n"
     "    poisson_ratio: 0.3\n"
     "    eos: mie_gruneisen\n",
     3, "materials.0: missing required key 'mie_gruneisen' (eos is mie_gruneisen)"},
    {"mie_gruneisen parameters with a linear eos",
     "dimension: 2\n"
     "materials:\n"
     "  - name: steel\n"
     "    density: 7800\n"
     "    youngs_modulus: 210.0e9\n"
     "    poisson_ratio: 0.3\n"
     "    mie_gruneisen: {c0: 3630, s: 1.8, gamma0: 1.8}\n",
     7, "materials.0.mie_gruneisen: only allowed when eos is mie_gruneisen"},
    {"johnson_cook thermal softening without a melting point",
     "dimension: 2\n"
     "materials:\n"
     "  - name: steel\n"
     "    density: 7800\n"
     "    youngs_modulus: 210.0e9\n"
     "    poisson_ratio: 0.3\n"
     "    strength: johnson_cook\n"
     "    yield_stress: 792e6\n"
     "    heat_capacity: 477\n"
     "    johnson_cook: {b: 510e6, n: 0.26, m: 1.03}\n",
     10, "materials.0.johnson_cook: missing required key 'melt_temperature'"},
    {"plastic without yield stress",
     "dimension: 2\n"
     "materials:\n"
     "  - name: steel\n"
     "    density: 7800\n"
     "    youngs_modulus: 210.0e9\n"
     "    poisson_ratio: 0.3\n"
     "    strength: perfectly_plastic\n",
     3, "materials.0: missing required key 'yield_stress'"},
    {"yield stress for an elastic material",
     "dimension: 2\n"
     "materials:\n"
     "  - name: steel\n"
     "    density: 7800\n"
     "    youngs_modulus: 210.0e9\n"
     "    poisson_ratio: 0.3\n"
     "    yield_stress: 250e6\n",
     7, "materials.0.yield_stress: only allowed when strength is perfectly_plastic"},
    {"poisson ratio of 0.5",
     "dimension: 2\n"
     "materials:\n"
     "  - {name: steel, density: 7800, youngs_modulus: 210.0e9, poisson_ratio: 0.5}\n",
     3,
     "materials.0.poisson_ratio: expected a number greater than -1 and less than 0.5, got '0.5'"},
    {"plane in 3-D", "dimension: 3\nplane: strain\n", 2, "plane: only allowed when dimension is 2"},
    {"thickness in 3-D", "dimension: 3\nthickness: 1e-3\n", 2,
     "thickness: only allowed when dimension is 2"},
    {"dimension 4", "dimension: 4\n", 1, "dimension: expected 2 or 3, got '4'"},
    {"max not above min",
     "dimension: 2\n"
     "materials:\n"
     "  - {name: steel, density: 7800, youngs_modulus: 210.0e9, poisson_ratio: 0.3}\n"
     "bodies:\n"
     "  - name: beam\n"
     "    material: steel\n"
     "    min: [0.0, 0.005]\n"
     "    max: [0.1, 0.005]\n",
     8, "bodies.0.max: expected max greater than min on every axis, got y"},
    {"nan", MINIMAL "numerics:\n  dx: nan\n  end_time: 3.0e-3\n", 13,
     "numerics.dx: expected a positive number (m), got 'nan'"},
    {"infinity", MINIMAL "numerics:\n  dx: 1e-3\n  end_time: 1e999\n", 14,
     "numerics.end_time: expected a positive number (s), got '1e999'"},
    {"quoted number", MINIMAL "numerics:\n  dx: \"1e-3\"\n  end_time: 3.0e-3\n", 13,
     "numerics.dx: expected a positive number (m), got the quoted string '1e-3'"},
    {"part out of range", MINIMAL "    part: 256\nnumerics: {dx: 1e-3, end_time: 1e-3}\n", 12,
     "bodies.0.part: expected an integer from 0 to 255, got '256'"},
    {"fractional exponent",
     MINIMAL "numerics:\n  dx: 1e-3\n  end_time: 3.0e-3\n  artificial_stress: {exponent: 2.5}\n",
     15, "numerics.artificial_stress.exponent: expected an integer from 1 to 8, got '2.5'"},
    {"bad boolean", MINIMAL "numerics:\n  dx: 1e-3\n  end_time: 3.0e-3\n  csph: maybe\n", 15,
     "numerics.csph: expected true or false, got 'maybe'"},
    {"cfl of zero", MINIMAL "numerics:\n  dx: 1e-3\n  end_time: 3.0e-3\n  cfl: 0\n", 15,
     "numerics.cfl: expected a number greater than 0 and at most 1, got '0'"},
    {"map where a number goes", MINIMAL "numerics:\n  dx: {a: 1}\n  end_time: 3.0e-3\n", 13,
     "numerics.dx: expected a positive number (m), got a map"},
    {"numerics not a map", MINIMAL "numerics: 1\n", 12, "numerics: expected a map, got '1'"},
    {"no materials", "dimension: 2\nmaterials: []\n", 2,
     "materials: expected a sequence of 1 to 8 maps, got a sequence of 0 items"},
    {"name with a space", "dimension: 2\nname: my case\n", 2,
     "name: expected a name of 1 to 63 letters, digits, '_' or '-', got 'my case'"},
    {"window out of order",
     MINIMAL "groups:\n"
             "  - {name: tip, min: [0.099, -0.006], max: [0.101, 0.006]}\n"
             "numerics: {dx: 1e-3, end_time: 1e-3}\n"
             "probe: {name: tip_deflection, group: tip, quantity: displacement_y}\n"
             "reference:\n"
             "  value: 1\n"
             "  window: [2e-3, 1e-3]\n",
     18, "reference.window: expected [t0, t1] with t0 < t1 (s), got [0.002, 0.001]"},
    {"a held wall with friction",
     MINIMAL "numerics: {dx: 1e-3, end_time: 1e-3}\n"
             "walls:\n"
             "  - {name: anvil, point: [0, -0.005], normal: [0, 1], hold: true, friction: 0.2}\n",
     14,
     "walls.0.friction: a held wall is frictionless (its face slides freely), got friction 0.2"},
    {"a held wall off the axes",
     MINIMAL "numerics: {dx: 1e-3, end_time: 1e-3}\n"
             "walls:\n"
             "  - {name: anvil, point: [0, -0.005], normal: [0.6, 0.8], hold: true}\n",
     14, "walls.0.hold: a held wall needs a normal along x or y (a symmetry plane stands in"},
    {"a held wall off its axis' symmetry plane",
     MINIMAL "numerics: {dx: 1e-3, end_time: 1e-3}\n"
             "walls:\n"
             "  - {name: anvil, point: [0, -0.005], normal: [0, 1], hold: true}\n"
             "symmetry:\n"
             "  - {axis: y, position: 0.01}\n",
     13, "walls.0: wall 'anvil' is held on y = -0.005, but y = 0.01 is a symmetry plane"},
    {"a held wall off the axis of revolution",
     "dimension: 2\nplane: axisymmetric\n" /* the axis x = 0 is a symmetry plane */
     "materials:\n  - {name: steel, density: 7800, youngs_modulus: 210.0e9, poisson_ratio: 0.3}\n"
     "bodies:\n  - {name: bar, material: steel, min: [0, 0], max: [0.003, 0.03]}\n"
     "numerics: {dx: 1e-3, end_time: 1e-3}\n"
     "walls:\n"
     "  - {name: sleeve, point: [0.005, 0], normal: [-1, 0], hold: true}\n",
     8,
     "walls.0: wall 'sleeve' is held on x = 0.005, but x = 0 is the axis of an axisymmetric "
     "case"},
    {"two held walls on one axis",
     MINIMAL "numerics: {dx: 1e-3, end_time: 1e-3}\n"
             "walls:\n"
             "  - {name: floor, point: [0, -0.005], normal: [0, 1], hold: true}\n"
             "  - {name: lid, point: [0, 0.005], normal: [0, -1], hold: true}\n",
     13, "walls.1: wall 'lid' is held on y = 0.005, but wall 'floor' already holds y = -0.005"},
    {"a tensor smoothing length without CSPH",
     MINIMAL "numerics: {dx: 1e-3, end_time: 1e-3, smoothing: tensor}\n", 12,
     "numerics.smoothing: tensor needs csph: true"},
    {"a tensor smoothing length in an axisymmetric case",
     "dimension: 2\nplane: axisymmetric\n"
     "materials:\n  - {name: steel, density: 7800, youngs_modulus: 210.0e9, poisson_ratio: 0.3}\n"
     "bodies:\n  - {name: bar, material: steel, min: [0, 0], max: [0.003, 0.03]}\n"
     "numerics: {dx: 1e-3, end_time: 1e-3, csph: true, smoothing: tensor}\n",
     7, "numerics.smoothing: tensor is not built for an axisymmetric case"},
    {"a second document", "dimension: 2\n---\ndimension: 3\n", 3, "a second YAML document"},
    {"a list at the top", "- dimension: 2\n", 1, "expected a map of case keys, got a sequence"},
    {"too many materials",
     "dimension: 2\n"
     "materials: [{}, {}, {}, {}, {}, {}, {}, {}, {}]\n",
     2, "materials: expected a sequence of 1 to 8 maps, got a sequence of 9 items"},
};

static void test_bad_input(void **state)
{
    const struct bad_input *b = *state;
    static struct sph_case c;
    char error[SPH_ERROR_MAX], prefix[SPH_PATH_MAX + 32];
    char *path = temp_file(b->text);
    const int rc = case_load(path, 0, NULL, &c, error, sizeof error);
    snprintf(prefix, sizeof prefix, "%s:%d: ", path, b->line);
    drop_file(path);
    if (rc == 0)
        fail_msg("'%s' was accepted", b->name);
    print_message("  %s\n", error);
    if (strncmp(error, prefix, strlen(prefix)) != 0)
        fail_msg("expected '%s...', got '%s'", prefix, error);
    if (!strstr(error, b->words))
        fail_msg("expected '%s' in '%s'", b->words, error);
    assert_int_equal(c.dimension, 0); /* a failed load leaves nothing half-filled */
}

static void test_unreadable_file(void **state)
{
    (void)state;
    static struct sph_case c;
    char error[SPH_ERROR_MAX];
    assert_int_not_equal(case_load("/nonexistent/case.yaml", 0, NULL, &c, error, sizeof error), 0);
    assert_string_equal(error, "/nonexistent/case.yaml: cannot open: No such file or directory");
    assert_int_not_equal(load_text("", 0, NULL, &c, error, sizeof error), 0);
    assert_non_null(strstr(error, "empty case file"));
}

static void test_small_error_buffer(void **state)
{
    (void)state;
    static struct sph_case c;
    char error[12] = "xxxxxxxxxxx";
    assert_int_not_equal(load_text(MINIMAL, 0, NULL, &c, error, sizeof error), 0);
    assert_int_equal(strlen(error), sizeof error - 1);
    assert_int_not_equal(load_text(MINIMAL, 0, NULL, &c, NULL, 0), 0);
}

/* ---- --set ------------------------------------------------------------- */

static void test_set_overrides(void **state)
{
    (void)state;
    static struct sph_case c;
    char error[SPH_ERROR_MAX];
    char *sets[] = {"numerics.dx=0.5e-3",
                    "materials.steel.density=7850",
                    "bodies.beam.max=[0.2, 0.005]",
                    "numerics.damping=100",
                    "numerics.artificial_viscosity.alpha=0.5",
                    "groups.tip.load.law=linear_ramp",
                    "bodies.1.fixed=false",
                    "output.history_interval=1e-5"};
    const int rc =
        case_load(BEAM, (int)(sizeof sets / sizeof *sets), sets, &c, error, sizeof error);
    if (rc)
        fail_msg("%s", error);
    assert_true(c.numerics.dx == 0.5e-3);
    assert_true(c.materials[0].density == 7850);
    assert_true(c.bodies[0].box.max[0] == 0.2 && c.bodies[0].box.max[1] == 0.005);
    assert_true(c.bodies[0].box.min[0] == 0.0); /* untouched */
    assert_true(c.numerics.damping == 100);
    assert_true(c.numerics.av_alpha == 0.5 && c.numerics.av_beta == 1.5);
    assert_int_equal(c.groups[0].load.law, SPH_LOAD_LINEAR_RAMP);
    assert_int_equal(c.bodies[1].fixed, 0);
    assert_true(c.output.history_interval == 1e-5);
    assert_true(c.output.snapshot_interval == 1.5e-4);
}

/* A map the file does not have is created, then validated as usual. */
static void test_set_creates_maps(void **state)
{
    (void)state;
    static struct sph_case c;
    char error[SPH_ERROR_MAX];
    char *sets[] = {"output.snapshot_interval=1e-4", "materials.0.density=2700",
                    "numerics.artificial_stress.exponent=6"};
    const int rc = load_text(MINIMAL "numerics: {dx: 1e-3, end_time: 1e-3}\n", 3, sets, &c, error,
                             sizeof error);
    if (rc)
        fail_msg("%s", error);
    assert_true(c.output.snapshot_interval == 1e-4);
    assert_true(c.output.history_interval == 1e-3 / 1000);
    assert_true(c.materials[0].density == 2700);
    assert_int_equal(c.numerics.as_exponent, 6);
}

static void expect_set_error(const char *set, const char *words)
{
    static struct sph_case c;
    char error[SPH_ERROR_MAX];
    char *sets[1] = {(char *)set};
    if (case_load(BEAM, 1, sets, &c, error, sizeof error) == 0)
        fail_msg("--set %s was accepted", set);
    print_message("  %s\n", error);
    if (!strstr(error, "--set") || !strstr(error, words))
        fail_msg("expected '--set' and '%s' in '%s'", words, error);
    if (strncmp(error, BEAM ": ", strlen(BEAM ": ")) != 0)
        fail_msg("expected the file without a line in '%s'", error);
}

static void test_set_errors(void **state)
{
    (void)state;
    expect_set_error("numerics.foo=1", "--set numerics.foo: unknown key 'foo' in numerics");
    expect_set_error("numerics.dx=-1", "--set numerics.dx: expected a positive number (m)");
    expect_set_error("numerics.dx=", "--set numerics.dx: expected a positive number (m), got ''");
    expect_set_error("bodies.beam.max=[0.2, 0.005, 0.1]",
                     "--set bodies.0.max: expected a sequence of 2 numbers");
}

static void test_set_errors_walk(void **state)
{
    (void)state;
    expect_set_error("bodies.nothere.max=[1, 2]",
                     "--set 'bodies.nothere.max=[1, 2]': bodies has no item 'nothere'");
    expect_set_error("bodies.7.max=[1, 2]", "bodies has no item '7'");
    expect_set_error("bodies.beam.max=[0.2,", "malformed value");
    expect_set_error("numerics.dx", "--set 'numerics.dx': expected key.path=value");
    expect_set_error("numerics..dx=1", "empty key");
    expect_set_error("numerics.dx.foo=1", "numerics.dx is a value, not a map or a sequence");
    expect_set_error("materials.steel={name: steel, density: 1}",
                     "--set materials.0: missing required key 'youngs_modulus'");
}

/* ---- case_write_resolved ----------------------------------------------- */

static void round_trip(const char *path)
{
    static struct sph_case first, second;
    char error[SPH_ERROR_MAX];
    int rc = case_load(path, 0, NULL, &first, error, sizeof error);
    if (rc)
        fail_msg("%s", error);

    char *written = temp_file("");
    FILE *f = fopen(written, "w");
    assert_non_null(f);
    assert_int_equal(case_write_resolved(&first, f), 0);
    assert_int_equal(fclose(f), 0);
    rc = case_load(written, 0, NULL, &second, error, sizeof error);
    if (rc)
        fail_msg("%s (the file is kept)", error);
    drop_file(written);
    memcpy(second.path, first.path, sizeof second.path);
    assert_memory_equal(&first, &second, sizeof first);
}

static void test_round_trip_beam(void **state)
{
    (void)state;
    round_trip(BEAM);
}

static void test_round_trip_3d(void **state)
{
    (void)state;
    char *path = temp_file("name: block-3d\n"
                           "dimension: 3\n"
                           "materials:\n"
                           "  - name: steel\n"
                           "    density: 7850\n"
                           "    youngs_modulus: 2.0e11\n"
                           "    poisson_ratio: -0.25\n"
                           "    strength: perfectly_plastic\n"
                           "    yield_stress: 3.5e8\n"
                           "  - {name: alu, density: 2700, youngs_modulus: 7e10, "
                           "poisson_ratio: 0.33, eos: linear, strength: elastic}\n"
                           "bodies:\n"
                           "  - name: target\n"
                           "    material: alu\n"
                           "    min: [0, 0, 0]\n"
                           "    max: [0.1, 0.1, 0.01]\n"
                           "  - name: impactor\n"
                           "    material: steel\n"
                           "    min: [0.04, 0.04, 0.011]\n"
                           "    max: [0.06, 0.06, 0.031]\n"
                           "    velocity: [0, 0, -350.5]\n"
                           "groups:\n"
                           "  - name: rim\n"
                           "    min: [-1, -1, -1]\n"
                           "    max: [1, 1, 1e-3]\n"
                           "    fixed: yes\n"
                           "  - name: top\n"
                           "    body: impactor\n"
                           "    min: [0, 0, 0.03]\n"
                           "    max: [1, 1, 1]\n"
                           "    load: {force: [1, 2, -3.25]}\n"
                           "numerics:\n"
                           "  dx: 0.1e-2\n"
                           "  kernel: cubic_spline\n"
                           "  h_over_dx: 1.5\n"
                           "  artificial_viscosity: {alpha: 1, beta: 2}\n"
                           "  artificial_stress: {epsilon: 0.3, exponent: 6}\n"
                           "  xsph: 0.1\n"
                           "  csph: true\n"
                           "  cfl: 1\n"
                           "  end_time: 1e-4\n"
                           "  damping: 12.5\n"
                           "  precision: double\n"
                           "probe: {name: dz, group: top, quantity: displacement_z}\n"
                           "reference: {value: -1e-3, source: \"a \\\"quoted\\\" \\\\ source\"}\n");
    round_trip(path);
    static struct sph_case c;
    char error[SPH_ERROR_MAX];
    const int rc = case_load(path, 0, NULL, &c, error, sizeof error);
    drop_file(path);
    if (rc)
        fail_msg("%s", error);
    assert_string_equal(c.name, "block-3d");
    assert_true(c.materials[0].poisson_ratio == -0.25);
    assert_true(c.materials[0].yield_stress == 3.5e8);
    assert_int_equal(c.groups[0].body, -1);
    assert_int_equal(c.groups[0].fixed, 1);
    assert_int_equal(c.groups[0].load.enabled, 0);
    assert_int_equal(c.groups[1].body, 1);
    assert_int_equal(c.groups[1].load.law, SPH_LOAD_CONSTANT);
    assert_true(c.groups[1].load.force[2] == -3.25);
    assert_true(c.bodies[1].velocity[2] == -350.5);
    assert_int_equal(c.numerics.double_precision, 1);
    assert_int_equal(c.numerics.csph, 1);
    assert_int_equal(c.probe.quantity, SPH_PROBE_DISPLACEMENT_Z);
    assert_true(c.reference.window[0] == 0 && c.reference.window[1] == 1e-4);
    assert_string_equal(c.reference.source, "a \"quoted\" \\ source");
}

static void test_round_trip_minimal(void **state)
{
    (void)state;
    char *path = temp_file(MINIMAL "numerics: {dx: 1e-3, end_time: 0.7e-3}\n");
    round_trip(path);
    drop_file(path);
}

/* A resumed run reloads the resolved case, so the resolved case must load
 * back to the same bits: an oblique wall normal, normalised once, is not
 * normalised again (twice moved its last digits). */
static void test_round_trip_oblique_wall(void **state)
{
    (void)state;
    char *path = temp_file(MINIMAL "numerics: {dx: 1e-3, end_time: 1e-3}\n"
                                   "walls:\n"
                                   "  - {name: a, point: [0, -0.01], normal: [0.6, 0.8]}\n"
                                   "  - {name: b, point: [0.2, 0], normal: [-1, 3]}\n");
    round_trip(path);
    drop_file(path);
}

/* A held wall is a symmetry plane on its normal's axis at its point, and the
 * resolved case (which lists that plane) loads back to the same case. */
static void test_held_wall_plane(void **state)
{
    (void)state;
    static struct sph_case c;
    char error[SPH_ERROR_MAX];
    const char *text =
        MINIMAL "numerics: {dx: 1e-3, end_time: 1e-3}\n"
                "walls:\n"
                "  - {name: anvil, point: [0, -0.005], normal: [0, 2], hold: true}\n";
    if (load_text(text, 0, NULL, &c, error, sizeof error))
        fail_msg("%s", error);
    assert_int_equal(c.walls[0].hold, 1);
    assert_int_equal(c.symmetry_count, 1);
    assert_int_equal(c.symmetry[0].axis, 1);
    assert_true(c.symmetry[0].position == -0.005);
    assert_int_equal(case_held_wall_axes(&c), 2u);
    char *path = temp_file(text);
    round_trip(path);
    drop_file(path);
}

/* In a float run every number must fit a float (it would reach the device
 * as inf or 0); a double run takes it. */
static void test_float_range(void **state)
{
    (void)state;
    static struct sph_case c;
    char error[SPH_ERROR_MAX];
    const char *text = MINIMAL "numerics: {dx: 1e-3, end_time: 1e-3}\n";
    char *dense[] = {"materials.steel.density=1e308"};
    assert_int_not_equal(load_text(text, 1, dense, &c, error, sizeof error), 0);
    assert_non_null(strstr(error, "materials[0].density = 1e+308 is outside single precision"));
    char *dense_double[] = {"materials.steel.density=1e308", "numerics.precision=double"};
    if (load_text(text, 2, dense_double, &c, error, sizeof error))
        fail_msg("%s", error);
    char *tiny[] = {"bodies.beam.velocity=[1e-300, 0]"};
    assert_int_not_equal(load_text(text, 1, tiny, &c, error, sizeof error), 0);
    assert_non_null(strstr(error, "bodies[0].velocity = 1e-300"));
}

/* A wall normal is normalised without overflow: [1e308, 1e308] is the
 * diagonal, not [0, 0] (its squares overflowed). */
static void test_wall_normal_scaled(void **state)
{
    (void)state;
    static struct sph_case c;
    char error[SPH_ERROR_MAX];
    char *sets[] = {"walls=[{name: floor, point: [0, 0], normal: [1e308, 1e308]}]"};
    if (load_text(MINIMAL "numerics: {dx: 1e-3, end_time: 1e-3}\n", 1, sets, &c, error,
                  sizeof error))
        fail_msg("%s", error);
    assert_float_equal(c.walls[0].normal[0], sqrt(0.5), 1e-15);
    assert_float_equal(c.walls[0].normal[1], sqrt(0.5), 1e-15);
}

/* An alias bomb in a --set value is refused before it expands. */
static void test_set_alias_bomb(void **state)
{
    (void)state;
    static struct sph_case c;
    char error[SPH_ERROR_MAX], value[1024] = "numerics.x=[&a [1,1,1,1,1,1,1,1,1,1]";
    for (char n = 'b'; n <= 'i'; ++n) {
        char level[64];
        snprintf(level, sizeof level, ", &%c [", n);
        strcat(value, level);
        for (int k = 0; k < 10; ++k)
            snprintf(level, sizeof level, "%s*%c", k ? "," : "", n - 1), strcat(value, level);
        strcat(value, "]");
    }
    strcat(value, "]");
    char *sets[] = {value};
    assert_int_not_equal(load_text(MINIMAL "numerics: {dx: 1e-3, end_time: 1e-3}\n", 1, sets, &c,
                                   error, sizeof error),
                         0);
    assert_non_null(strstr(error, "value expands to more than"));
}

/* numerics.lane_lists auto (host/state.c, solver_choose_lane_lists): the
 * lists where the case fits with them, none where it fits only without
 * them, and the lists kept where it fits neither way (the memory check
 * then refuses it and names the key). */
static void lane_lists_for(double particles, double device_bytes, int expected)
{
    struct sph_case c;
    char error[512];
    assert_int_equal(
        case_load(SPH_SOURCE_DIR "/cases/gelatin_silica_3d.yaml", 0, NULL, &c, error, sizeof error),
        0);
    assert_int_equal(c.numerics.lane_lists, SPH_LANE_LISTS_AUTO);
    solver_choose_lane_lists(&c, particles, device_bytes, 1);
    assert_int_equal(c.numerics.lane_lists, expected);
}

static void test_lane_lists_auto(void **state)
{
    (void)state;
    struct sph_case c;
    char error[512];
    assert_int_equal(
        case_load(SPH_SOURCE_DIR "/cases/gelatin_silica_3d.yaml", 0, NULL, &c, error, sizeof error),
        0);
    const double with = (double)solver_case_bytes_per_particle(&c),
                 lists = (double)solver_lane_list_estimate(&c), n = 1e7;
    assert_true(lists > 0 && lists < with);
    lane_lists_for(n, 2 * n * with, 1);
    lane_lists_for(n, n * (with - 0.5 * lists), 0);
    lane_lists_for(n, 0.5 * n * (with - lists), 1);
}

int main(void)
{
    struct CMUnitTest tests[96] = {
        cmocka_unit_test(test_beam_loads),         cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_kernel_names),       cmocka_unit_test(test_unreadable_file),
        cmocka_unit_test(test_small_error_buffer), cmocka_unit_test(test_set_overrides),
        cmocka_unit_test(test_set_creates_maps),   cmocka_unit_test(test_set_errors),
        cmocka_unit_test(test_set_errors_walk),    cmocka_unit_test(test_round_trip_beam),
        cmocka_unit_test(test_round_trip_3d),      cmocka_unit_test(test_round_trip_minimal),
        cmocka_unit_test(test_float_range),        cmocka_unit_test(test_wall_normal_scaled),
        cmocka_unit_test(test_set_alias_bomb),     cmocka_unit_test(test_round_trip_oblique_wall),
        cmocka_unit_test(test_held_wall_plane),    cmocka_unit_test(test_lane_lists_auto),
    };
    int n = 0; /* the entries above (a hand count left one out) */
    while (tests[n].test_func)
        ++n;
    const int bad = (int)(sizeof bad_inputs / sizeof *bad_inputs);
    if (n + bad > (int)(sizeof tests / sizeof *tests)) {
        fprintf(stderr, "test_case: the test table is too small\n");
        return 1;
    }
    for (int i = 0; i < bad; ++i) {
        struct CMUnitTest t = cmocka_unit_test_prestate(test_bad_input, (void *)&bad_inputs[i]);
        t.name = bad_inputs[i].name;
        tests[n++] = t;
    }
    return _cmocka_run_group_tests("case", tests, (size_t)n, NULL, NULL);
}
