/* cli.c: the one parser that reads the option tables (cli_tables.c) of the four programs.
 *
 * cli_parse walks argv once, left to right: "--" ends the options; "--name" or "--name=value"
 * is looked up by long name; any other argument starting with '-' is a switch string, walked
 * letter by letter as Triangle does (walk_switches; the rule, glued and spaced values and the
 * bare -q and -a, is in cli.h); any other argument is positional.  Without -o a mesher's output
 * prefix is Triangle's name for the input (cli_output_name).  A row's value is read by the
 * reader of its kind (read_real, read_int, read_uint: decimal only, no blanks, NaN, infinities
 * or overflow; each reports where its number ends) and checked against the row's range; strings
 * must not be empty.  The first problem ends the parse with one line "PROG: problem (try
 * --help)" and status 2.
 *
 * Invariants: every row's destination has the size its kind stores (checked, with letter and
 * name uniqueness, by check_prog at every parse: a bad table is a bug, reported as one); the
 * defaults are stored from the same rows that --help prints them from.
 */
#include "cli.h"

#include "base/base.h"
#include "pcdm.h"

#include <ctype.h>
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* ---- table checks ------------------------------------------------------------------------ */

static size_t kind_size(cli_kind k) {
    switch (k) {
    case CLI_HELP:
    case CLI_VERSION:
        return 0;
    case CLI_FLAG:
        return sizeof(int);
    case CLI_STRING:
        return sizeof(const char *);
    case CLI_REAL:
        return sizeof(double);
    case CLI_INT32:
        return sizeof(int32_t);
    case CLI_INT64:
        return sizeof(int64_t);
    case CLI_UINT64:
        return sizeof(uint64_t);
    }
    MESH_BUG("option kind %d unknown", (int)k);
}

static int takes_value(const cli_opt *r) {
    return r->value->kind != CLI_FLAG && r->value->kind != CLI_HELP &&
           r->value->kind != CLI_VERSION;
}

static const cli_opt *find_name(const cli_prog *p, const char *name, size_t len);

/* Bug unless every row is well formed and no letter or name repeats within p. */
static void check_prog(const cli_prog *p) {
    for (const cli_opt *const *t = p->tables; *t; t++)
        for (const cli_opt *r = *t; r->help; r++) {
            if (!r->value || (!r->letter && !r->name))
                MESH_BUG("%s: an option row without a value kind or a name", p->name);
            size_t want = kind_size(r->value->kind);
            if (want && (r->at.size != want || r->at.offset + want > sizeof(cli_opts)))
                MESH_BUG("%s: option %c%s stores %zu bytes into a field of %zu", p->name,
                         r->letter ? r->letter : '-', r->name ? r->name : "", want, r->at.size);
            for (const cli_opt *const *u = p->tables; *u; u++)
                for (const cli_opt *s = *u; s->help && s != r; s++)
                    if ((r->letter && s->letter == r->letter) ||
                        (r->name && s->name && !strcmp(r->name, s->name)))
                        MESH_BUG("%s: option %c%s declared twice", p->name,
                                 r->letter ? r->letter : '-', r->name ? r->name : "");
            if (r->spelling && (r->value->kind != CLI_FLAG || strlen(r->spelling) < 2))
                MESH_BUG("%s: spelling %s on a row that is not a flag", p->name, r->spelling);
            if (r->bare && (!takes_value(r) || !r->letter))
                MESH_BUG("%s: a bare meaning on a row without a letter and a value", p->name);
            if (r->bare && r->bare[0] == '-') {
                const cli_opt *f = find_name(p, r->bare + 2, strlen(r->bare + 2));
                if (strncmp(r->bare, "--", 2) || !f || f->value->kind != CLI_FLAG)
                    MESH_BUG("%s: -%c's bare meaning %s is not a flag of the program", p->name,
                             r->letter, r->bare);
            }
        }
}

/* ---- value readers ----------------------------------------------------------------------- */

/* A number starts with an optional sign and then a digit or a point (this refuses blanks,
 * "nan", "inf" and the like); hexadecimal is refused. */
static int number_start(const char *s, int sign_ok) {
    if (sign_ok && (*s == '-' || *s == '+')) s++;
    if (s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) return 0;
    return isdigit((unsigned char)s[0]) || (s[0] == '.' && isdigit((unsigned char)s[1]));
}

