/*
 * Case files: YAML (libyaml's document API) -> struct sph_case.
 *
 * Every map of the format is a table of fields (key, type, range, default,
 * offset into the struct it fills); one reader walks the tables, and one
 * writer walks them again for case_write_resolved(). What a table cannot say
 * (cross-field rules, defaults that depend on other keys) is in the map's
 * check function. --set overrides are grafted into the document before
 * validation, so they go through exactly the same checks.
 */
#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <yaml.h>

#include "sph_case.h"

/* Enum members are filled through int pointers. */
_Static_assert(sizeof(enum sph_kernel_type) == sizeof(int), "enum size");
_Static_assert(sizeof(enum sph_eos_type) == sizeof(int), "enum size");
_Static_assert(sizeof(enum sph_strength_type) == sizeof(int), "enum size");
_Static_assert(sizeof(enum sph_plane_mode) == sizeof(int), "enum size");
_Static_assert(sizeof(enum sph_load_law) == sizeof(int), "enum size");
_Static_assert(sizeof(enum sph_shape) == sizeof(int), "enum size");
_Static_assert(sizeof(enum sph_failure) == sizeof(int), "enum size");
_Static_assert(sizeof(enum sph_probe_quantity) == sizeof(int), "enum size");

#define ARRAY_LEN(a) ((int)(sizeof(a) / sizeof *(a)))
#define MAX_FIELDS 20
#define KEY_MAX 256
/* start_mark.line of nodes grafted by --set: no file line can be this. */
#define SET_LINE ((size_t)-1)

enum kind { K_NUMBER, K_INT, K_BOOL, K_ENUM, K_STRING, K_NAME, K_REF, K_VECTOR, K_MAP, K_LIST };
enum range { R_ANY, R_POSITIVE, R_NONNEG, R_CLOSED, R_OPEN, R_LEFT_OPEN };
enum flag {
    F_REQUIRED = 1,
    F_2D_ONLY = 2,   /* an error in 3-D; not written in 3-D */
    F_OMIT_ZERO = 4, /* only valid when positive, so 0 means "not given" */
    F_UNIQUE = 8,    /* unique among the items of the list */
    F_ENABLE = 16,   /* K_MAP: set the int at aux to 1 when the map is given */
    F_CYLINDER = 32, /* a body key of cylinders only: not written for other shapes */
    F_TRACK = 64,    /* a grading key of the track form only */
    F_BOX = 128      /* a grading key of the box form only */
};
enum ref_kind { REF_MATERIAL, REF_BODY, REF_GROUP };

struct ctx;
struct frame;
struct schema;

struct field {
    const char *key;
    enum kind kind;
    unsigned flags;
    enum range range;
    double lo, hi; /* range; K_INT bounds; K_LIST item count bounds */
    double def;    /* default of K_NUMBER, K_INT, K_BOOL, K_ENUM (index), K_REF */
    size_t offset; /* of the member, from the start of the struct the map fills */
    size_t aux;    /* K_STRING, K_NAME: buffer size; K_VECTOR: length (0: dimension);
                      K_REF: enum ref_kind; K_LIST: offset of the count;
                      K_MAP with F_ENABLE: offset of the flag */
    const char *unit;
    const char *what;         /* replaces the generated "expected ..." text */
    const char *const *names; /* K_ENUM */
    const struct schema *sub; /* K_MAP (base shifted by offset), K_LIST (items) */
};

struct schema {
    const struct field *fields;
    int count;
    size_t size; /* of one item when the map is a list item */
    int (*check)(struct ctx *x, const struct frame *fr, void *base);
};

/* One map being read: which node holds each field. */
struct frame {
    const struct schema *schema;
    int blame;             /* node whose line names the map */
    int value[MAX_FIELDS]; /* value node of each field; 0 when absent */
    int at[MAX_FIELDS];    /* node whose line names the field */
};

struct ctx {
    const char *path;
    yaml_document_t *doc;
    struct sph_case *c;
    char key[KEY_MAX]; /* key path being read, e.g. "bodies.0.max" */
    char sub[KEY_MAX];
    char *error;
    size_t error_size, error_len;
};

static const char *const kernel_names[] = {
    "cubic_spline", "gaussian", "quintic_spline", "wendland_c2", "double_cosine",
    "hyperbolic",   NULL};
_Static_assert(ARRAY_LEN(kernel_names) == SPH_KERNEL_COUNT + 1, "one name per kernel");
static const char *const plane_names[] = {"stress", "strain", "axisymmetric", NULL};
static const char *const eos_names[] = {"linear", "mie_gruneisen", "polynomial", NULL};
static const char *const strength_names[] = {"elastic", "perfectly_plastic", "johnson_cook", NULL};
static const char *const shape_names[] = {"box", "cylinder", NULL};
static const char *const failure_names[] = {"none", "yield", "plastic_strain", NULL};
static const char *const axis_names[] = {"x", "y", "z", NULL};
static const char *const law_names[] = {"constant", "linear_ramp", "quadratic_ramp", NULL};
static const char *const quantity_names[] = {"displacement_x", "displacement_y", "displacement_z",
                                             NULL};
static const char *const precision_names[] = {"float", "double", NULL};
static const char *const as_weight_names[] = {"relative", "lattice", NULL};
static const char *const neighbour_loop_names[] = {"lanes", "plain", "auto", NULL};
static const char *const lane_lists_names[] = {"false", "true", "auto", NULL};
static const char *const formulation_names[] = {"updated_lagrangian", "total_lagrangian", NULL};
static const char *const smoothing_names[] = {"isotropic", "tensor", NULL};
static const char *const av_scheme_names[] = {"monaghan", "limited", "switch", "cullen_dehnen",
                                              NULL};
static const char *const motion_names[] = {"free", "prescribed", NULL};
static const char *const contact_names[] = {"free_slip", "no_slip", NULL};
static const char *const boundary_names[] = {"penalty", "integral", NULL};
static const char *const ref_nouns[] = {"material", "body", "group"};

/* ---- errors ------------------------------------------------------------ */

static void vput(struct ctx *x, const char *fmt, va_list ap)
{
    if (!x->error || x->error_len + 1 >= x->error_size)
        return;
    const int n = vsnprintf(x->error + x->error_len, x->error_size - x->error_len, fmt, ap);
    if (n > 0)
        x->error_len += (size_t)n;
    if (x->error_len >= x->error_size)
        x->error_len = x->error_size - 1;
}

static void put(struct ctx *x, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vput(x, fmt, ap);
    va_end(ap);
}

static yaml_node_t *node(struct ctx *x, int id)
{
    return id ? yaml_document_get_node(x->doc, id) : NULL;
}

static int from_set(struct ctx *x, int id)
{
    const yaml_node_t *n = node(x, id);
    return n && n->start_mark.line == SET_LINE;
}

/* "<path>:<line>: <key path>: message", or "<path>: --set <key path>: message"
 * when the node came from --set; `id` 0 gives no line. Returns -1. */
static int fail(struct ctx *x, int id, const char *key_path, const char *fmt, ...)
{
    const yaml_node_t *n = node(x, id);
    const int has_key = key_path && *key_path;
    x->error_len = 0;
    if (n && n->start_mark.line == SET_LINE)
        put(x, "%s: --set %s: ", x->path, has_key ? key_path : "(top level)");
    else if (n)
        put(x, "%s:%zu: %s%s", x->path, n->start_mark.line + 1, has_key ? key_path : "",
            has_key ? ": " : "");
    else
        put(x, "%s: %s%s", x->path, has_key ? key_path : "", has_key ? ": " : "");
    va_list ap;
    va_start(ap, fmt);
    vput(x, fmt, ap);
    va_end(ap);
    return -1;
}

static int fail_set(struct ctx *x, const char *arg, const char *fmt, ...)
{
    x->error_len = 0;
    put(x, "%s: --set '%s': ", x->path, arg ? arg : "");
    va_list ap;
    va_start(ap, fmt);
    vput(x, fmt, ap);
    va_end(ap);
    return -1;
}

/* Appends the strings up to NULL to `dst`, cut to fit `size`. */
static void append(char *dst, size_t size, ...)
{
    size_t n = strlen(dst);
    va_list ap;
    va_start(ap, size);
    for (const char *s = va_arg(ap, const char *); s; s = va_arg(ap, const char *))
        for (; *s && n + 1 < size; ++s)
            dst[n++] = *s;
    va_end(ap);
    dst[n] = '\0';
}

static size_t push(struct ctx *x, const char *segment)
{
    const size_t n = strlen(x->key);
    append(x->key, sizeof x->key, n ? "." : "", segment, (char *)NULL);
    return n;
}

static void pop(struct ctx *x, size_t mark)
{
    x->key[mark] = '\0';
}

/* The key path of `key` inside the map being read. */
static const char *subkey(struct ctx *x, const char *key)
{
    x->sub[0] = '\0';
    append(x->sub, sizeof x->sub, x->key, *x->key ? "." : "", key, (char *)NULL);
    return x->sub;
}

/* ---- scalars ----------------------------------------------------------- */

static const char *scalar_text(const yaml_node_t *n)
{
    if (n->type != YAML_SCALAR_NODE ||
        strlen((const char *)n->data.scalar.value) != n->data.scalar.length)
        return NULL;
    return (const char *)n->data.scalar.value;
}

static const char *plain_text(const yaml_node_t *n)
{
    return n->type == YAML_SCALAR_NODE && n->data.scalar.style == YAML_PLAIN_SCALAR_STYLE
               ? scalar_text(n)
               : NULL;
}

static int parse_number(const yaml_node_t *n, double *v)
{
    const char *s = plain_text(n);
    char *end;
    if (!s || !*s || isspace((unsigned char)*s))
        return -1;
    errno = 0;
    *v = strtod(s, &end);
    return *end || errno == ERANGE || !isfinite(*v) ? -1 : 0;
}

static int parse_int(const yaml_node_t *n, int *v)
{
    const char *s = plain_text(n);
    char *end;
    if (!s || !*s || isspace((unsigned char)*s))
        return -1;
    errno = 0;
    const long l = strtol(s, &end, 10);
    if (*end || errno == ERANGE || l < -1000000 || l > 1000000)
        return -1;
    *v = (int)l;
    return 0;
}

static int parse_bool(const yaml_node_t *n, int *v)
{
    static const char *const yes[] = {"true", "True", "TRUE", "yes", "Yes", "YES"};
    static const char *const no[] = {"false", "False", "FALSE", "no", "No", "NO"};
    const char *s = plain_text(n);
    for (int i = 0; s && i < ARRAY_LEN(yes); ++i)
        if (strcmp(s, yes[i]) == 0 || strcmp(s, no[i]) == 0) {
            *v = strcmp(s, yes[i]) == 0;
            return 0;
        }
    return -1;
}

static int is_name(const char *s, size_t size)
{
    const size_t n = strlen(s);
    if (n == 0 || n >= size)
        return 0;
    for (size_t i = 0; i < n; ++i)
        if (!isalnum((unsigned char)s[i]) && s[i] != '_' && s[i] != '-')
            return 0;
    return 1;
}

static int in_range(const struct field *f, double v)
{
    switch (f->range) {
    case R_ANY:
        return 1;
    case R_POSITIVE:
        return v > 0;
    case R_NONNEG:
        return v >= 0;
    case R_CLOSED:
        return v >= f->lo && v <= f->hi;
    case R_OPEN:
        return v > f->lo && v < f->hi;
    case R_LEFT_OPEN:
        return v > f->lo && v <= f->hi;
    }
    return 0;
}

/* ---- "expected ..., got ..." ------------------------------------------- */

static void join(char *buf, size_t size, const char *const *names, int count, const char *last)
{
    size_t n = strlen(buf);
    for (int i = 0; i < count && n < size; ++i) {
        const char *sep = i == 0 ? "" : i == count - 1 && last ? last : ", ";
        n += (size_t)snprintf(buf + n, size - n, "%s%s", sep, names[i]);
    }
}

