/* cli.c: the option tables of the four programs and the one parser that reads them.
 *
 * cli_parse walks argv once, left to right: "--" ends the options; "--name" or "--name=value"
 * is looked up by long name, "-x" by letter (a letter's value may be glued on, "-q30"); any
 * other argument is positional.  A row's value is read by the reader of its kind (read_real,
 * read_int, read_uint: decimal only, no blanks, NaN, infinities or overflow; each reports where
 * its number ends) and checked against the row's range; strings must not be empty.  The first
 * problem ends the parse with one line "PROG: problem (try --help)" and status 2.
 *
 * Invariants: every row's destination has the size its kind stores (checked, with letter and
 * name uniqueness, by check_prog at every parse: a bad table is a bug, reported as one); the
 * defaults are stored from the same rows that --help prints them from.
 */
#include "cli.h"

#include "base/base.h"
#include "par/pout.h"

#include <ctype.h>
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ---- the tables ------------------------------------------------------------------------ */

static const cli_value v_help = {CLI_HELP, NULL, 0, 0, 0};
static const cli_value v_flag = {CLI_FLAG, NULL, 0, 0, 0};
static const cli_value v_file = {CLI_STRING, "FILE", 0, 0, 0};
static const cli_value v_prefix = {CLI_STRING, "PREFIX", 0, 0, 0};
static const cli_value v_angle = {CLI_REAL, "DEG", 0, 60, 0};
static const cli_value v_area = {CLI_REAL, "AREA", 0, INFINITY, 0};
static const cli_value v_count = {CLI_INT64, "N", 0, INFINITY, 0};
static const cli_value v_nsub = {CLI_INT32, "K", 1, 1e6, 0};
static const cli_value v_ratio = {CLI_REAL, "R", 0, 1e6, 1};
static const cli_value v_seed = {CLI_UINT64, "SEED", 0, INFINITY, 0};
static const cli_value v_poll = {CLI_INT32, "N", 1, 1e6, 0};

/* Every program. */
static const cli_opt common_rows[] = {
    {.letter = 'h', .name = "help", .value = &v_help, .help = "print this text and exit"},
    {.help = NULL}};

/* What every mesher (./mesh, ./pcdm, ./pbw) is told. */
_Static_assert(PAR_SVG_MAX_TRIS == 2000000, "--svg's help text states the cap");