/* Each reader takes the number at the start of s, stores it and points *end past it; returns
 * -1 when there is no number there or it is out of its type's range. */
static int read_real(const char *s, const char **end, double *x) {
    if (!number_start(s, 1)) return -1;
    char *e;
    errno = 0;
    double v = strtod(s, &e);
    if (e == s || errno == ERANGE || !isfinite(v)) return -1;
    *x = v;
    *end = e;
    return 0;
}

static int read_int(const char *s, const char **end, int64_t *x) {
    if (!number_start(s, 1)) return -1;
    char *e;
    errno = 0;
    long long v = strtoll(s, &e, 10);
    if (e == s || errno == ERANGE) return -1;
    *x = (int64_t)v;
    *end = e;
    return 0;
}

static int read_uint(const char *s, const char **end, uint64_t *x) {
    if (!number_start(s, 0)) return -1;
    char *e;
    errno = 0;
    unsigned long long v = strtoull(s, &e, 10);
    if (e == s || errno == ERANGE) return -1;
    *x = (uint64_t)v;
    *end = e;
    return 0;
}

static int in_range(const cli_value *v, double x) {
    return (v->min_open ? x > v->min : x >= v->min) && (v->max_open ? x < v->max : x <= v->max);
}

/* "a non-negative number at most 60": what v accepts, for messages. */
static void describe(const cli_value *v, char *buf, size_t n) {
    const char *noun = v->kind == CLI_REAL ? "number" : "integer";
    char lo[64] = "", hi[64] = "";
    if (v->min == 0 || (v->min == 1 && v->kind != CLI_REAL && !v->min_open))
        snprintf(lo, sizeof lo, "%s %s",
                 v->min_open || v->min == 1 ? "a positive" : "a non-negative", noun);
    else
        snprintf(lo, sizeof lo, "%s %s %.15g", v->kind == CLI_REAL ? "a number" : "an integer",
                 v->min_open ? "above" : "at least", v->min);
    if (v->max < 9e18)
        snprintf(hi, sizeof hi, " %s %.15g", v->max_open ? "below" : "at most", v->max);
    snprintf(buf, n, "%s%s", lo, hi);
}

/* ---- parsing ----------------------------------------------------------------------------- */

typedef struct parse_ctx {
    const cli_prog *p;
    FILE *err;
    int *status;
} parse_ctx;

static MESH_PRINTF(2, 3) int usage_error(const parse_ctx *c, const char *fmt, ...) {
    if (c->err) {
        va_list ap;
        va_start(ap, fmt);
        fprintf(c->err, "%s: ", c->p->name);
        vfprintf(c->err, fmt, ap);
        fprintf(c->err, " (try --help)\n");
        va_end(ap);
    }
    *c->status = CLI_EXIT_USAGE;
    return 1;
}

/* "-q" or "--vtk": how messages name row r. */
static const char *row_name(const cli_opt *r, char *buf, size_t n) {
    if (r->name)
        snprintf(buf, n, "--%s", r->name);
    else
        snprintf(buf, n, "-%c", r->letter);
    return buf;
}

static const cli_opt *find_letter(const cli_prog *p, char letter) {
    for (const cli_opt *const *t = p->tables; *t; t++)
        for (const cli_opt *r = *t; r->help; r++)
            if (r->letter && r->letter == letter) return r;
    return NULL;
}

static const cli_opt *find_name(const cli_prog *p, const char *name, size_t len) {
    for (const cli_opt *const *t = p->tables; *t; t++)
        for (const cli_opt *r = *t; r->help; r++)
            if (r->name && strlen(r->name) == len && !strncmp(r->name, name, len)) return r;
    return NULL;
}

static void store_default(const cli_opt *r, cli_opts *o) {
    void *dst = (char *)o + r->at.offset;
    switch (r->value->kind) {
    case CLI_REAL:
        *(double *)dst = r->dflt;
        break;
    case CLI_INT32:
        *(int32_t *)dst = (int32_t)r->dflt;
        break;
    case CLI_INT64:
        *(int64_t *)dst = (int64_t)r->dflt;
        break;
    case CLI_UINT64:
        *(uint64_t *)dst = (uint64_t)r->dflt;
        break;
    default:
        break;
    }
}