static int count_names(const char *const *names)
{
    int n = 0;
    while (names[n])
        ++n;
    return n;
}

static void describe(const struct ctx *x, const struct field *f, char *buf, size_t size)
{
    static const char *const axes[] = {"x", "y", "z"};
    const char *unit_open = f->unit ? " (" : "", *unit = f->unit ? f->unit : "";
    const char *unit_close = f->unit ? ")" : "";
    buf[0] = '\0';
    if (f->what) {
        snprintf(buf, size, "%s", f->what);
        return;
    }
    switch (f->kind) {
    case K_NUMBER:
        switch (f->range) {
        case R_ANY:
            snprintf(buf, size, "a number%s%s%s", unit_open, unit, unit_close);
            break;
        case R_POSITIVE:
            snprintf(buf, size, "a positive number%s%s%s", unit_open, unit, unit_close);
            break;
        case R_NONNEG:
            snprintf(buf, size, "a non-negative number%s%s%s", unit_open, unit, unit_close);
            break;
        case R_CLOSED:
            snprintf(buf, size, "a number from %g to %g", f->lo, f->hi);
            break;
        case R_OPEN:
            snprintf(buf, size, "a number greater than %g and less than %g", f->lo, f->hi);
            break;
        case R_LEFT_OPEN:
            snprintf(buf, size, "a number greater than %g and at most %g", f->lo, f->hi);
            break;
        }
        break;
    case K_INT:
        snprintf(buf, size, "an integer from %g to %g", f->lo, f->hi);
        break;
    case K_BOOL:
        snprintf(buf, size, "true or false");
        break;
    case K_ENUM: {
        const int n = count_names(f->names);
        snprintf(buf, size, "%s", n > 2 ? "one of " : "");
        join(buf, size, f->names, n, n == 2 ? " or " : NULL);
        break;
    }
    case K_STRING:
        snprintf(buf, size, "a string of at most %zu characters", f->aux - 1);
        break;
    case K_NAME:
        snprintf(buf, size, "a name of 1 to %zu letters, digits, '_' or '-'", f->aux - 1);
        break;
    case K_REF:
        snprintf(buf, size, "the name of a %s", ref_nouns[f->aux]);
        break;
    case K_VECTOR: {
        const int n = f->aux ? (int)f->aux : x->c->dimension;
        snprintf(buf, size, "a sequence of %d numbers", n);
        if (n <= 3) { /* an axis each; longer ones (a tensor row by row) say so in README */
            strncat(buf, " [", size - strlen(buf) - 1);
            join(buf, size, axes, n, NULL);
            strncat(buf, "]", size - strlen(buf) - 1);
        }
        const size_t len = strlen(buf);
        snprintf(buf + len, size - len, "%s%s%s", unit_open, unit, unit_close);
        break;
    }
    case K_MAP:
        snprintf(buf, size, "a map");
        break;
    case K_LIST:
        snprintf(buf, size, "a sequence of %g to %g maps", f->lo, f->hi);
        break;
    }
}

static const char *got(const yaml_node_t *n, char *buf, size_t size)
{
    switch (n->type) {
    case YAML_SCALAR_NODE:
        if (n->data.scalar.style == YAML_PLAIN_SCALAR_STYLE)
            snprintf(buf, size, "'%.80s'", (const char *)n->data.scalar.value);
        else
            snprintf(buf, size, "the quoted string '%.80s'", (const char *)n->data.scalar.value);
        break;
    case YAML_SEQUENCE_NODE: {
        const long items = (long)(n->data.sequence.items.top - n->data.sequence.items.start);
        snprintf(buf, size, "a sequence of %ld item%s", items, items == 1 ? "" : "s");
        break;
    }
    case YAML_MAPPING_NODE:
        snprintf(buf, size, "a map");
        break;
    default:
        snprintf(buf, size, "nothing");
        break;
    }
    return buf;
}

static int expected(struct ctx *x, const struct field *f, int at, int value)
{
    char what[512], seen[160];
    describe(x, f, what, sizeof what);
    return fail(x, at, x->key, "expected %s, got %s", what, got(node(x, value), seen, sizeof seen));
}

/* ---- reading values ---------------------------------------------------- */

static int ref_count(const struct sph_case *c, size_t kind)
{
    return kind == REF_MATERIAL ? c->material_count
           : kind == REF_BODY   ? c->body_count
                                : c->group_count;
}

static const char *ref_name(const struct sph_case *c, size_t kind, int i)
{
    return kind == REF_MATERIAL ? c->materials[i].name
           : kind == REF_BODY   ? c->bodies[i].name
                                : c->groups[i].name;
}

static int read_map(struct ctx *x, const struct schema *s, char *base, int map, int blame);

static int read_string(struct ctx *x, const struct field *f, char *p, int at, int value)
{
    const char *s = scalar_text(node(x, value));
    if (!s || (f->kind == K_NAME ? !is_name(s, f->aux) : strlen(s) >= f->aux))
        return expected(x, f, at, value);
    memcpy(p, s, strlen(s) + 1);
    return 0;
}

static int read_ref(struct ctx *x, const struct field *f, int *p, int at, int value)
{
    const char *s = scalar_text(node(x, value));
    if (!s)
        return expected(x, f, at, value);
    const int n = ref_count(x->c, f->aux);
    for (int i = 0; i < n; ++i)
        if (strcmp(s, ref_name(x->c, f->aux, i)) == 0) {
            *p = i;
            return 0;
        }
    if (n == 0)
        return fail(x, at, x->key, "unknown %s '%.80s'; no %s is defined", ref_nouns[f->aux], s,
                    ref_nouns[f->aux]);
    char known[512] = "";
    for (int i = 0; i < n; ++i) {
        const size_t len = strlen(known);
        snprintf(known + len, sizeof known - len, "%s%s", i ? ", " : "", ref_name(x->c, f->aux, i));
    }
    return fail(x, at, x->key, "unknown %s '%.80s'; expected one of: %s", ref_nouns[f->aux], s,
                known);
}

/* Bytes of the member: fixed-length vectors are that long, the others [3]. */
/* The longest K_VECTOR (bodies[].velocity_gradient's 9). */
#define VECTOR_MAX 9

static size_t vector_size(const struct field *f)
{
    return (f->aux ? f->aux : 3) * sizeof(double);
}

static int read_vector(struct ctx *x, const struct field *f, double *p, int at, int value)
{
    const yaml_node_t *n = node(x, value);
    const int len = f->aux ? (int)f->aux : x->c->dimension;
    if (n->type != YAML_SEQUENCE_NODE ||
        n->data.sequence.items.top - n->data.sequence.items.start != len)
        return expected(x, f, at, value);
    double v[VECTOR_MAX] = {0};
    for (int i = 0; i < len; ++i) {
        const int item = n->data.sequence.items.start[i];
        if (parse_number(node(x, item), &v[i]))
            return expected(x, f, at, item);
    }
    memcpy(p, v, vector_size(f));
    return 0;
}

/* The node whose line names `key` of the map `map`. */
static int key_line(struct ctx *x, int map, const char *key)
{
    const yaml_node_t *m = node(x, map);
    for (const yaml_node_pair_t *p = m->data.mapping.pairs.start; p < m->data.mapping.pairs.top;
         ++p) {
        const char *k = scalar_text(node(x, p->key));
        if (k && strcmp(k, key) == 0)
            return from_set(x, p->value) ? p->value : p->key;
    }
    return map;
}

/* Item i of a list against the items before it. */
static int check_unique(struct ctx *x, const struct schema *s, const struct field *u,
                        const char *items, int i, int item)
{
    const char *mine = items + (size_t)i * s->size + u->offset;
    for (int j = 0; j < i; ++j)
        if (strcmp(mine, items + (size_t)j * s->size + u->offset) == 0)
            return fail(x, key_line(x, item, u->key), subkey(x, u->key),
                        "duplicate %s '%s' (also item %d)", u->key, mine, j);
    return 0;
}

static int read_list(struct ctx *x, const struct field *f, char *base, int at, int value)
{
    const yaml_node_t *n = node(x, value);
    const long count = n->type == YAML_SEQUENCE_NODE
                           ? (long)(n->data.sequence.items.top - n->data.sequence.items.start)
                           : -1;
    if (count < f->lo || count > f->hi)
        return expected(x, f, at, value);
    const struct schema *s = f->sub;
    char *items = base + f->offset;
    for (int i = 0; i < count; ++i) {
        const int item = n->data.sequence.items.start[i];
        char index[16];
        snprintf(index, sizeof index, "%d", i);
        const size_t mark = push(x, index);
        int rc = read_map(x, s, items + (size_t)i * s->size, item, item);
        for (int k = 0; !rc && k < s->count; ++k)
            if (s->fields[k].flags & F_UNIQUE)
                rc = check_unique(x, s, &s->fields[k], items, i, item);
        pop(x, mark);
        if (rc)
            return rc;
    }
    *(int *)(base + f->aux) = (int)count;
    return 0;
}

static int has_required(const struct schema *s)
{
    for (int i = 0; i < s->count; ++i)
        if (s->fields[i].flags & F_REQUIRED)
            return 1;
    return 0;
}

static int set_default(struct ctx *x, const struct field *f, char *base)
{
    void *p = base + f->offset;
    switch (f->kind) {
    case K_NUMBER:
        *(double *)p = f->def;
        break;
    case K_INT:
    case K_BOOL:
    case K_ENUM:
    case K_REF:
        *(int *)p = (int)f->def;
        break;
    case K_STRING:
    case K_NAME:
        *(char *)p = '\0';
        break;
    case K_VECTOR:
        memset(p, 0, vector_size(f));
        break;
    case K_MAP:
        /* An absent map with required keys stays off; others take their defaults. */
        return has_required(f->sub) ? 0 : read_map(x, f->sub, base + f->offset, 0, 0);
    case K_LIST:
        *(int *)(base + f->aux) = 0;
        break;
    }
    return 0;
}

static int read_value(struct ctx *x, const struct field *f, char *base, int at, int value)
{
    void *p = base + f->offset;
    const yaml_node_t *n = node(x, value);
    if ((f->flags & F_2D_ONLY) && x->c->dimension != 2)
        return fail(x, at, x->key, "only allowed when dimension is 2");
    switch (f->kind) {
    case K_NUMBER: {
        double v;
        if (parse_number(n, &v) || !in_range(f, v))
            return expected(x, f, at, value);
        *(double *)p = v;
        return 0;
    }
    case K_INT: {
        int v;
        if (parse_int(n, &v) || v < f->lo || v > f->hi)
            return expected(x, f, at, value);
        *(int *)p = v;
        return 0;
    }
    case K_BOOL:
        return parse_bool(n, p) ? expected(x, f, at, value) : 0;
    case K_ENUM: {
        const char *s = scalar_text(n);
        for (int i = 0; s && f->names[i]; ++i)
            if (strcmp(s, f->names[i]) == 0) {
                *(int *)p = i;
                return 0;
            }
        return expected(x, f, at, value);
    }
    case K_STRING:
    case K_NAME:
        return read_string(x, f, p, at, value);
    case K_REF:
        return read_ref(x, f, p, at, value);
    case K_VECTOR:
        return read_vector(x, f, p, at, value);
    case K_MAP:
        if (f->flags & F_ENABLE)
            *(int *)(base + f->aux) = 1;
        return read_map(x, f->sub, base + f->offset, value, at);
    case K_LIST:
        return read_list(x, f, base, at, value);
    }
    return -1;
}

static int slot(const struct schema *s, const char *key)
{
    for (int i = 0; i < s->count; ++i)
        if (strcmp(s->fields[i].key, key) == 0)
            return i;
    return -1;
}