static const cli_opt mesher_rows[] = {
    {.letter = 'q',
     .value = &v_angle,
     .at = CLI_AT(par.min_angle),
     .dflt = 20.7,
     .warn_above = 34,
     .warning = "above about 34 degrees may not terminate",
     .help = "minimum angle bound in degrees, 0 to 60 (0: none; above about 34, refinement may "
             "not terminate)"},
    {.letter = 'a',
     .value = &v_area,
     .at = CLI_AT(par.max_area),
     .dflt = 0,
     .dflt_text = "none",
     .help = "maximum triangle area (0: none)"},
    {.letter = 'S',
     .value = &v_count,
     .at = CLI_AT(par.max_steiner),
     .dflt = -1,
     .dflt_text = "none",
     .help = "at most N Steiner points in all (the parallel meshers share them among the ranks)"},
    {.letter = 'o',
     .value = &v_prefix,
     .at = CLI_AT(par.out_prefix),
     .help = "write PREFIX.node, PREFIX.ele, PREFIX.poly (Triangle's formats)"},
    {.name = "vtk",
     .value = &v_file,
     .at = CLI_AT(par.vtk),
     .help = "write VTK, binary unless --vtk-ascii (./mesh: legacy FILE; ./pcdm, ./pbw: FILE's "
             ".pvtu index, e.g. F.pvtu for F.vtk, with one piece F_R.vtu per rank, cell data "
             "rank; no gather)"},
    {.name = "vtk-ascii",
     .value = &v_flag,
     .at = CLI_AT(par.vtk_ascii),
     .help = "write --vtk as ASCII (default: binary)"},
    {.name = "svg",
     .value = &v_file,
     .at = CLI_AT(par.svg),
     .help = "write an SVG picture (parallel meshers: coloured by rank, interfaces drawn; "
             "collected on rank 0, at most 2000000 triangles)"},
    {.name = "stats",
     .value = &v_flag,
     .at = CLI_AT(par.stats),
     .help = "print the statistics line last (parallel meshers: per-rank lines before it)"},
    {.name = "check",
     .value = &v_flag,
     .at = CLI_AT(par.check),
     .help = "validate the mesh as ./meshcheck does (parallel meshers: each rank its own "
             "part, interfaces compared, results reduced); exit 1 if it fails"},
    {.name = "circumcenters",
     .value = &v_flag,
     .at = CLI_AT(par.circumcenters),
     .help = "insert circumcenters only, the paper's choice (default: Ungor's off-centers where "
             "they are closer, fewer triangles)"},
    {.name = "progress",
     .value = &v_flag,
     .at = CLI_AT(par.progress),
     .help = "progress lines on stderr (./mesh prints them anyway when stderr is a terminal)"},
    {.letter = 'A',
     .name = "region-attributes",
     .value = &v_flag,
     .at = CLI_AT(par.region_attr),
     .help = "give each triangle its region's attribute (the .poly's regions), written to .ele"},
    {.name = "region-areas",
     .value = &v_flag,
     .at = CLI_AT(par.region_area),
     .help = "honour the .poly's per-region area bounds (Triangle's -a without a number)"},
    {.letter = 'e',
     .name = "edges",
     .value = &v_flag,
     .at = CLI_AT(par.edges),
     .help = "also write PREFIX.edge (every edge, with its boundary marker)"},
    {.letter = 'n',
     .name = "neighbors",
     .value = &v_flag,
     .at = CLI_AT(par.neighbors),
     .help = "also write PREFIX.neigh (the three neighbours of every triangle)"},
    {.name = "order2",
     .value = &v_flag,
     .at = CLI_AT(par.order2),
     .help = "quadratic triangles: six nodes each, edge midpoints added (Triangle's -o2)"},
    {.letter = 'r',
     .name = "refine",
     .value = &v_flag,
     .at = CLI_AT(par.refine),
     .help = "refine a mesh: the input is NAME.node/NAME.ele (and NAME.poly, NAME.area if "
             "present)"},
    {.letter = 'Q',
     .name = "quiet",
     .value = &v_flag,
     .at = CLI_AT(par.quiet),
     .help = "quiet: nothing but errors"},
    {.letter = 'V',
     .name = "verbose",
     .value = &v_flag,
     .at = CLI_AT(par.verbose),
     .help = "verbose: more detail on stderr"},
    {.name = "strict",
     .value = &v_flag,
     .at = CLI_AT(par.strict),
     .help = "refuse crossing or overlapping segments (default: split them at the intersection, "
             "as Triangle does)"},
    {.name = "msh",
     .value = &v_file,
     .at = CLI_AT(par.msh),
     .help = "write Gmsh 4.1 (physical groups from boundary markers and region attributes)"},
    {.name = "size",
     .value = &v_file,
     .at = CLI_AT(par.size_field),
     .help = "size field: a background mesh (.node with one attribute, the target edge length "
             "per vertex, and .ele), interpolated"},
    {.help = NULL}};

/* What both parallel meshers are told on top. */
static const cli_opt parallel_rows[] = {
    {.name = "subdomains",
     .value = &v_nsub,
     .at = CLI_AT(par.nsub),
     .dflt_text = "the number of ranks",
     .help = "number of subdomains, at least the number of ranks"},
    {.name = "imbalance",
     .value = &v_ratio,
     .at = CLI_AT(par.imbalance),
     .dflt = 1,
     .help = "rank 0 gets R times the work of every other rank (the paper's two-to-one "
             "experiment)"},
    {.name = "cuts",
     .value = &v_file,
     .at = CLI_AT(par.cuts),
     .help = "take the subdomain cuts from FILE (x1 y1 x2 y2 per line)"},
    {.name = "write-cuts",
     .value = &v_file,
     .at = CLI_AT(par.write_cuts),
     .help = "write the cuts used to FILE (rank 0)"},
    {.name = "poll",
     .value = &v_poll,
     .at = CLI_AT(par.poll_every),
     .dflt = 0,
     .dflt_text = "300 for ./pcdm, 64 for ./pbw",
     .help = "local work units (insertions, splits) between two services of incoming requests "
             "(1: after every insertion, as the paper)"},
    {.name = "perturb",
     .value = &v_seed,
     .at = CLI_AT(par.perturb),
     .dflt_text = "off, or the environment's RT_PERTURB",
     .help = "delay and reorder message delivery, reproducibly from SEED; 0: off"},
    {.help = NULL}};