/* 1 iff val is one of the words of choices ("a|b|c"). */
static int is_choice(const char *choices, const char *val) {
    size_t n = strlen(val);
    for (const char *c = choices; *c;) {
        size_t w = strcspn(c, "|");
        if (w == n && !strncmp(c, val, n)) return 1;
        c += w + (c[w] == '|');
    }
    return 0;
}

/* Reads val (NULL for flags) into row r's field; a usage error if it does not fit. */
static int store(const parse_ctx *c, const cli_opt *r, const char *val, cli_opts *o) {
    void *dst = (char *)o + r->at.offset;
    const cli_value *v = r->value;
    const char *end = NULL;
    double x = 0;
    int64_t i = 0;
    uint64_t u = 0;
    int ok = 1;
    switch (v->kind) {
    case CLI_FLAG:
        *(int *)dst = 1;
        return 0;
    case CLI_HELP:
    case CLI_VERSION:
        MESH_BUG("--help or --version reached store()");
    case CLI_STRING:
        ok = val[0] != 0 && (!v->choices || is_choice(v->choices, val));
        if (ok) *(const char **)dst = val;
        break;
    case CLI_REAL:
        ok = read_real(val, &end, &x) == 0 && !*end && in_range(v, x);
        if (ok) *(double *)dst = x;
        break;
    case CLI_INT32:
    case CLI_INT64:
        ok = read_int(val, &end, &i) == 0 && !*end && in_range(v, (double)i) &&
             (v->kind == CLI_INT64 || (i >= INT32_MIN && i <= INT32_MAX));
        if (ok && v->kind == CLI_INT32) *(int32_t *)dst = (int32_t)i;
        if (ok && v->kind == CLI_INT64) *(int64_t *)dst = i;
        break;
    case CLI_UINT64:
        ok = read_uint(val, &end, &u) == 0 && !*end;
        if (ok) *(uint64_t *)dst = u;
        break;
    }
    if (ok) return 0;
    char name[64], what[128];
    if (v->kind == CLI_STRING && v->choices)
        snprintf(what, sizeof what, "one of %s", v->choices);
    else if (v->kind == CLI_STRING)
        snprintf(what, sizeof what, "a %s", v->metavar);
    else
        describe(v, what, sizeof what);
    return usage_error(c, "bad value '%s': %s needs %s", val, row_name(r, name, sizeof name), what);
}

/* Triangle's letters this project does not implement, for a clearer refusal than "unknown". */
static const struct {
    char letter;
    const char *what;
} triangle_only[] = {{'D', "conforming Delaunay"},
                     {'j', "jettison unused vertices"},
                     {'v', "Voronoi diagram"},
                     {'g', "OFF output"},
                     {'B', "no boundary markers"},
                     {'I', "no iteration numbers"},
                     {'O', "ignore holes"},
                     {'X', "no exact arithmetic"},
                     {'z', "numbering from zero"},
                     {'Y', "no Steiner points on the boundary"},
                     {'i', "incremental triangulation"},
                     {'F', "Fortune's sweepline"},
                     {'l', "vertical cuts only"},
                     {'s', "segments split instead of constrained"},
                     {'C', "consistency check; here: --check"},
                     {'u', "a compiled-in size test; here: --size FILE"},
                     {'U', "a compiled-in size test; here: --size FILE"}};

/* The letter at s is no option of p: one usage error naming it (and the string it is in). */
static int bad_letter(const parse_ctx *c, const char *s, const char *arg) {
    char in[160] = "";
    if (strlen(arg) > 2) snprintf(in, sizeof in, " in '%.120s'", arg);
    for (size_t k = 0; k < sizeof triangle_only / sizeof *triangle_only; k++)
        if (triangle_only[k].letter == *s)
            return usage_error(c, "option -%c%s is not supported (in Triangle: %s)", *s, in,
                               triangle_only[k].what);
    return usage_error(c, "unknown option '-%c'%s", *s, in);
}

/* Where a number glued on in a switch string begins: a digit, a point and a digit, or a sign
 * and either. */
static int glued_start(const char *s) {
    if (*s == '-' || *s == '+') s++;
    return isdigit((unsigned char)s[0]) || (s[0] == '.' && isdigit((unsigned char)s[1]));
}