static int given(const struct frame *fr, const char *key)
{
    return fr->value[slot(fr->schema, key)];
}

static int line_of(const struct frame *fr, const char *key)
{
    const int i = slot(fr->schema, key);
    return fr->value[i] ? fr->at[i] : fr->blame;
}

static int unknown_key(struct ctx *x, const struct schema *s, int key_node, const char *key)
{
    char keys[512] = "";
    for (int i = 0; i < s->count; ++i) {
        const size_t len = strlen(keys);
        snprintf(keys + len, sizeof keys - len, "%s%s", i ? ", " : "", s->fields[i].key);
    }
    return fail(x, key_node, from_set(x, key_node) ? subkey(x, key) : NULL,
                "unknown key '%.80s' %s%s; expected one of: %s", key,
                *x->key ? "in " : "at top level", x->key, keys);
}

/* Fills fr->value/at from the pairs of `map`, rejecting unknown and repeated keys. */
static int index_pairs(struct ctx *x, struct frame *fr, int map)
{
    const yaml_node_t *n = node(x, map);
    char seen[160];
    if (n->type != YAML_MAPPING_NODE)
        return fail(x, fr->blame, x->key, "expected a map, got %s", got(n, seen, sizeof seen));
    for (const yaml_node_pair_t *p = n->data.mapping.pairs.start; p < n->data.mapping.pairs.top;
         ++p) {
        const char *key = scalar_text(node(x, p->key));
        if (!key)
            return fail(x, p->key, x->key, "expected a key name, got %s",
                        got(node(x, p->key), seen, sizeof seen));
        const int i = slot(fr->schema, key);
        if (i < 0)
            return unknown_key(x, fr->schema, p->key, key);
        if (fr->value[i])
            return fail(x, p->key, subkey(x, key), "duplicate key '%s'", key);
        fr->value[i] = p->value;
        fr->at[i] = from_set(x, p->value) ? p->value : p->key;
    }
    return 0;
}

/* Reads `map` (0: absent, defaults only) into `base` by the table `s`. */
static int read_map(struct ctx *x, const struct schema *s, char *base, int map, int blame)
{
    struct frame fr = {.schema = s, .blame = blame};
    if (map && index_pairs(x, &fr, map))
        return -1;
    for (int i = 0; i < s->count; ++i) {
        const struct field *f = &s->fields[i];
        if (!fr.value[i] && (f->flags & F_REQUIRED))
            return fail(x, blame, x->key, "missing required key '%s'", f->key);
        const size_t mark = push(x, f->key);
        const int rc =
            fr.value[i] ? read_value(x, f, base, fr.at[i], fr.value[i]) : set_default(x, f, base);
        pop(x, mark);
        if (rc)
            return rc;
    }
    return s->check ? s->check(x, &fr, base) : 0;
}

/* ---- rules the tables cannot express ----------------------------------- */

/* A key that must be given exactly when `needed` holds (a model's own
 * parameters). */
static int needed_exactly(struct ctx *x, const struct frame *fr, const char *key, int needed,
                          const char *when)
{
    if (needed && !given(fr, key))
        return fail(x, fr->blame, x->key, "missing required key '%s' (%s)", key, when);
    if (!needed && given(fr, key))
        return fail(x, line_of(fr, key), subkey(x, key), "only allowed when %s", when);
    return 0;
}

static int check_material(struct ctx *x, const struct frame *fr, void *base)
{
    const struct case_material *m = base;
    const int plastic = m->strength != SPH_STRENGTH_ELASTIC;
    const int jc = m->strength == SPH_STRENGTH_JOHNSON_COOK;
    if (needed_exactly(x, fr, "yield_stress", plastic,
                       "strength is perfectly_plastic or johnson_cook") ||
        needed_exactly(x, fr, "johnson_cook", jc, "strength is johnson_cook") ||
        needed_exactly(x, fr, "heat_capacity", jc && m->johnson_cook.m > 0,
                       "strength is johnson_cook with thermal softening (m > 0)") ||
        needed_exactly(x, fr, "failure_strain", m->failure == SPH_FAILURE_PLASTIC_STRAIN,
                       "failure is plastic_strain") ||
        needed_exactly(x, fr, "mie_gruneisen", m->eos == SPH_EOS_MIE_GRUNEISEN,
                       "eos is mie_gruneisen") ||
        needed_exactly(x, fr, "polynomial", m->eos == SPH_EOS_POLYNOMIAL, "eos is polynomial"))
        return 1;
    if (m->failure != SPH_FAILURE_NONE && !plastic)
        return fail(x, line_of(fr, "failure"), subkey(x, "failure"),
                    "needs a yield stress: strength perfectly_plastic or johnson_cook");
    /* the time step, the viscosity and the contact all divide by it */
    const double speed = case_material_sound_speed(m);
    if (!(speed > 0) || !isfinite(speed)) {
        const char *key = m->eos == SPH_EOS_POLYNOMIAL      ? "polynomial"
                          : m->eos == SPH_EOS_MIE_GRUNEISEN ? "mie_gruneisen"
                                                            : "youngs_modulus";
        return fail(x, line_of(fr, key), subkey(x, key),
                    "expected a positive, finite sound speed at the reference density, got %g "
                    "m/s: the EOS's bulk modulus (polynomial: rho c0^2 - gamma0 p0 / 2) plus 4/3 "
                    "of the shear modulus must be positive",
                    speed);
    }
    return 0;
}

/* |v| without overflow for any finite components. */
static double norm3(const double v[3])
{
    const double largest = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
    if (!(largest > 0))
        return 0;
    const double a = v[0] / largest, b = v[1] / largest, c = v[2] / largest;
    return largest * sqrt(a * a + b * b + c * c);
}

double case_fastest_speed(const struct sph_case *c, int with_projectile)
{
    double fastest = with_projectile && c->projectile.enabled ? norm3(c->projectile.velocity) : 0;
    for (int b = 0; b < c->body_count; ++b)
        fastest = fmax(fastest, norm3(c->bodies[b].velocity));
    return fastest;
}

/* sqrt((K + 4 G / 3) / rho0), K the EOS's bulk modulus at rho0 (dp/dmu at
 * mu = 0; the elastic one for the linear EOS). */
double case_material_sound_speed(const struct case_material *m)
{
    const double nu = m->poisson_ratio, e = m->youngs_modulus;
    const double shear = e / (2.0 * (1.0 + nu));
    double bulk = e / (3.0 * (1.0 - 2.0 * nu));
    if (m->eos == SPH_EOS_MIE_GRUNEISEN)
        bulk = m->density * m->mie_gruneisen.c0 * m->mie_gruneisen.c0;
    else if (m->eos == SPH_EOS_POLYNOMIAL)
        bulk = m->density * m->polynomial.c0 * m->polynomial.c0 -
               0.5 * m->polynomial.gamma0 * m->polynomial.p0;
    return sqrt((bulk + 4.0 * shear / 3.0) / m->density);
}

int case_has_viscosity(const struct sph_case *c)
{
    for (int m = 0; m < c->material_count; ++m)
        if (c->materials[m].viscosity > 0)
            return 1;
    return 0;
}

int case_has_part_contact(const struct sph_case *c)
{
    for (int b = 1; b < c->body_count; ++b)
        if (c->bodies[b].part != c->bodies[0].part)
            return 1;
    return 0;
}

/* A body's velocity as it starts (a fixed body is held at rest). */
static double start_velocity(const struct case_body *b, int axis)
{
    return b->fixed ? 0.0 : b->velocity[axis];
}

void case_note_welding(const struct sph_case *c, FILE *out)
{
    for (int a = 0; a < c->body_count; ++a)
        for (int b = a + 1; b < c->body_count; ++b) {
            const struct case_body *p = &c->bodies[a], *q = &c->bodies[b];
            int differ = 0;
            for (int k = 0; k < 3; ++k)
                differ |= start_velocity(p, k) != start_velocity(q, k);
            if (p->part == q->part && differ)
                fprintf(out,
                        "sph: note: bodies '%s' and '%s' are one part (bodies[].part %d) and start "
                        "at different velocities: %s; give them different parts to let them meet "
                        "by contact and part again (docs/validation_contact.md)\n",
                        p->name, q->name, p->part,
                        c->numerics.total_lagrangian
                            ? "in the total Lagrangian form they pass through each other where "
                              "they meet (only the neighbours of t = 0 interact, until a "
                              "numerics.reference_update makes those near then neighbours), and "
                              "are one continuum where they touch at t = 0"
                            : "where they meet they act as one continuum and weld");
        }
}

double case_viscous_time_step(const struct sph_case *c, double h)
{
    double dt = HUGE_VAL;
    for (int m = 0; m < c->material_count; ++m)
        if (c->materials[m].viscosity > 0)
            dt = fmin(dt, 0.125 * h * h * c->materials[m].density / c->materials[m].viscosity);
    return dt;
}

static int check_johnson_cook(struct ctx *x, const struct frame *fr, void *base)
{
    const struct case_johnson_cook *j = base;
    return needed_exactly(x, fr, "melt_temperature", j->m > 0, "m (thermal softening) is positive");
}

static int check_box(struct ctx *x, const struct frame *fr, const struct case_box *b)
{
    static const char *const axes[] = {"x", "y", "z"};
    for (int a = 0; a < x->c->dimension; ++a)
        if (!(b->max[a] > b->min[a]))
            return fail(x, line_of(fr, "max"), subkey(x, "max"),
                        "expected max greater than min on every axis, got %s: min %g, max %g",
                        axes[a], b->min[a], b->max[a]);
    return 0;
}

static int check_body(struct ctx *x, const struct frame *fr, void *base)
{
    struct case_body *b = base;
    if (check_box(x, fr, &b->box))
        return 1;
    const int cylinder = b->shape == SPH_SHAPE_CYLINDER;
    if (needed_exactly(x, fr, "radius", cylinder, "shape is cylinder"))
        return 1;
    if (!cylinder && (given(fr, "axis") || given(fr, "inner_radius") || given(fr, "centre"))) {
        const char *key = given(fr, "axis")     ? "axis"
                          : given(fr, "centre") ? "centre"
                                                : "inner_radius";
        return fail(x, line_of(fr, key), subkey(x, key), "only allowed when shape is cylinder");
    }
    if (cylinder && x->c->dimension == 2 && b->axis != 2)
        return fail(x, line_of(fr, "axis"), subkey(x, "axis"),
                    "expected z in 2-D (the cylinder is a disk in the x-y plane)");
    if (cylinder && !(b->inner_radius < b->radius))
        return fail(x, line_of(fr, "inner_radius"), subkey(x, "inner_radius"),
                    "expected less than radius (%g m), got %g", b->radius, b->inner_radius);
    for (int k = 0; k < 9 && x->c->dimension == 2; ++k)
        if ((k / 3 == 2 || k % 3 == 2) && b->velocity_gradient[k] != 0)
            return fail(x, line_of(fr, "velocity_gradient"), subkey(x, "velocity_gradient"),
                        "expected 0 for the z entries in 2-D (entry %d is %g)", k + 1,
                        b->velocity_gradient[k]);
    b->has_centre = given(fr, "centre") != 0;
    if (!b->has_centre)
        for (int a = 0; a < 3; ++a)
            b->centre[a] = a < x->c->dimension ? 0.5 * (b->box.min[a] + b->box.max[a]) : 0.0;
    return 0;
}

static int check_group(struct ctx *x, const struct frame *fr, void *base)
{
    return check_box(x, fr, &((struct case_group *)base)->region);
}

static int check_load(struct ctx *x, const struct frame *fr, void *base)
{
    const struct case_load *l = base;
    const int ramp = l->law != SPH_LOAD_CONSTANT;
    if (ramp && !given(fr, "ramp_time"))
        return fail(x, fr->blame, x->key, "missing required key 'ramp_time' (law is %s)",
                    law_names[l->law]);
    if (!ramp && given(fr, "ramp_time"))
        return fail(x, line_of(fr, "ramp_time"), subkey(x, "ramp_time"),
                    "only allowed with law linear_ramp or quadratic_ramp");
    return 0;
}