static const cli_opt pcdm_rows[] = {
    {.name = "deterministic",
     .value = &v_flag,
     .at = CLI_AT(par.deterministic),
     .help = "refine each subdomain in rounds, its neighbours' splits applied in canonical order: "
             "the same mesh, bit for bit, for any rank count and message timing, given the "
             "input, the bounds and the subdomains (--subdomains)"},
    {.help = NULL}};

static const cli_opt pbw_rows[] = {
    {.name = "phases",
     .value = &v_flag,
     .at = CLI_AT(par.phases),
     .help = "refine in phases (the data-parallel variant of the paper's Figure 1)"},
    {.help = NULL}};

static const cli_opt mesh_rows[] = {
    {.name = "lens",
     .value = &v_flag,
     .at = CLI_AT(lens),
     .help = "diametral lenses decide encroachment (as Triangle -q); default: diametral circles "
             "(Ruppert)"},
    {.name = "cdt-only",
     .value = &v_flag,
     .at = CLI_AT(cdt_only),
     .help = "no refinement at all: the constrained Delaunay triangulation"},
    {.help = NULL}};

/* ./meshcheck's -q and -a are the bounds to verify: the same values and checks as the
 * meshers', but no bound unless given. */
static const cli_opt meshcheck_rows[] = {
    {.letter = 'q',
     .value = &v_angle,
     .at = CLI_AT(par.min_angle),
     .dflt = 0,
     .dflt_text = "no check",
     .help = "fail if a triangle has an angle below DEG degrees (triangles at input angles "
             "below 60 degrees are exempt)"},
    {.letter = 'a',
     .value = &v_area,
     .at = CLI_AT(par.max_area),
     .dflt = 0,
     .dflt_text = "no check",
     .help = "fail if a triangle's area exceeds AREA"},
    {.name = "interfaces-delaunay",
     .value = &v_flag,
     .at = CLI_AT(interfaces_delaunay),
     .help = "interface constraint edges must be locally Delaunay too"},
    {.help = NULL}};

static const cli_opt *const mesh_tables[] = {mesher_rows, mesh_rows, common_rows, NULL};
static const cli_opt *const meshcheck_tables[] = {meshcheck_rows, common_rows, NULL};
static const cli_opt *const pcdm_tables[] = {mesher_rows, parallel_rows, pcdm_rows, common_rows,
                                             NULL};
static const cli_opt *const pbw_tables[] = {mesher_rows, parallel_rows, pbw_rows, common_rows,
                                            NULL};

const cli_prog cli_mesh = {"mesh",
                           "./mesh [options] input.poly",
                           "Constrained Delaunay triangulation + Ruppert/Chew quality refinement.",
                           mesh_tables,
                           {"input.poly", NULL},
                           "Coordinates: any finite doubles whose largest magnitude is at least "
                           "2^-723 (about 1.8e-218); nonzero coordinates below 2^-247 (about "
                           "4.4e-75) times the largest are rejected (FILE:LINE message).  Features "
                           "below about 2^-44 of the coordinates' magnitude cannot be resolved: "
                           "such inputs, and angle bounds refinement cannot reach, end with an "
                           "error (exit 1), never with a mesh outside the bounds."};
const cli_prog cli_meshcheck = {
    "meshcheck",
    "meshcheck [options] input.poly PREFIX",
    "Validates PREFIX.node/.ele (and PREFIX.poly) against input.poly: conformity, orientation, "
    "input vertices and segments present, domain area, local Delaunay property, and the quality "
    "bounds given.",
    meshcheck_tables,
    {"input.poly", "PREFIX"},
    NULL};
const cli_prog cli_pcdm = {"pcdm",
                           "mpirun -np P ./pcdm [options] input.poly",
                           "Parallel constrained Delaunay meshing (PCDM: constrained subdomains, "
                           "TR-97-17 section 3).",
                           pcdm_tables,
                           {"input.poly", NULL},
                           "Every rank exits with the same status."};
const cli_prog cli_pbw = {"pbw",
                          "mpirun -np P ./pbw [options] input.poly",
                          "Parallel Delaunay meshing (PBW: distributed Bowyer-Watson, TR-97-17 "
                          "section 2).",
                          pbw_tables,
                          {"input.poly", NULL},
                          "Every rank exits with the same status."};

static const char exit_text[] = "Exit status: 0 success; 1 bad input (an unreadable or invalid "
                                "file), an output error, a failed mesh or a failed check; 2 "
                                "usage error; 3 the Steiner limit (-S) stopped refinement: the "
                                "mesh is written and conforming but does not meet -q/-a.";

/* ---- table checks ------------------------------------------------------------------------ */