/* Whether a whole argument is meant as a letter's value rather than the next option or the
 * input: it starts as a number does, or spells nan or inf (each refused later, strictly). */
static int looks_like_value(const char *s) {
    if (glued_start(s) || (s[0] == '.' && !s[1])) return 1;
    if (*s == '-' || *s == '+') s++;
    return !strncasecmp(s, "nan", 3) || !strncasecmp(s, "inf", 3);
}

static int stop_help(const parse_ctx *c, const cli_opt *r, FILE *out) {
    if (r->value->kind == CLI_HELP) {
        if (out) cli_help(c->p, out);
    } else if (out) {
        fprintf(out, "%s (pcdm) %s\n", c->p->name, pcdm_version());
    }
    *c->status = CLI_EXIT_OK;
    return 1;
}

/* Row r's meaning without a value: its bare number, or the flag row it names. */
static int store_bare(const parse_ctx *c, const cli_opt *r, cli_opts *o) {
    if (r->bare[0] != '-') return store(c, r, r->bare, o);
    return store(c, find_name(c->p, r->bare + 2, strlen(r->bare + 2)), NULL, o);
}

/* Walks the switch string argv[*i] (cli.h states the rule), storing each option; may take the
 * next argument as a lone letter's value (then *i moves on).  Returns 0 to go on, or 1 to stop
 * (help, version or a usage error, with *c->status). */
static int walk_switches(const parse_ctx *c, int argc, char **argv, int *i, FILE *out,
                         cli_opts *o) {
    const char *arg = argv[*i], *s = arg + 1;
    char name[64];
    while (*s) {
        const cli_opt *r = NULL;
        for (const cli_opt *const *t = c->p->tables; *t && !r; t++)
            for (const cli_opt *q = *t; q->help && !r; q++)
                if (q->spelling && !strncmp(s, q->spelling, strlen(q->spelling))) r = q;
        const char *at = s;
        if (r) {
            s += strlen(r->spelling);
        } else if ((r = find_letter(c->p, *s)) != NULL) {
            s++;
        } else {
            return bad_letter(c, s, arg);
        }
        if (r->value->kind == CLI_HELP || r->value->kind == CLI_VERSION)
            return stop_help(c, r, out);
        if (!takes_value(r)) {
            if (store(c, r, NULL, o)) return 1;
            continue;
        }
        int alone = at == arg + 1 && !*s;
        if (r->value->kind == CLI_STRING) {
            if (at != arg + 1)
                return usage_error(c,
                                   "option -%c (%s) must open its argument, as in -%c %s, not '%s'",
                                   r->letter, r->value->metavar, r->letter, r->value->metavar, arg);
            if (!*s && *i + 1 >= argc)
                return usage_error(c, "option %s needs a value (%s)",
                                   row_name(r, name, sizeof name), r->value->metavar);
            return store(c, r, *s ? s : argv[++*i], o);
        }
        if (glued_start(s)) { /* the number glued on: as far as strtod reads, then to a letter */
            char *e;
            (void)strtod(s, &e);
            while (*e && !isalpha((unsigned char)*e))
                e++;
            char val[128];
            snprintf(val, sizeof val, "%.*s", (int)(e - s), s);
            if (store(c, r, val, o)) return 1;
            s = e;
        } else if (alone && *i + 1 < argc && (!r->bare || looks_like_value(argv[*i + 1]))) {
            return store(c, r, argv[++*i], o); /* the spaced form, -q 30 */
        } else if (r->bare) {
            if (store_bare(c, r, o)) return 1;
        } else {
            return usage_error(c, "option %s needs a value (%s)%s%s%s",
                               row_name(r, name, sizeof name), r->value->metavar,
                               alone ? "" : " glued on, in '", alone ? "" : arg, alone ? "" : "'");
        }
    }
    return 0;
}