int case_wall_axis(const struct case_wall *w)
{
    for (int a = 0; a < 3; ++a)
        if (fabs(fabs(w->normal[a]) - 1.0) <= 1e-12)
            return a;
    return -1;
}

unsigned case_held_wall_axes(const struct sph_case *c)
{
    unsigned axes = 0;
    for (int w = 0; w < c->wall_count; ++w)
        if (c->walls[w].hold)
            axes |= 1u << case_wall_axis(&c->walls[w]);
    return axes;
}

static int check_held_wall(struct ctx *x, const struct frame *fr, const struct case_wall *w)
{
    if (w->friction > 0)
        return fail(x, line_of(fr, "friction"), subkey(x, "friction"),
                    "a held wall is frictionless (its face slides freely), got friction %g",
                    w->friction);
    const int a = case_wall_axis(w);
    if (a < 0 || a >= x->c->dimension)
        return fail(x, line_of(fr, "hold"), subkey(x, "hold"),
                    "a held wall needs a normal along x or y%s (a symmetry plane stands in "
                    "for it), got [%g, %g, %g]",
                    x->c->dimension == 3 ? " or z" : "", w->normal[0], w->normal[1], w->normal[2]);
    return 0;
}

static int normalise_wall_normal(struct ctx *x, const struct frame *fr, struct case_wall *w)
{
    double squares = 0;
    for (int a = 0; a < 3; ++a)
        squares += w->normal[a] * w->normal[a];
    /* a unit normal (a resolved case's) is kept to the bit: normalising it
     * again would move its last digits, and a resumed run must be the run */
    if (fabs(squares - 1.0) <= 4 * DBL_EPSILON)
        return 0;
    /* scaled by the largest component first: the squares of [1e308, ...]
     * overflow, of [1e-200, ...] underflow */
    double largest = 0, norm = 0;
    for (int a = 0; a < 3; ++a)
        largest = fmax(largest, fabs(w->normal[a]));
    for (int a = 0; a < 3 && largest > 0; ++a)
        w->normal[a] /= largest;
    for (int a = 0; a < 3; ++a)
        norm += w->normal[a] * w->normal[a];
    norm = sqrt(norm);
    if (!(norm > 0) || !isfinite(norm))
        return fail(x, line_of(fr, "normal"), subkey(x, "normal"), "expected a non-zero vector");
    for (int a = 0; a < 3; ++a)
        w->normal[a] /= norm;
    return 0;
}

static int check_wall(struct ctx *x, const struct frame *fr, void *base)
{
    struct case_wall *w = base;
    const int bad = normalise_wall_normal(x, fr, w);
    if (bad)
        return bad;
    return w->hold ? check_held_wall(x, fr, w) : 0;
}

static int check_symmetry(struct ctx *x, const struct frame *fr, void *base)
{
    const struct case_symmetry *p = base;
    if (p->axis >= x->c->dimension)
        return fail(x, line_of(fr, "axis"), subkey(x, "axis"), "expected x or y in 2-D, got 'z'");
    for (const struct case_symmetry *q = x->c->symmetry; q < p; ++q) /* the items before */
        if (q->axis == p->axis)
            return fail(x, line_of(fr, "axis"), subkey(x, "axis"),
                        "one symmetry plane per axis, got a second on '%s'", axis_names[p->axis]);
    return 0;
}

static int check_output(struct ctx *x, const struct frame *fr, void *base)
{
    struct case_output *o = base;
    if (!given(fr, "snapshot_interval"))
        o->snapshot_interval = x->c->numerics.end_time / 20;
    if (!given(fr, "history_interval"))
        o->history_interval = x->c->numerics.end_time / 1000;
    /* a typo in an interval would write a file every step */
    const double end = x->c->numerics.end_time;
    const struct {
        const char *key;
        double interval, most;
        const char *what;
    } counts[] = {
        {"snapshot_interval", o->snapshot_interval, SPH_MAX_SNAPSHOTS - 2, "snapshots"},
        {"history_interval", o->history_interval, SPH_MAX_HISTORY_ROWS, "history rows"},
        {"checkpoint_interval", o->checkpoint_interval, SPH_MAX_SNAPSHOTS, "checkpoints"},
    };
    if (o->checkpoint_wall_interval > 0 && o->checkpoint_wall_interval < 10)
        return fail(x, line_of(fr, "checkpoint_wall_interval"),
                    subkey(x, "checkpoint_wall_interval"),
                    "expected 0 (none) or at least 10 s of wall-clock time, got %g s",
                    o->checkpoint_wall_interval);
    for (int k = 0; k < 3; ++k)
        if (counts[k].interval > 0 && !(end / counts[k].interval <= counts[k].most))
            return fail(x, line_of(fr, counts[k].key), subkey(x, counts[k].key),
                        "expected at least end_time / %.0f = %g s, got %g s (%.3g %s)",
                        counts[k].most, end / counts[k].most, counts[k].interval,
                        end / counts[k].interval, counts[k].what);
    return 0;
}

static int check_probe(struct ctx *x, const struct frame *fr, void *base)
{
    const struct case_probe *p = base;
    if (p->quantity == SPH_PROBE_DISPLACEMENT_Z && x->c->dimension != 3)
        return fail(x, line_of(fr, "quantity"), subkey(x, "quantity"),
                    "expected displacement_x or displacement_y in 2-D, got 'displacement_z'");
    return 0;
}

static int check_reference(struct ctx *x, const struct frame *fr, void *base)
{
    struct case_reference *r = base;
    if (!given(fr, "window")) {
        r->window[0] = 0;
        r->window[1] = x->c->numerics.end_time;
    } else if (!(r->window[0] < r->window[1])) {
        return fail(x, line_of(fr, "window"), subkey(x, "window"),
                    "expected [t0, t1] with t0 < t1 (s), got [%g, %g]", r->window[0], r->window[1]);
    }
    return 0;
}

/* What the tensor smoothing length is built for (kernels/tensor_smoothing.cl):
 * the updated Lagrangian passes with the CSPH correction, through which the
 * metric drops out of the stress terms; the limited viscosity's slopes and
 * the artificial stress's weight are written for a scalar h. */
static int check_tensor_smoothing(struct ctx *x, const struct frame *fr,
                                  const struct case_numerics *n)
{
    if (!n->tensor_smoothing)
        return 0;
    const char *why = n->total_lagrangian ? "formulation updated_lagrangian"
                      : !n->csph          ? "csph: true"
                      : n->as_epsilon > 0 ? "no artificial stress (epsilon 0)"
                      : n->av_scheme == SPH_AV_LIMITED
                          ? "an artificial viscosity scheme other than limited"
                          : NULL;
    if (why)
        return fail(x, line_of(fr, "smoothing"), subkey(x, "smoothing"),
                    "tensor needs %s (kernels/tensor_smoothing.cl)", why);
    return 0;
}

static int check_numerics(struct ctx *x, const struct frame *fr, void *base)
{
    const struct case_numerics *n = base;
    if (n->total_lagrangian && n->av_scheme == SPH_AV_LIMITED)
        return fail(x, line_of(fr, "artificial_viscosity"), subkey(x, "artificial_viscosity"),
                    "expected scheme monaghan or switch with formulation total_lagrangian (the "
                    "limited scheme is built into the updated Lagrangian passes only)");
    if ((n->av_scheme == SPH_AV_SWITCH || n->av_scheme == SPH_AV_CULLEN_DEHNEN) &&
        n->av_alpha_min > n->av_alpha)
        return fail(x, line_of(fr, "artificial_viscosity"), subkey(x, "artificial_viscosity"),
                    "expected alpha_min (%g) at most alpha (%g): with scheme %s alpha is the "
                    "largest value a particle's alpha reaches (switch is the default scheme); "
                    "for a constant viscosity write scheme: monaghan",
                    n->av_alpha_min, n->av_alpha, av_scheme_names[n->av_scheme]);
    if (n->av_balsara && n->av_scheme != SPH_AV_SWITCH && n->av_scheme != SPH_AV_CULLEN_DEHNEN)
        return fail(x, line_of(fr, "artificial_viscosity"), subkey(x, "artificial_viscosity"),
                    "expected scheme switch or cullen_dehnen with balsara: true (it scales the "
                    "floor alpha_min their alpha decays to), got scheme %s",
                    av_scheme_names[n->av_scheme]);
    if (n->total_lagrangian && n->as_epsilon > 0)
        return fail(x, line_of(fr, "artificial_stress"), subkey(x, "artificial_stress"),
                    "expected epsilon 0 with formulation total_lagrangian (it has no tensile "
                    "instability and no artificial stress), got epsilon %g",
                    n->as_epsilon);
    if (n->reference_update > 0 && !n->total_lagrangian)
        return fail(x, line_of(fr, "reference_update"), subkey(x, "reference_update"),
                    "expected 0 with formulation updated_lagrangian (the updated form's "
                    "reference is the current configuration at every step), got %g",
                    n->reference_update);
    return check_tensor_smoothing(x, fr, n);
}

/* The sphere moves; in an axisymmetric case it stays on the axis. */
static int check_projectile(struct ctx *x, const struct frame *fr, void *base)
{
    struct case_projectile *p = base;
    double speed2 = 0;
    for (int a = 0; a < 3; ++a)
        speed2 += p->velocity[a] * p->velocity[a];
    if (!(speed2 > 0))
        return fail(x, line_of(fr, "velocity"), subkey(x, "velocity"),
                    "expected a non-zero velocity (it sets the impact axis)");
    if (x->c->dimension == 2 && x->c->plane == SPH_PLANE_AXISYMMETRIC &&
        (p->centre[0] != 0 || p->velocity[0] != 0))
        return fail(x, line_of(fr, p->centre[0] != 0 ? "centre" : "velocity"),
                    subkey(x, p->centre[0] != 0 ? "centre" : "velocity"),
                    "expected x = 0 in an axisymmetric case (the sphere moves along the axis)");
    if (p->boundary_integral && x->c->numerics.total_lagrangian)
        return fail(x, line_of(fr, "boundary"), subkey(x, "boundary"),
                    "expected penalty with formulation total_lagrangian (the integral wall "
                    "enters the updated form's pass 1)");
    if (p->boundary_integral && p->no_slip)
        return fail(x, line_of(fr, "contact"), subkey(x, "contact"),
                    "expected free_slip with boundary: integral (the integral wall is free slip; "
                    "no_slip needs boundary: penalty)");
    if (!given(fr, "cavity_probe_spacing"))
        p->cavity_probe_spacing = p->diameter;
    return 0;
}

/* The file's basename without its extension, made a valid name. */
static void default_name(const char *path, char *name, size_t size)
{
    const char *slash = strrchr(path, '/');
    const char *start = slash ? slash + 1 : path;
    const char *dot = strrchr(start, '.');
    size_t n = dot && dot != start ? (size_t)(dot - start) : strlen(start);
    if (n >= size)
        n = size - 1;
    for (size_t i = 0; i < n; ++i)
        name[i] = isalnum((unsigned char)start[i]) || start[i] == '-' ? start[i] : '_';
    name[n] = '\0';
    if (n == 0)
        snprintf(name, size, "case");
}

/* The case's symmetry plane on `axis`, or NULL. */
static const struct case_symmetry *symmetry_plane_on(const struct sph_case *c, int axis)
{
    for (int k = 0; k < c->symmetry_count; ++k)
        if (c->symmetry[k].axis == axis)
            return &c->symmetry[k];
    return NULL;
}

/* A plane the case implies (the axis of revolution, a held wall), added
 * unless the case lists it, as a resolved case does (one per axis). */