static size_t kind_size(cli_kind k) {
    switch (k) {
    case CLI_HELP:
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
    return r->value->kind != CLI_FLAG && r->value->kind != CLI_HELP;
}

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
    return (v->min_open ? x > v->min : x >= v->min) && x <= v->max;
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
    if (v->max < 9e18) snprintf(hi, sizeof hi, " at most %.15g", v->max);
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
        MESH_BUG("--help reached store()");
    case CLI_STRING:
        ok = val[0] != 0;
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
    if (v->kind == CLI_STRING)
        snprintf(what, sizeof what, "a %s", v->metavar);
    else
        describe(v, what, sizeof what);
    return usage_error(c, "bad value '%s': %s needs %s", val, row_name(r, name, sizeof name), what);
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
            /* a Triangle switch string would be walked here, letter by letter */
            r = find_letter(p, a[1]);
            if (!r || (a[2] && !takes_value(r))) return usage_error(&c, "unknown option '%s'", a);
            if (a[2]) val = a + 2;
        } else {
            if (npos == 0 && !p->args[0]) return usage_error(&c, "unexpected argument '%s'", a);
            if (npos == 2 || !p->args[npos])
                return usage_error(&c, "unexpected argument '%s' (%s is '%s')", a,
                                   p->args[npos - 1], *pos[npos - 1]);
            *pos[npos++] = a;
            continue;
        }
        if (r->value->kind == CLI_HELP) {
            if (out) cli_help(p, out);
            return 1;
        }
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
    for (const cli_opt *const *t = p->tables; *t; t++)
        for (const cli_opt *r = *t; r->help; r++) {
            if (r->value->kind != CLI_REAL || !(r->warn_above > 0)) continue;
            double x = *(const double *)((const char *)o + r->at.offset);
            if (x > r->warn_above && err)
                fprintf(err, "%s: warning: %s %g %s\n", p->name, row_name(r, name, sizeof name), x,
                        r->warning);
        }
    return 0;
}

/* ---- help -------------------------------------------------------------------------------- */

/* Writes text from column col (the cursor is there), wrapping at 100 columns back to col. */
static void wrap(FILE *f, const char *text, int col) {
    int at = col;
    while (*text) {
        while (*text == ' ')
            text++;
        size_t w = strcspn(text, " ");
        if (at > col && at + 1 + (int)w > 100) {
            fprintf(f, "\n%*s", col, "");
            at = col;
        } else if (at > col) {
            fputc(' ', f);
            at++;
        }
        fprintf(f, "%.*s", (int)w, text);
        at += (int)w;
        text += w;
    }
    fputc('\n', f);
}

void cli_help(const cli_prog *p, FILE *f) {
    enum { COL = 24 };
    fprintf(f, "usage: %s\n", p->usage);
    wrap(f, p->about, 0);
    fprintf(f, "Options:\n");
    for (const cli_opt *const *t = p->tables; *t; t++)
        for (const cli_opt *r = *t; r->help; r++) {
            char left[64], text[512], dflt[96] = "";
            int n = snprintf(left, sizeof left, "  ");
            if (r->letter)
                n += snprintf(left + n, sizeof left - (size_t)n, "-%c%s", r->letter,
                              r->name ? ", " : "");
            if (r->name) n += snprintf(left + n, sizeof left - (size_t)n, "--%s", r->name);
            if (takes_value(r))
                n += snprintf(left + n, sizeof left - (size_t)n, " %s", r->value->metavar);
            if (r->dflt_text)
                snprintf(dflt, sizeof dflt, " (default: %s)", r->dflt_text);
            else if (takes_value(r) && r->value->kind != CLI_STRING)
                snprintf(dflt, sizeof dflt, " (default: %.15g)", r->dflt);
            snprintf(text, sizeof text, "%s%s", r->help, dflt);
            fputs(left, f);
            if (n >= COL - 1)
                fprintf(f, "\n%*s", COL, "");
            else
                fprintf(f, "%*s", COL - n, "");
            wrap(f, text, COL);
        }
    wrap(f, exit_text, 0);
    if (p->notes) wrap(f, p->notes, 0);
}

int cli_par_parse(int argc, char **argv, int rank, const void *prog, par_opts *o, int *status) {
    cli_opts c;
    int stop = cli_parse(prog, argc, argv, rank == 0 ? stdout : NULL, rank == 0 ? stderr : NULL, &c,
                         status);
    *o = c.par;
    return stop;
}
