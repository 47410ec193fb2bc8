/* The steal share sph bench reports (host/cpu_steal.c): /proc/stat lines
 * with and without the steal field, lines that are not the aggregate, and
 * the share between two readings. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "cpu_steal.h"

static void parses_a_current_kernel_line(void **state)
{
    (void)state;
    struct cpu_times t;
    /* user nice system idle iowait irq softirq steal guest guest_nice */
    assert_int_equal(cpu_times_parse("cpu  100 5 20 800 10 1 4 60 30 0\n", &t), 0);
    assert_true(t.valid);
    assert_float_equal(t.total, 1000.0, 0.0); /* guest is inside user: not added */
    assert_float_equal(t.steal, 60.0, 0.0);
}

static void an_old_kernel_has_no_steal(void **state)
{
    (void)state;
    struct cpu_times t;
    assert_int_equal(cpu_times_parse("cpu 10 0 5 85 0 0 0\n", &t), 0);
    assert_float_equal(t.total, 100.0, 0.0);
    assert_float_equal(t.steal, 0.0, 0.0);
}

static void other_lines_are_refused(void **state)
{
    (void)state;
    struct cpu_times t;
    assert_int_equal(cpu_times_parse("cpu0 1 2 3 4 5 6 7 8\n", &t), -1);
    assert_int_equal(cpu_times_parse("intr 12345\n", &t), -1);
    assert_int_equal(cpu_times_parse("cpu  1 2\n", &t), -1);
    assert_int_equal(cpu_times_parse("cpu  1 -2 3 4\n", &t), -1);
    assert_false(t.valid);
}

static void share_between_two_readings(void **state)
{
    (void)state;
    struct cpu_times a, b;
    cpu_times_parse("cpu  100 0 0 800 0 0 0 100 0 0", &a);
    cpu_times_parse("cpu  250 0 0 900 0 0 0 150 0 0", &b); /* 300 ticks, 50 stolen */
    assert_float_equal(cpu_steal_fraction(&a, &b), 50.0 / 300.0, 1e-15);
    assert_true(isnan(cpu_steal_fraction(&a, &a))); /* no time passed */
    b.valid = 0;
    assert_true(isnan(cpu_steal_fraction(&a, &b)));
}

static void reads_this_machine(void **state)
{
    (void)state;
    const struct cpu_times now = cpu_times_now();
    if (!now.valid)
        skip(); /* no /proc/stat: not Linux */
    assert_true(now.total > 0);
    assert_true(now.steal >= 0 && now.steal <= now.total);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(parses_a_current_kernel_line),
        cmocka_unit_test(an_old_kernel_has_no_steal),
        cmocka_unit_test(other_lines_are_refused),
        cmocka_unit_test(share_between_two_readings),
        cmocka_unit_test(reads_this_machine),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