static void add_symmetry_plane(struct sph_case *c, int axis, double position)
{
    if (symmetry_plane_on(c, axis))
        return;
    c->symmetry[c->symmetry_count].axis = axis;
    c->symmetry[c->symmetry_count].position = position;
    ++c->symmetry_count;
}

/* Axisymmetric (x = r, y = z): bodies at r >= 0, the axis a symmetry plane
 * (added when the case does not list it), no total Lagrangian form. */
static int check_axisymmetric(struct ctx *x, const struct frame *fr, struct sph_case *c)
{
    if (c->numerics.total_lagrangian)
        return fail(x, line_of(fr, "plane"), "plane",
                    "axisymmetric runs use formulation updated_lagrangian");
    for (int b = 0; b < c->body_count; ++b)
        if (c->bodies[b].box.min[0] < 0)
            return fail(x, line_of(fr, "bodies"), "bodies",
                        "expected r = x >= 0 in an axisymmetric case, body '%s' has min x = %g",
                        c->bodies[b].name, c->bodies[b].box.min[0]);
    const struct case_symmetry *axis = symmetry_plane_on(c, 0);
    if (axis && axis->position != 0)
        return fail(x, line_of(fr, "symmetry"), "symmetry",
                    "the axis of an axisymmetric case is x = 0, got x = %g", axis->position);
    add_symmetry_plane(c, 0, 0.0);
    return 0;
}

/* A held wall is a symmetry plane (kernels/ghost.cl): the mirror images of
 * the body's particles stand beyond it, so the face stays on the plane and
 * slides along it freely, with the kernel's support whole at the face. That
 * is the constraint of the mesh codes' Taylor benchmarks (Simo 1992: the
 * impact face's nodes held at u_z = 0; DynELA: the axial displacement of
 * the impact face restrained), where a penalty wall lets the face lift off.
 * The plane is added unless the case lists it (a resolved case does). */
static int held_walls(struct ctx *x, const struct frame *fr, struct sph_case *c)
{
    for (int w = 0; w < c->wall_count; ++w) {
        const struct case_wall *wall = &c->walls[w];
        if (!wall->hold)
            continue;
        const int a = case_wall_axis(wall);
        const double position = wall->point[a];
        char key[32];
        snprintf(key, sizeof key, "walls.%d", w);
        for (int v = 0; v < w; ++v)
            if (c->walls[v].hold && case_wall_axis(&c->walls[v]) == a &&
                c->walls[v].point[a] != position)
                return fail(x, line_of(fr, "walls"), key,
                            "wall '%s' is held on %s = %g, but wall '%s' already holds %s = %g "
                            "(one held wall or symmetry plane per axis)",
                            wall->name, axis_names[a], position, c->walls[v].name, axis_names[a],
                            c->walls[v].point[a]);
        const int axis_of_revolution =
            c->dimension == 2 && c->plane == SPH_PLANE_AXISYMMETRIC && a == 0;
        const struct case_symmetry *plane = symmetry_plane_on(c, a);
        if (plane && plane->position != position)
            return fail(x, line_of(fr, "walls"), key,
                        "wall '%s' is held on %s = %g, but %s = %g is %s (one held wall or "
                        "symmetry plane per axis)",
                        wall->name, axis_names[a], position, axis_names[a], plane->position,
                        axis_of_revolution ? "the axis of an axisymmetric case"
                                           : "a symmetry plane");
        add_symmetry_plane(c, a, position);
    }
    return 0;
}

static int case_any_graded(const struct sph_case *c)
{
    for (int b = 0; b < c->body_count; ++b)
        if (c->bodies[b].grading.enabled)
            return 1;
    return 0;
}

static int check_case(struct ctx *x, const struct frame *fr, void *base)
{
    struct sph_case *c = base;
    if (!given(fr, "name"))
        default_name(x->path, c->name, sizeof c->name);
    /* The total Lagrangian form measures clumping against the pair's
     * deformation (kernels/health.cl), which reads 0 in every healthy run
     * measured there and 0.38% where two particles of the copper rod's face
     * collapsed (docs/validation_taylor.md, "The hourglass spring on the
     * whole mismatch"); the updated form keeps its dx / 2 test's 1%. */
    if (isnan(c->health.clumped_fraction))
        c->health.clumped_fraction = c->numerics.total_lagrangian ? 0.001 : 0.01;
    for (int b = 0; b < c->body_count; ++b)
        if (c->bodies[b].grading.enabled &&
            (c->numerics.total_lagrangian || c->numerics.as_epsilon > 0))
            return fail(x, line_of(fr, "bodies"), "bodies",
                        "body '%s' is graded: graded lattices need formulation "
                        "updated_lagrangian and no artificial stress",
                        c->bodies[b].name);
    if (c->reference.enabled && !c->has_probe)
        return fail(x, line_of(fr, "reference"), "reference",
                    "needs a probe (add a probe map naming the group to compare)");
    if (c->numerics.tensor_smoothing) {
        const char *why = c->dimension == 2 && c->plane == SPH_PLANE_AXISYMMETRIC
                              ? "an axisymmetric case (its hoop rate v_r / r is exact already)"
                          : case_any_graded(c) ? "a graded lattice"
                          : c->projectile.enabled && c->projectile.boundary_integral
                              ? "the projectile's integral boundary"
                              : NULL;
        if (why)
            return fail(x, line_of(fr, "numerics"), "numerics.smoothing",
                        "tensor is not built for %s; use isotropic", why);
    }
    const int bad =
        c->dimension == 2 && c->plane == SPH_PLANE_AXISYMMETRIC ? check_axisymmetric(x, fr, c) : 0;
    return bad ? bad : held_walls(x, fr, c);
}

/* ---- the tables -------------------------------------------------------- */

#define NUMBER(k, T, m, fl, r, lo_, hi_, d, u)                                                     \
    {                                                                                              \
        .key = k, .kind = K_NUMBER, .flags = fl, .range = r, .lo = lo_, .hi = hi_, .def = d,       \
        .offset = offsetof(T, m), .unit = u                                                        \
    }
#define INT(k, T, m, fl, lo_, hi_, d, w)                                                           \
    {                                                                                              \
        .key = k, .kind = K_INT, .flags = fl, .lo = lo_, .hi = hi_, .def = d,                      \
        .offset = offsetof(T, m), .what = w                                                        \
    }
#define BOOL(k, T, m)                                                                              \
    {                                                                                              \
        .key = k, .kind = K_BOOL, .offset = offsetof(T, m)                                         \
    }
#define ENUM(k, T, m, fl, d, n, w)                                                                 \
    {                                                                                              \
        .key = k, .kind = K_ENUM, .flags = fl, .def = d, .offset = offsetof(T, m), .names = n,     \
        .what = w                                                                                  \
    }
#define STRING(k, T, m, fl, kind_)                                                                 \
    {                                                                                              \
        .key = k, .kind = kind_, .flags = fl, .offset = offsetof(T, m), .aux = sizeof(((T *)0)->m) \
    }
#define REF(k, T, m, fl, ref, d)                                                                   \
    {                                                                                              \
        .key = k, .kind = K_REF, .flags = fl, .def = d, .offset = offsetof(T, m), .aux = ref       \
    }
#define VECTOR(k, T, m, fl, n, u, w)                                                               \
    {                                                                                              \
        .key = k, .kind = K_VECTOR, .flags = fl, .offset = offsetof(T, m), .aux = n, .unit = u,    \
        .what = w                                                                                  \
    }
#define MAP(k, fl, off, enable, s)                                                                 \
    {                                                                                              \
        .key = k, .kind = K_MAP, .flags = fl, .offset = off, .aux = enable, .sub = &s              \
    }
#define LIST(k, T, m, count, fl, lo_, hi_, s)                                                      \
    {                                                                                              \
        .key = k, .kind = K_LIST, .flags = fl, .lo = lo_, .hi = hi_, .offset = offsetof(T, m),     \
        .aux = offsetof(T, count), .sub = &s                                                       \
    }
#define SCHEMA(fields, T, check)                                                                   \
    {                                                                                              \
        fields, ARRAY_LEN(fields), sizeof(T), check                                                \
    }

static const struct field mie_gruneisen_fields[] = {
    NUMBER("c0", struct case_eos_parameters, c0, F_REQUIRED, R_POSITIVE, 0, 0, 0, "m/s"),
    NUMBER("s", struct case_eos_parameters, s, F_REQUIRED, R_NONNEG, 0, 0, 0, NULL),
    NUMBER("gamma0", struct case_eos_parameters, gamma0, F_REQUIRED, R_NONNEG, 0, 0, 0, NULL),
};
static const struct schema mie_gruneisen_schema =
    SCHEMA(mie_gruneisen_fields, struct case_eos_parameters, NULL);

static const struct field polynomial_fields[] = {
    NUMBER("c0", struct case_eos_parameters, c0, F_REQUIRED, R_POSITIVE, 0, 0, 0, "m/s"),
    NUMBER("s", struct case_eos_parameters, s, F_REQUIRED, R_NONNEG, 0, 0, 0, NULL),
    NUMBER("gamma0", struct case_eos_parameters, gamma0, 0, R_NONNEG, 0, 0, 0, NULL),
    NUMBER("p0", struct case_eos_parameters, p0, 0, R_ANY, 0, 0, 0, "Pa"),
};
static const struct schema polynomial_schema =
    SCHEMA(polynomial_fields, struct case_eos_parameters, NULL);

static const struct field johnson_cook_fields[] = {
    NUMBER("b", struct case_johnson_cook, b, F_REQUIRED, R_NONNEG, 0, 0, 0, "Pa"),
    NUMBER("n", struct case_johnson_cook, n, F_REQUIRED, R_NONNEG, 0, 0, 0, NULL),
    NUMBER("c", struct case_johnson_cook, c, 0, R_NONNEG, 0, 0, 0, NULL),
    NUMBER("reference_rate", struct case_johnson_cook, reference_rate, 0, R_POSITIVE, 0, 0, 1,
           "1/s"),
    NUMBER("m", struct case_johnson_cook, m, 0, R_NONNEG, 0, 0, 0, NULL),
    NUMBER("melt_temperature", struct case_johnson_cook, melt_temperature, F_OMIT_ZERO, R_POSITIVE,
           0, 0, 0, "K"),
};
static const struct schema johnson_cook_schema =
    SCHEMA(johnson_cook_fields, struct case_johnson_cook, check_johnson_cook);

static const struct field material_fields[] = {
    STRING("name", struct case_material, name, F_REQUIRED | F_UNIQUE, K_NAME),
    NUMBER("density", struct case_material, density, F_REQUIRED, R_POSITIVE, 0, 0, 0, "kg/m^3"),
    NUMBER("youngs_modulus", struct case_material, youngs_modulus, F_REQUIRED, R_POSITIVE, 0, 0, 0,
           "Pa"),
    NUMBER("poisson_ratio", struct case_material, poisson_ratio, F_REQUIRED, R_OPEN, -1, 0.5, 0,
           NULL),
    ENUM("eos", struct case_material, eos, 0, SPH_EOS_LINEAR, eos_names, NULL),
    MAP("mie_gruneisen", F_ENABLE, offsetof(struct case_material, mie_gruneisen),
        offsetof(struct case_material, mie_gruneisen.enabled), mie_gruneisen_schema),
    MAP("polynomial", F_ENABLE, offsetof(struct case_material, polynomial),
        offsetof(struct case_material, polynomial.enabled), polynomial_schema),
    ENUM("strength", struct case_material, strength, 0, SPH_STRENGTH_ELASTIC, strength_names, NULL),
    NUMBER("yield_stress", struct case_material, yield_stress, F_OMIT_ZERO, R_POSITIVE, 0, 0, 0,
           "Pa"),
    MAP("johnson_cook", F_ENABLE, offsetof(struct case_material, johnson_cook),
        offsetof(struct case_material, johnson_cook.enabled), johnson_cook_schema),
    NUMBER("room_temperature", struct case_material, room_temperature, 0, R_POSITIVE, 0, 0, 293,
           "K"),
    NUMBER("heat_capacity", struct case_material, heat_capacity, F_OMIT_ZERO, R_POSITIVE, 0, 0, 0,
           "J/(kg K)"),
    NUMBER("taylor_quinney", struct case_material, taylor_quinney, 0, R_CLOSED, 0, 1, 0.9, NULL),
    ENUM("failure", struct case_material, failure, 0, SPH_FAILURE_NONE, failure_names, NULL),
    NUMBER("failure_strain", struct case_material, failure_strain, F_OMIT_ZERO, R_POSITIVE, 0, 0, 0,
           NULL),
    NUMBER("viscosity", struct case_material, viscosity, 0, R_NONNEG, 0, 0, 0, "Pa s"),
    NUMBER("cavitation_pressure", struct case_material, cavitation_pressure, 0, R_NONNEG, 0, 0, 0,
           "Pa"),
    NUMBER("failure_stretch", struct case_material, failure_stretch, F_OMIT_ZERO, R_POSITIVE, 0, 0,
           0, NULL),
};