int cli_output_name(const char *input, int refine, char *buf, size_t n) {
    static const char *const ext[] = {".poly", ".node", ".ele", ".area"};
    size_t len = strlen(input);
    for (size_t k = 0; k < sizeof ext / sizeof *ext; k++) {
        size_t e = strlen(ext[k]);
        if (len > e && !strcmp(input + len - e, ext[k])) {
            len -= e;
            break;
        }
    }
    unsigned long long num = 1;
    if (refine) { /* NAME.N -> NAME.N+1 (up to 18 digits; more is no number) */
        size_t d = len;
        while (d > 0 && isdigit((unsigned char)input[d - 1]))
            d--;
        if (d < len && len - d <= 18 && d > 0 && input[d - 1] == '.') {
            num = strtoull(input + d, NULL, 10) + 1;
            len = d - 1;
        }
    }
    int w = snprintf(buf, n, "%.*s.%llu", (int)len, input, num);
    return w < 0 || (size_t)w >= n ? -1 : 0;
}

int cli_parse(const cli_prog *p, int argc, char **argv, FILE *out, FILE *err, cli_opts *o,
              int *status) {
    check_prog(p);
    memset(o, 0, sizeof *o);
    o->par.prog = p->name;
    for (const cli_opt *const *t = p->tables; *t; t++)
        for (const cli_opt *r = *t; r->help; r++)
            store_default(r, o);
    parse_ctx c = {p, err, status};
    const char **pos[2] = {&o->par.input, &o->mesh_prefix};
    int npos = 0, options_done = 0;
    char name[64];
    *status = CLI_EXIT_OK;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *val = NULL;
        const cli_opt *r;
        if (!options_done && !strcmp(a, "--")) {
            options_done = 1;
            continue;
        } else if (!options_done && a[0] == '-' && a[1] == '-') {
            const char *eq = strchr(a + 2, '=');
            size_t len = eq ? (size_t)(eq - (a + 2)) : strlen(a + 2);
            r = find_name(p, a + 2, len);
            if (!r) return usage_error(&c, "unknown option '%.*s'", (int)len + 2, a);
            if (eq && !takes_value(r))
                return usage_error(&c, "option --%s takes no value", r->name);
            if (eq) val = eq + 1;
        } else if (!options_done && a[0] == '-' && a[1]) {
            if (walk_switches(&c, argc, argv, &i, out, o)) return 1;
            continue;
        } else {
            if (npos == 0 && !p->args[0]) return usage_error(&c, "unexpected argument '%s'", a);
            if (npos == 2 || !p->args[npos])
                return usage_error(&c, "unexpected argument '%s' (%s is '%s')", a,
                                   p->args[npos - 1], *pos[npos - 1]);
            *pos[npos++] = a;
            continue;
        }
        if (r->value->kind == CLI_HELP || r->value->kind == CLI_VERSION)
            return stop_help(&c, r, out);
        if (takes_value(r) && !val) {
            if (i + 1 >= argc)
                return usage_error(&c, "option %s needs a value (%s)",
                                   row_name(r, name, sizeof name), r->value->metavar);
            val = argv[++i];
        }
        if (store(&c, r, val, o)) return 1;
    }
    if (npos < 2 && p->args[npos])
        return usage_error(&c, "missing %s; usage: %s", p->args[npos], p->usage);
    if (p->triangle_names && !o->par.out_prefix) {
        if (cli_output_name(o->par.input, o->par.refine, o->par.out_name, sizeof o->par.out_name))
            return usage_error(&c, "input name '%.100s...' too long to name the output (give -o)",
                               o->par.input);
        o->par.out_prefix = o->par.out_name;
    }
    for (const cli_opt *const *t = p->tables; *t; t++)
        for (const cli_opt *r = *t; r->help; r++) {
            if (r->value->kind != CLI_REAL || !(r->warn_above > 0)) continue;
            double x = *(const double *)((const char *)o + r->at.offset);
            if (x > r->warn_above && err && !o->par.quiet)
                fprintf(err, "%s: warning: %s %g %s\n", p->name, row_name(r, name, sizeof name), x,
                        r->warning);
        }
    return 0;
}

int cli_par_parse(int argc, char **argv, int rank, const void *prog, par_opts *o, int *status) {
    cli_opts c;
    int stop = cli_parse(prog, argc, argv, rank == 0 ? stdout : NULL, rank == 0 ? stderr : NULL, &c,
                         status);
    *o = c.par;
    if (c.par.out_prefix == c.par.out_name) o->out_prefix = o->out_name; /* not into c */
    return stop;
}