static const struct field grading_fields[] = {
    VECTOR("fine_min", struct case_grading, fine.min, F_BOX, 0, "m", NULL),
    VECTOR("fine_max", struct case_grading, fine.max, F_BOX, 0, "m", NULL),
    VECTOR("track_from", struct case_grading, track_from, F_TRACK, 0, "m", NULL),
    VECTOR("track_to", struct case_grading, track_to, F_TRACK, 0, "m", NULL),
    NUMBER("track_radius", struct case_grading, track_radius, F_OMIT_ZERO, R_POSITIVE, 0, 0, 0,
           "m"),
    INT("layers", struct case_grading, layers, 0, 2, 1000, 6, NULL),
    INT("levels", struct case_grading, levels, 0, 1, 6, 3, NULL),
};
/* The fine region is a box (fine_min, fine_max) or a track (track_from,
 * track_to, track_radius): one form, all of its keys. */
static int check_grading(struct ctx *x, const struct frame *fr, void *base)
{
    const struct case_grading *g = base;
    if (!g->enabled)
        return 0;
    const char *box[] = {"fine_min", "fine_max"},
               *track[] = {"track_from", "track_to", "track_radius"};
    const int is_track = given(fr, track[0]) || given(fr, track[1]) || given(fr, track[2]);
    const char **keys = is_track ? track : box, **other = is_track ? box : track;
    for (int k = 0; k < (is_track ? 3 : 2); ++k)
        if (!given(fr, keys[k]))
            return fail(x, fr->blame, subkey(x, keys[k]),
                        "missing: a grading takes fine_min and fine_max (a box) or track_from, "
                        "track_to and track_radius (a segment)");
    for (int k = 0; k < (is_track ? 2 : 3); ++k)
        if (given(fr, other[k]))
            return fail(x, line_of(fr, other[k]), subkey(x, other[k]),
                        "a grading takes a box (fine_min, fine_max) or a track (track_from, "
                        "track_to, track_radius), not both");
    for (int a = 0; !is_track && a < x->c->dimension; ++a)
        if (!(g->fine.max[a] > g->fine.min[a]))
            return fail(x, line_of(fr, "fine_max"), subkey(x, "fine_max"),
                        "expected fine_max greater than fine_min on every axis");
    return 0;
}
static const struct schema grading_schema =
    SCHEMA(grading_fields, struct case_grading, check_grading);

static const struct field body_fields[] = {
    STRING("name", struct case_body, name, F_REQUIRED | F_UNIQUE, K_NAME),
    REF("material", struct case_body, material, F_REQUIRED, REF_MATERIAL, 0),
    ENUM("shape", struct case_body, shape, 0, SPH_SHAPE_BOX, shape_names, NULL),
    ENUM("axis", struct case_body, axis, F_CYLINDER, 2, axis_names, NULL),
    NUMBER("radius", struct case_body, radius, F_OMIT_ZERO, R_POSITIVE, 0, 0, 0, "m"),
    NUMBER("inner_radius", struct case_body, inner_radius, F_CYLINDER, R_NONNEG, 0, 0, 0, "m"),
    VECTOR("centre", struct case_body, centre, F_CYLINDER, 0, "m", NULL),
    VECTOR("min", struct case_body, box.min, F_REQUIRED, 0, "m", NULL),
    VECTOR("max", struct case_body, box.max, F_REQUIRED, 0, "m", NULL),
    BOOL("fixed", struct case_body, fixed),
    INT("part", struct case_body, part, 0, 0, SPH_PART_MASK, 0, NULL),
    VECTOR("velocity", struct case_body, velocity, 0, 0, "m/s", NULL),
    VECTOR("velocity_gradient", struct case_body, velocity_gradient, 0, 9, "1/s", NULL),
    MAP("grading", F_ENABLE, offsetof(struct case_body, grading),
        offsetof(struct case_body, grading.enabled), grading_schema),
};

static const struct field load_fields[] = {
    VECTOR("force", struct case_load, force, F_REQUIRED, 0, "N", NULL),
    ENUM("law", struct case_load, law, 0, SPH_LOAD_CONSTANT, law_names, NULL),
    NUMBER("ramp_time", struct case_load, ramp_time, F_OMIT_ZERO, R_POSITIVE, 0, 0, 0, "s"),
};
static const struct schema load_schema = SCHEMA(load_fields, struct case_load, check_load);

static const struct field group_fields[] = {
    STRING("name", struct case_group, name, F_REQUIRED | F_UNIQUE, K_NAME),
    REF("body", struct case_group, body, 0, REF_BODY, -1),
    VECTOR("min", struct case_group, region.min, F_REQUIRED, 0, "m", NULL),
    VECTOR("max", struct case_group, region.max, F_REQUIRED, 0, "m", NULL),
    BOOL("fixed", struct case_group, fixed),
    MAP("load", F_ENABLE, offsetof(struct case_group, load),
        offsetof(struct case_group, load.enabled), load_schema),
};

static const struct field wall_fields[] = {
    STRING("name", struct case_wall, name, F_REQUIRED | F_UNIQUE, K_NAME),
    VECTOR("point", struct case_wall, point, F_REQUIRED, 0, "m", NULL),
    VECTOR("normal", struct case_wall, normal, F_REQUIRED, 0, NULL, NULL),
    NUMBER("friction", struct case_wall, friction, 0, R_NONNEG, 0, 0, 0, NULL),
    BOOL("hold", struct case_wall, hold),
};
static const struct schema wall_schema = SCHEMA(wall_fields, struct case_wall, check_wall);

static const struct field symmetry_fields[] = {
    ENUM("axis", struct case_symmetry, axis, F_REQUIRED, 0, axis_names, NULL),
    NUMBER("position", struct case_symmetry, position, 0, R_ANY, 0, 0, 0, "m"),
};
static const struct schema symmetry_schema =
    SCHEMA(symmetry_fields, struct case_symmetry, check_symmetry);

static const struct field viscosity_fields[] = {
    /* the one numerics block's shock capturing (docs/shock_capturing.md,
     * "One block"): the switch (Morris & Monaghan 1997) between 1.5 (the
     * 4340 bars' constant, thesis 3.4.2) and its floor 0.1 (the beams') */
    NUMBER("alpha", struct case_numerics, av_alpha, 0, R_NONNEG, 0, 0, 1.5, NULL),
    NUMBER("beta", struct case_numerics, av_beta, 0, R_NONNEG, 0, 0, 1.5, NULL),
    ENUM("scheme", struct case_numerics, av_scheme, 0, SPH_AV_SWITCH, av_scheme_names, NULL),
    NUMBER("alpha_min", struct case_numerics, av_alpha_min, 0, R_NONNEG, 0, 0, 0.1, NULL),
    BOOL("balsara", struct case_numerics, av_balsara),
};
static const struct schema viscosity_schema = SCHEMA(viscosity_fields, struct case_numerics, NULL);

static const struct field stress_fields[] = {
    NUMBER("epsilon", struct case_numerics, as_epsilon, 0, R_NONNEG, 0, 0, 0, NULL),
    INT("exponent", struct case_numerics, as_exponent, 0, 1, 8, 4, NULL),
    ENUM("weight", struct case_numerics, as_lattice_weight, 0, 0, as_weight_names, NULL),
};
static const struct schema stress_schema = SCHEMA(stress_fields, struct case_numerics, NULL);

static const struct field numerics_fields[] = {
    NUMBER("dx", struct case_numerics, dx, F_REQUIRED, R_POSITIVE, 0, 0, 0, "m"),
    ENUM("kernel", struct case_numerics, kernel, 0, SPH_KERNEL_WENDLAND_C2, kernel_names, NULL),
    NUMBER("h_over_dx", struct case_numerics, h_over_dx, 0, R_CLOSED, 1.0, 3.0, 1.2, NULL),
    MAP("artificial_viscosity", 0, 0, 0, viscosity_schema),
    MAP("artificial_stress", 0, 0, 0, stress_schema),
    NUMBER("xsph", struct case_numerics, xsph_epsilon, 0, R_CLOSED, 0, 1, 0, NULL),
    BOOL("csph", struct case_numerics, csph),
    ENUM("formulation", struct case_numerics, total_lagrangian, 0, 0, formulation_names, NULL),
    ENUM("smoothing", struct case_numerics, tensor_smoothing, 0, 0, smoothing_names, NULL),
    NUMBER("hourglass", struct case_numerics, hourglass, 0, R_NONNEG, 0, 0, 0.1, NULL),
    NUMBER("reference_update", struct case_numerics, reference_update, 0, R_NONNEG, 0, 0, 0, NULL),
    NUMBER("cfl", struct case_numerics, cfl, 0, R_LEFT_OPEN, 0, 1, 0.3, NULL),
    NUMBER("end_time", struct case_numerics, end_time, F_REQUIRED, R_POSITIVE, 0, 0, 0, "s"),
    NUMBER("damping", struct case_numerics, damping, 0, R_NONNEG, 0, 0, 0, "1/s"),
    ENUM("precision", struct case_numerics, double_precision, 0, 0, precision_names, NULL),
    ENUM("neighbour_loop", struct case_numerics, neighbour_loop, 0, SPH_LOOP_AUTO,
         neighbour_loop_names, NULL),
    ENUM("lane_lists", struct case_numerics, lane_lists, 0, SPH_LANE_LISTS_AUTO, lane_lists_names,
         NULL),
};

static const struct field health_fields[] = {
    NUMBER("min_pair_distance", struct case_health, min_pair_distance, 0, R_CLOSED, 0, 1, 0, NULL),
    /* NAN: the form's default, check_case */
    NUMBER("clumped_fraction", struct case_health, clumped_fraction, 0, R_CLOSED, 0, 1, NAN, NULL),
    NUMBER("energy_error", struct case_health, energy_error, 0, R_POSITIVE, 0, 0, 0.05, NULL),
    BOOL("stop", struct case_health, stop),
};
static const struct schema health_schema = SCHEMA(health_fields, struct case_health, NULL);

static const struct field output_fields[] = {
    NUMBER("snapshot_interval", struct case_output, snapshot_interval, 0, R_POSITIVE, 0, 0, 0, "s"),
    NUMBER("history_interval", struct case_output, history_interval, 0, R_POSITIVE, 0, 0, 0, "s"),
    NUMBER("checkpoint_interval", struct case_output, checkpoint_interval, 0, R_NONNEG, 0, 0, 0,
           "s"),
    NUMBER("checkpoint_wall_interval", struct case_output, checkpoint_wall_interval, 0, R_NONNEG, 0,
           0, 900, "s"),
};

static const struct field probe_fields[] = {
    STRING("name", struct case_probe, name, F_REQUIRED, K_NAME),
    REF("group", struct case_probe, group, F_REQUIRED, REF_GROUP, 0),
    ENUM("quantity", struct case_probe, quantity, F_REQUIRED, 0, quantity_names, NULL),
};

static const struct field reference_fields[] = {
    NUMBER("value", struct case_reference, value, F_REQUIRED, R_ANY, 0, 0, 0, NULL),
    VECTOR("window", struct case_reference, window, 0, 2, NULL, "a sequence [t0, t1] (s)"),
    STRING("source", struct case_reference, source, 0, K_STRING),
};

static const struct field projectile_fields[] = {
    NUMBER("diameter", struct case_projectile, diameter, F_REQUIRED, R_POSITIVE, 0, 0, 0, "m"),
    NUMBER("density", struct case_projectile, density, F_REQUIRED, R_POSITIVE, 0, 0, 0, "kg/m^3"),
    VECTOR("centre", struct case_projectile, centre, F_REQUIRED, 0, "m", NULL),
    VECTOR("velocity", struct case_projectile, velocity, F_REQUIRED, 0, "m/s", NULL),
    NUMBER("cavity_probe_spacing", struct case_projectile, cavity_probe_spacing, F_OMIT_ZERO,
           R_POSITIVE, 0, 0, 0, "m"),
    INT("cavity_probe_count", struct case_projectile, cavity_probe_count, 0, 1,
        SPH_MAX_CAVITY_PROBES, SPH_MAX_CAVITY_PROBES, NULL),
    ENUM("motion", struct case_projectile, prescribed, 0, 0, motion_names, NULL),
    ENUM("contact", struct case_projectile, no_slip, 0, 0, contact_names, NULL),
    ENUM("boundary", struct case_projectile, boundary_integral, 0, 0, boundary_names, NULL),
    BOOL("embedded", struct case_projectile, embedded),
};

static const struct schema material_schema =
    SCHEMA(material_fields, struct case_material, check_material);
static const struct schema body_schema = SCHEMA(body_fields, struct case_body, check_body);
static const struct schema group_schema = SCHEMA(group_fields, struct case_group, check_group);
static const struct schema numerics_schema =
    SCHEMA(numerics_fields, struct case_numerics, check_numerics);
static const struct schema output_schema = SCHEMA(output_fields, struct case_output, check_output);
static const struct schema probe_schema = SCHEMA(probe_fields, struct case_probe, check_probe);
static const struct schema reference_schema =
    SCHEMA(reference_fields, struct case_reference, check_reference);
static const struct schema projectile_schema =
    SCHEMA(projectile_fields, struct case_projectile, check_projectile);

/* Order matters: a field is read after those it depends on (dimension before
 * vectors, materials before bodies, numerics before output...). */
static const struct field case_fields[] = {
    STRING("name", struct sph_case, name, 0, K_NAME),
    INT("dimension", struct sph_case, dimension, F_REQUIRED, 2, 3, 0, "2 or 3"),
    ENUM("plane", struct sph_case, plane, F_2D_ONLY, SPH_PLANE_STRESS, plane_names, NULL),
    NUMBER("thickness", struct sph_case, thickness, F_2D_ONLY, R_POSITIVE, 0, 0, 1.0, "m"),
    LIST("materials", struct sph_case, materials, material_count, F_REQUIRED, 1, SPH_MAX_MATERIALS,
         material_schema),
    LIST("bodies", struct sph_case, bodies, body_count, F_REQUIRED, 1, SPH_MAX_BODIES, body_schema),
    LIST("groups", struct sph_case, groups, group_count, 0, 0, SPH_MAX_BODIES, group_schema),
    LIST("walls", struct sph_case, walls, wall_count, 0, 0, SPH_MAX_WALLS, wall_schema),
    LIST("symmetry", struct sph_case, symmetry, symmetry_count, 0, 0, 3, symmetry_schema),
    MAP("numerics", F_REQUIRED, offsetof(struct sph_case, numerics), 0, numerics_schema),
    MAP("output", 0, offsetof(struct sph_case, output), 0, output_schema),
    MAP("health", 0, offsetof(struct sph_case, health), 0, health_schema),
    MAP("probe", F_ENABLE, offsetof(struct sph_case, probe), offsetof(struct sph_case, has_probe),
        probe_schema),
    MAP("reference", F_ENABLE, offsetof(struct sph_case, reference),
        offsetof(struct sph_case, reference.enabled), reference_schema),
    MAP("projectile", F_ENABLE, offsetof(struct sph_case, projectile),
        offsetof(struct sph_case, projectile.enabled), projectile_schema),
};
static const struct schema case_schema = SCHEMA(case_fields, struct sph_case, check_case);

_Static_assert(ARRAY_LEN(case_fields) <= MAX_FIELDS, "frame too small");
_Static_assert(ARRAY_LEN(numerics_fields) <= MAX_FIELDS, "frame too small");
_Static_assert(ARRAY_LEN(material_fields) <= MAX_FIELDS, "frame too small");
_Static_assert(ARRAY_LEN(body_fields) <= MAX_FIELDS, "frame too small");
_Static_assert(ARRAY_LEN(group_fields) <= MAX_FIELDS, "frame too small");

/* ---- --set ------------------------------------------------------------- */

static void mark_set(yaml_document_t *doc, int id)
{
    yaml_node_t *n = yaml_document_get_node(doc, id);
    n->start_mark.line = n->end_mark.line = SET_LINE;
}

/* Copies node `id` of `from` (and all below it) into `to`; 0 when out of
 * memory or nested deeper than any case value (the recursion must stay bounded). */
/* Nodes a --set value may graft: far more than any case needs; an alias
 * bomb (an anchor repeated within itself) expands past it at once. */
#define SET_MAX_NODES 100000
#define SET_MAX_TEXT 65536

static int graft(yaml_document_t *to, yaml_document_t *from, int id, int depth, long *budget)
{
    const yaml_node_t *n = yaml_document_get_node(from, id);
    int copy = 0;
    if (depth > 16 || --*budget < 0)
        return 0;
    switch (n->type) {
    case YAML_SCALAR_NODE:
        copy = yaml_document_add_scalar(to, NULL, n->data.scalar.value, (int)n->data.scalar.length,
                                        n->data.scalar.style);
        break;
    case YAML_SEQUENCE_NODE:
        copy = yaml_document_add_sequence(to, NULL, n->data.sequence.style);
        for (const yaml_node_item_t *i = n->data.sequence.items.start;
             copy && i < n->data.sequence.items.top; ++i) {
            const int item = graft(to, from, *i, depth + 1, budget);
            if (!item || !yaml_document_append_sequence_item(to, copy, item))
                copy = 0;
        }
        break;
    case YAML_MAPPING_NODE:
        copy = yaml_document_add_mapping(to, NULL, n->data.mapping.style);
        for (const yaml_node_pair_t *p = n->data.mapping.pairs.start;
             copy && p < n->data.mapping.pairs.top; ++p) {
            const int key = graft(to, from, p->key, depth + 1, budget),
                      value = key ? graft(to, from, p->value, depth + 1, budget) : 0;
            if (!value || !yaml_document_append_mapping_pair(to, copy, key, value))
                copy = 0;
        }
        break;
    default:
        break;
    }
    if (copy)
        mark_set(to, copy);
    return copy;
}

/* Parses the text after '=' as YAML and grafts it into the case document. */
static int set_value(struct ctx *x, const char *arg, const char *text, int *id)
{
    yaml_parser_t parser;
    yaml_document_t value;
    *id = 0;
    if (strlen(text) > SET_MAX_TEXT)
        return fail_set(x, arg, "value longer than %d characters", SET_MAX_TEXT);
    if (!yaml_parser_initialize(&parser))
        return fail_set(x, arg, "out of memory");
    yaml_parser_set_input_string(&parser, (const unsigned char *)text, strlen(text));
    if (!yaml_parser_load(&parser, &value)) {
        fail_set(x, arg, "malformed value: %s", parser.problem ? parser.problem : "out of memory");
        yaml_parser_delete(&parser);
        return -1;
    }
    const yaml_node_t *root = yaml_document_get_root_node(&value);
    long budget = SET_MAX_NODES;
    if (root)
        *id = graft(x->doc, &value, (int)(root - value.nodes.start) + 1, 0, &budget);
    else
        *id = yaml_document_add_scalar(x->doc, NULL, (const yaml_char_t *)"", 0,
                                       YAML_PLAIN_SCALAR_STYLE);
    if (*id)
        mark_set(x->doc, *id);
    yaml_document_delete(&value);
    yaml_parser_delete(&parser);
    if (budget < 0)
        return fail_set(x, arg, "value expands to more than %d YAML nodes (aliases?)",
                        SET_MAX_NODES);
    return *id ? 0 : fail_set(x, arg, "value nested too deeply (or out of memory)");
}

static yaml_node_pair_t *find_pair(struct ctx *x, int map, const char *key)
{
    yaml_node_t *n = node(x, map);
    for (yaml_node_pair_t *p = n->data.mapping.pairs.start; p < n->data.mapping.pairs.top; ++p) {
        const char *k = scalar_text(node(x, p->key));
        if (k && strcmp(k, key) == 0)
            return p;
    }
    return NULL;
}

/* The item of a sequence named by index or by its `name`; NULL if none. */
static yaml_node_item_t *find_item(struct ctx *x, int seq, const char *segment)
{
    yaml_node_t *n = node(x, seq);
    const long count = (long)(n->data.sequence.items.top - n->data.sequence.items.start);
    char *end;
    const long index = strtol(segment, &end, 10);
    if (isdigit((unsigned char)*segment) && !*end)
        return index < count ? n->data.sequence.items.start + index : NULL;
    for (yaml_node_item_t *i = n->data.sequence.items.start; i < n->data.sequence.items.top; ++i) {
        const yaml_node_pair_t *p =
            node(x, *i)->type == YAML_MAPPING_NODE ? find_pair(x, *i, "name") : NULL;
        const char *name = p ? scalar_text(node(x, p->value)) : NULL;
        if (name && strcmp(name, segment) == 0)
            return i;
    }
    return NULL;
}

static int add_pair(struct ctx *x, int map, const char *key, int value)
{
    const int k = yaml_document_add_scalar(x->doc, NULL, (const yaml_char_t *)key, -1,
                                           YAML_PLAIN_SCALAR_STYLE);
    if (!k || !yaml_document_append_mapping_pair(x->doc, map, k, value))
        return -1;
    mark_set(x->doc, k);
    return 0;
}

/* Applies one "key.path=value": walks maps by key and sequences by index or
 * item name, creating missing maps, and puts the value at the end. */
static int apply_set(struct ctx *x, const char *arg)
{
    const char *eq = arg ? strchr(arg, '=') : NULL;
    char keys[KEY_MAX], walked[KEY_MAX] = "";
    if (!eq || eq == arg)
        return fail_set(x, arg, "expected key.path=value");
    if ((size_t)(eq - arg) >= sizeof keys)
        return fail_set(x, arg, "key path too long");
    memcpy(keys, arg, (size_t)(eq - arg));
    keys[eq - arg] = '\0';
    int value, current = (int)(yaml_document_get_root_node(x->doc) - x->doc->nodes.start) + 1;
    if (set_value(x, arg, eq + 1, &value))
        return -1;
    for (char *segment = keys, *dot;; segment = dot + 1) {
        dot = strchr(segment, '.');
        if (dot)
            *dot = '\0';
        if (!*segment)
            return fail_set(x, arg, "empty key in the key path");
        const yaml_node_type_t type = node(x, current)->type;
        if (type == YAML_MAPPING_NODE) {
            yaml_node_pair_t *p = find_pair(x, current, segment);
            if (!dot) {
                if (p)
                    p->value = value;
                else if (add_pair(x, current, segment, value))
                    return fail_set(x, arg, "out of memory");
                return 0;
            }
            if (!p) {
                const int map = yaml_document_add_mapping(x->doc, NULL, YAML_BLOCK_MAPPING_STYLE);
                if (!map || add_pair(x, current, segment, map))
                    return fail_set(x, arg, "out of memory");
                mark_set(x->doc, map);
                current = map;
            } else {
                current = p->value;
            }
        } else if (type == YAML_SEQUENCE_NODE) {
            yaml_node_item_t *item = find_item(x, current, segment);
            if (!item)
                return fail_set(x, arg, "%s has no item '%s' (expected an index or a name)", walked,
                                segment);
            if (!dot) {
                *item = value;
                return 0;
            }
            current = *item;
        } else {
            return fail_set(x, arg, "%s is a value, not a map or a sequence", walked);
        }
        append(walked, sizeof walked, *walked ? "." : "", segment, (char *)NULL);
    }
}

/* ---- loading ----------------------------------------------------------- */

static int parser_error(struct ctx *x, const yaml_parser_t *p, FILE *f)
{
    x->error_len = 0;
    if (p->error == YAML_READER_ERROR && f && ferror(f))
        put(x, "%s: cannot read: %s", x->path, strerror(errno));
    else if (p->error == YAML_MEMORY_ERROR || !p->problem)
        put(x, "%s: out of memory while reading YAML", x->path);
    else if (p->error == YAML_READER_ERROR && f) {
        /* an encoding error (bad UTF-8, a NUL or control byte): the reader
         * gives its byte offset, not its line */
        size_t line = 1;
        rewind(f);
        for (size_t k = 0; k < p->problem_offset; ++k) {
            const int ch = fgetc(f);
            if (ch == EOF)
                break;
            line += ch == '\n';
        }
        put(x,
            "%s:%zu: malformed YAML: %s (byte %zu of the file, value 0x%02x); expected UTF-8 "
            "text",
            x->path, line, p->problem, p->problem_offset, (unsigned)p->problem_value & 0xffu);
    } else if (p->context)
        put(x, "%s:%zu: malformed YAML: %s (%s at line %zu)", x->path, p->problem_mark.line + 1,
            p->problem, p->context, p->context_mark.line + 1);
    else
        put(x, "%s:%zu: malformed YAML: %s", x->path, p->problem_mark.line + 1, p->problem);
    return -1;
}

/* Loads the file's single document into `doc`; on failure nothing is left to free. */
static int load_document(struct ctx *x, yaml_document_t *doc)
{
    FILE *f = fopen(x->path, "rb");
    if (!f) {
        put(x, "%s: cannot open: %s", x->path, strerror(errno));
        return -1;
    }
    yaml_parser_t parser;
    if (!yaml_parser_initialize(&parser)) {
        fclose(f);
        put(x, "%s: out of memory", x->path);
        return -1;
    }
    yaml_parser_set_input_file(&parser, f);
    const int loaded = yaml_parser_load(&parser, doc);
    int rc = loaded ? 0 : parser_error(x, &parser, f);
    if (!rc && !yaml_document_get_root_node(doc)) {
        put(x,
            "%s: empty case file; expected a map with dimension, materials, bodies and "
            "numerics",
            x->path);
        rc = -1;
    } else if (!rc) {
        yaml_document_t extra;
        if (!yaml_parser_load(&parser, &extra)) {
            rc = parser_error(x, &parser, f);
        } else {
            const yaml_node_t *root = yaml_document_get_root_node(&extra);
            if (root) {
                put(x, "%s:%zu: a second YAML document; expected one", x->path,
                    root->start_mark.line + 1);
                rc = -1;
            }
            yaml_document_delete(&extra);
        }
    }
    if (rc && loaded) /* a failed load has freed the document itself */
        yaml_document_delete(doc);
    yaml_parser_delete(&parser);
    fclose(f);
    return rc;
}

static int written(const struct sph_case *c, const struct field *f, const char *base);

/* A float run takes every number in single precision: one past its range
 * (or a non-zero one below its smallest normal) would become inf or 0 on
 * the device, so it is refused here with its key. */
static int out_of_float_range(double v)
{
    return !(fabs(v) <= FLT_MAX) || (v != 0 && fabs(v) < FLT_MIN);
}

static int float_range(struct ctx *x, const struct schema *s, const char *base, const char *path)
{
    for (int i = 0; i < s->count; ++i) {
        const struct field *fl = &s->fields[i];
        const char *p = base + fl->offset;
        if (!written(x->c, fl, base))
            continue;
        char key[KEY_MAX];
        snprintf(key, sizeof key, "%s%s%s", path, *path ? "." : "", fl->key);
        const int n = fl->kind == K_NUMBER   ? 1
                      : fl->kind == K_VECTOR ? (fl->aux ? (int)fl->aux : x->c->dimension)
                                             : 0;
        for (int k = 0; k < n; ++k) {
            const double v = ((const double *)p)[k];
            if (out_of_float_range(v)) {
                snprintf(x->error, x->error_size,
                         "%s: %s = %g is outside single precision (%g to %g in magnitude, or 0) "
                         "and this case runs in float: use numerics.precision: double, or check "
                         "the units",
                         x->path, key, v, FLT_MIN, FLT_MAX);
                return -1;
            }
        }
        if (fl->kind == K_MAP && float_range(x, fl->sub, p, key))
            return -1;
        for (int k = 0; fl->kind == K_LIST && k < *(const int *)(base + fl->aux); ++k) {
            char item[KEY_MAX + 16];
            snprintf(item, sizeof item, "%s[%d]", key, k);
            if (float_range(x, fl->sub, p + (size_t)k * fl->sub->size, item))
                return -1;
        }
    }
    return 0;
}

int case_load(const char *path, int set_count, char *const *sets, struct sph_case *out, char *error,
              size_t error_size)
{
    struct ctx x = {
        .path = path ? path : "(null)", .c = out, .error = error, .error_size = error_size};
    if (error && error_size)
        error[0] = '\0';
    memset(out, 0, sizeof *out);
    yaml_document_t doc;
    if (load_document(&x, &doc))
        return -1;
    x.doc = &doc;
    const int root = (int)(yaml_document_get_root_node(&doc) - doc.nodes.start) + 1;
    char seen[160];
    int rc = 0;
    if (node(&x, root)->type != YAML_MAPPING_NODE)
        rc = fail(&x, root, NULL, "expected a map of case keys, got %s",
                  got(node(&x, root), seen, sizeof seen));
    for (int i = 0; !rc && i < set_count; ++i)
        rc = apply_set(&x, sets[i]);
    if (!rc)
        rc = read_map(&x, &case_schema, (char *)out, root, root);
    if (!rc && !out->numerics.double_precision)
        rc = float_range(&x, &case_schema, (const char *)out, "");
    yaml_document_delete(&doc);
    if (rc) {
        memset(out, 0, sizeof *out);
        return -1;
    }
    append(out->path, sizeof out->path, x.path, (char *)NULL);
    return 0;
}

/* ---- writing ----------------------------------------------------------- */

/* The shortest %g form that reads back to the same double. */
static void write_number(FILE *f, double v)
{
    char buf[40];
    if (v > -1e15 && v < 1e15 && v == (double)(long long)v) {
        fprintf(f, "%.0f", v);
        return;
    }
    for (int digits = 1; digits <= 17; ++digits) {
        snprintf(buf, sizeof buf, "%.*g", digits, v);
        if (strtod(buf, NULL) == v)
            break;
    }
    fputs(buf, f);
}

static void write_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; ++s) {
        const unsigned char ch = (unsigned char)*s;
        if (ch == '"' || ch == '\\')
            fprintf(f, "\\%c", ch);
        else if (ch < 0x20 || ch == 0x7f)
            fprintf(f, "\\x%02x", ch);
        else
            fputc(ch, f);
    }
    fputc('"', f);
}

static int written(const struct sph_case *c, const struct field *f, const char *base)
{
    const void *p = base + f->offset;
    if ((f->flags & F_2D_ONLY) && c->dimension != 2)
        return 0;
    if ((f->flags & F_OMIT_ZERO) && *(const double *)p == 0)
        return 0;
    if ((f->flags & F_CYLINDER) && ((const struct case_body *)base)->shape != SPH_SHAPE_CYLINDER)
        return 0;
    if ((f->flags & (F_TRACK | F_BOX)) &&
        (((const struct case_grading *)base)->track_radius > 0) != !!(f->flags & F_TRACK))
        return 0;
    if (f->kind == K_REF && *(const int *)p < 0)
        return 0;
    if (f->kind == K_MAP && (f->flags & F_ENABLE) && !*(const int *)(base + f->aux))
        return 0;
    if (f->kind == K_LIST && !(f->flags & F_REQUIRED) && !*(const int *)(base + f->aux))
        return 0;
    return 1;
}

/* Starts a line at `indent`; the first line of a list item gets its "- ". */
static void start_line(FILE *f, int indent, int *dash)
{
    fprintf(f, "%*s%s", *dash ? indent - 2 : indent, "", *dash ? "- " : "");
    *dash = 0;
}

static void write_map(const struct sph_case *c, FILE *f, const struct schema *s, const char *base,
                      int indent, int dash)
{
    for (int i = 0; i < s->count; ++i) {
        const struct field *fl = &s->fields[i];
        const void *p = base + fl->offset;
        if (!written(c, fl, base))
            continue;
        start_line(f, indent, &dash);
        fprintf(f, "%s:", fl->key);
        switch (fl->kind) {
        case K_NUMBER:
            fputc(' ', f);
            write_number(f, *(const double *)p);
            break;
        case K_INT:
            fprintf(f, " %d", *(const int *)p);
            break;
        case K_BOOL:
            fprintf(f, " %s", *(const int *)p ? "true" : "false");
            break;
        case K_ENUM:
            fprintf(f, " %s", fl->names[*(const int *)p]);
            break;
        case K_STRING:
        case K_NAME:
            fputc(' ', f);
            write_string(f, p);
            break;
        case K_REF:
            fputc(' ', f);
            write_string(f, ref_name(c, fl->aux, *(const int *)p));
            break;
        case K_VECTOR: {
            const int n = fl->aux ? (int)fl->aux : c->dimension;
            for (int k = 0; k < n; ++k) {
                fputs(k ? ", " : " [", f);
                write_number(f, ((const double *)p)[k]);
            }
            fputc(']', f);
            break;
        }
        case K_MAP:
            fputc('\n', f);
            write_map(c, f, fl->sub, (const char *)p, indent + 2, 0);
            continue;
        case K_LIST:
            fputc('\n', f);
            for (int k = 0; k < *(const int *)(base + fl->aux); ++k)
                write_map(c, f, fl->sub, (const char *)p + (size_t)k * fl->sub->size, indent + 4,
                          1);
            continue;
        }
        fputc('\n', f);
    }
}

int case_write_resolved(const struct sph_case *c, FILE *f)
{
    fprintf(f, "# %s: the resolved case, every default filled in (SI units)\n", c->name);
    write_map(c, f, &case_schema, (const char *)c, 0, 0);
    return fflush(f) || ferror(f) ? -1 : 0;
}

char *case_resolved_text(const struct sph_case *c, size_t *length)
{
    char *text = NULL;
    *length = 0;
    FILE *f = open_memstream(&text, length);
    if (!f)
        return NULL;
    const int bad = case_write_resolved(c, f) != 0;
    if ((fclose(f) != 0) | bad) {
        free(text);
        return NULL;
    }
    return text;
}

const char *case_kernel_name(enum sph_kernel_type k)
{
    return (unsigned)k < SPH_KERNEL_COUNT ? kernel_names[k] : "unknown";
}
