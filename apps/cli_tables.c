/* cli_tables.c: the option tables of the four programs and their --help.
 *
 * Each row is one option (apps/cli.h: cli_opt); a program is a list of tables: the shared
 * mesher rows (Triangle's switches among them), the parallel rows, the program's own and the
 * common ones (--help, --version).  cli_help writes every row as "  -x, --name VALUE  help
 * (default: ...)", then the switch-string rule (meshers), the exit statuses and the program's
 * notes, wrapped at 100 columns.  The parser is cli.c; it checks these tables at every parse
 * (check_prog), so a malformed row is reported as a bug at once.
 */
#include "cli.h"

#include "bounds/bounds.h"
#include "par/pout.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

/* ---- the tables ------------------------------------------------------------------------ */

static const cli_value v_help = {CLI_HELP, NULL, 0, 0, 0, NULL, 0};
static const cli_value v_version = {CLI_VERSION, NULL, 0, 0, 0, NULL, 0};
static const cli_value v_flag = {CLI_FLAG, NULL, 0, 0, 0, NULL, 0};
static const cli_value v_file = {CLI_STRING, "FILE", 0, 0, 0, NULL, 0};
static const cli_value v_prefix = {CLI_STRING, "PREFIX", 0, 0, 0, NULL, 0};
static const cli_value v_angle = {CLI_REAL, "DEG", 0, BOUNDS_ANGLE_LIMIT, 0, NULL, 1};
static const cli_value v_check_angle = {CLI_REAL, "DEG", 0, 60, 0, NULL, 0};
static const cli_value v_area = {CLI_REAL, "AREA", 0, INFINITY, 0, NULL, 0};
static const cli_value v_count = {CLI_INT64, "N", 0, INFINITY, 0, NULL, 0};
static const cli_value v_nsub = {CLI_INT32, "K", 1, 1e6, 0, NULL, 0};
static const cli_value v_ratio = {CLI_REAL, "R", 0, 1e6, 1, NULL, 0};
static const cli_value v_seed = {CLI_UINT64, "SEED", 0, INFINITY, 0, NULL, 0};
static const cli_value v_poll = {CLI_INT32, "N", 1, 1e6, 0, NULL, 0};
static const cli_value v_inflight = {CLI_INT32, "N", 1, 1024, 0, NULL, 0};
static const cli_value v_threads = {CLI_INT32, "T", 1, 256, 0, NULL, 0};
static const cli_value v_balance = {CLI_STRING, "MODE", 0, 0, 0, "static|dynamic", 0};
static const cli_value v_net = {CLI_STRING, "SPEC", 0, 0, 0, NULL, 0};

/* Every program. */
static const cli_opt common_rows[] = {
    {.letter = 'h', .name = "help", .value = &v_help, .help = "print this text and exit"},
    {.name = "version",
     .value = &v_version,
     .help = "print the program's name and version and exit"},
    {.help = NULL}};

/* What every mesher (./mesh, ./pcdm, ./pbw) is told. */
_Static_assert(PAR_SVG_MAX_TRIS == 2000000, "--svg's help text states the cap");
_Static_assert(PAR_MAX_SUBDOMAINS == 256, "--subdomains' help text states the cap");

static const cli_opt mesher_rows[] = {
    {.letter = 'p',
     .value = &v_flag,
     .at = CLI_AT(pslg),
     .help = "the input is a PSLG (Triangle's -p: accepted; the input is always read as one, a "
             ".node file as its vertices alone)"},
    {.letter = 'q',
     .value = &v_angle,
     .at = CLI_AT(par.min_angle),
     .dflt = BOUNDS_DEFAULT_ANGLE,
     .bare = "20",
     .warn_above = 34,
     .warning = "above about 34 degrees may not be reachable (refinement then stops with an "
                "error)",
     .help = "minimum angle bound in degrees, at least 0 and below 60 (0: none; -q without a "
             "number: 20, as "
             "Triangle; above about 34, refinement may stall: it then stops with an error)"},
    {.letter = 'a',
     .value = &v_area,
     .at = CLI_AT(par.max_area),
     .dflt = 0,
     .dflt_text = "none",
     .bare = "--region-areas",
     .help = "maximum triangle area (0: none; -a without a number: --region-areas, as "
             "Triangle)"},
    {.letter = 'S',
     .value = &v_count,
     .at = CLI_AT(par.max_steiner),
     .dflt = -1,
     .dflt_text = "none",
     .help = "at most N Steiner points in all (the parallel meshers share them among the ranks)"},
    {.letter = 'o',
     .value = &v_prefix,
     .at = CLI_AT(par.out_prefix),
     .dflt_text = "as Triangle, next to the input: NAME.1 for NAME.poly; with -r, NAME.2 for "
                  "NAME.1",
     .help = "write PREFIX.node, PREFIX.ele, PREFIX.poly (Triangle's formats; -o2 is not a "
             "prefix but --order2: write a prefix starting with 2 spaced, -o 2x)"},
    {.letter = 'N',
     .name = "no-node",
     .value = &v_flag,
     .at = CLI_AT(par.no_node),
     .help = "write no .node file (Triangle's -N; -NEP: no Triangle files at all)"},
    {.letter = 'E',
     .name = "no-ele",
     .value = &v_flag,
     .at = CLI_AT(par.no_ele),
     .help = "write no .ele file (Triangle's -E)"},
    {.letter = 'P',
     .name = "no-poly",
     .value = &v_flag,
     .at = CLI_AT(par.no_poly),
     .help = "write no .poly file (Triangle's -P)"},
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
     .help = "give each triangle its region's attribute (the .poly's regions; 0 in none): the "
             ".ele's attribute column and VTK cell data region_attr"},
    {.name = "region-areas",
     .value = &v_flag,
     .at = CLI_AT(par.region_area),
     .help = "honour the .poly's per-region area bounds (Triangle's -a without a number; with "
             "-a AREA the smaller bound wins)"},
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
     .spelling = "o2",
     .value = &v_flag,
     .at = CLI_AT(par.order2),
     .help = "quadratic triangles: six nodes each, edge midpoints added to .node (Triangle's -o2, "
             "also inside a switch string: -pq30o2); --vtk: cell type 22, one file"},
    {.letter = 'r',
     .name = "refine",
     .value = &v_flag,
     .at = CLI_AT(par.refine),
     .help = "refine a mesh, keeping its vertices: the input is NAME (NAME.node, NAME.ele; "
             "NAME.poly if present, else its boundary edges are the segments; with -a alone "
             "NAME.area's bound per old triangle)"},
    {.letter = 'Q',
     .name = "quiet",
     .value = &v_flag,
     .at = CLI_AT(par.quiet),
     .help = "quiet: nothing on stdout or stderr but errors (and --stats, when asked for; "
             "--check's report only when it fails)"},
    {.letter = 'V',
     .name = "verbose",
     .value = &v_flag,
     .at = CLI_AT(par.verbose),
     .help = "verbose: a summary on stderr (input counts, bounds, phase times, the mesh made)"},
    {.name = "write-partial",
     .value = &v_flag,
     .at = CLI_AT(par.write_partial),
     .help = "when refinement cannot meet the bounds, still write the mesh made so far (as "
             "asked: conforming, outside the bounds; exit status 1 all the same)"},
    {.letter = 'c',
     .name = "convex-hull",
     .value = &v_flag,
     .at = CLI_AT(par.convex_hull),
     .help = "enclose the convex hull of the vertices with segments (Triangle's -c; boundary "
             "marker 1 on the new ones, cut at every vertex on the hull): the domain is "
             "everything inside the hull but the holes, dangling segments included; check the "
             "mesh with ./meshcheck -c, or against the written .poly, which holds the hull's "
             "segments"},
    {.name = "strict",
     .value = &v_flag,
     .at = CLI_AT(par.strict),
     .help = "refuse crossing or overlapping segments (default: split them at the intersection, "
             "as Triangle does)"},
    {.name = "msh",
     .value = &v_file,
     .at = CLI_AT(par.msh),
     .help = "write Gmsh MSH 4.1 ASCII (physical curves by boundary marker, surfaces by regional "
             "attribute; one file)"},
    {.name = "size",
     .value = &v_file,
     .at = CLI_AT(par.size_field),
     .help = "size field: a background mesh (FILE.node with one attribute, the target edge "
             "length h per vertex, and FILE.ele); h interpolated at each triangle's centroid, "
             "area at most sqrt(3)/4 h^2 (no bound outside it)"},
    {.help = NULL}};

/* What both parallel meshers are told on top. */
static const cli_opt parallel_rows[] = {
    {.name = "subdomains",
     .value = &v_nsub,
     .at = CLI_AT(par.nsub),
     .dflt_text = "./pcdm: 16, or ranks x threads where that is more, fewer on a small mesh; "
                  "./pcdm --async and "
                  "./pbw: the ranks, x4 with --balance dynamic",
     .help = "number of subdomains, at least the number of ranks (the automatic decomposition "
             "makes at most 256; --cuts any number)"},
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
     .dflt_text = "300 for ./pcdm, 1024 for ./pbw",
     .help = "local work units (insertions, splits) between two services of incoming requests "
             "(1: after every insertion, as the paper)"},
    {.name = "perturb",
     .value = &v_seed,
     .at = CLI_AT(par.perturb),
     .dflt_text = "off, or the environment's RT_PERTURB",
     .help = "delay and reorder message delivery, reproducibly from SEED; 0: off"},
    {.name = "net",
     .value = &v_net,
     .at = CLI_AT(par.net),
     .dflt_text = "off, or the environment's PCDM_NET",
     .help = "model a slower network: every message between ranks is held at its receiver until "
             "LAT_US microseconds plus its size at MBPS megabytes per second after it was sent "
             "(\"LAT_US[,MBPS]\"; sp2 = 29,33.6, the paper's IBM SP2; off)"},
    {.help = NULL}};

static const cli_opt pcdm_rows[] = {
    {.name = "threads",
     .value = &v_threads,
     .at = CLI_AT(par.threads),
     .dflt_text = "1",
     .help = "refine each rank's subdomains on T threads at once (the mesh is the same as on "
             "one thread); one process needs "
             "no mpirun: ./pcdm --threads 2 in.poly uses two cores"},
    {.name = "async",
     .value = &v_flag,
     .at = CLI_AT(par.async),
     .help = "the paper's asynchronous protocol: one mesh per rank, split requests served as "
             "they arrive, so the mesh depends on message timing (default: subdomains refined "
             "in rounds, the same mesh, bit for bit, for any ranks, threads and timing, given "
             "the input, the bounds and --subdomains); not with --threads above 1 or --balance "
             "dynamic"},
    {.name = "deterministic",
     .value = &v_flag,
     .at = CLI_AT(par.deterministic),
     .help = "refinement in rounds: the default (accepted, changes nothing)"},
    {.name = "balance",
     .value = &v_balance,
     .at = CLI_AT(par.balance),
     .dflt_text = "static",
     .help = "static: each rank refines the subdomains the decomposition gives it; dynamic: an "
             "idle rank takes unstarted subdomains from busy ones (the mesh stays the same)"},
    {.help = NULL}};

static const cli_opt pbw_rows[] = {
    {.name = "phases",
     .value = &v_flag,
     .at = CLI_AT(par.phases),
     .help = "refine in phases (the data-parallel variant of the paper's Figure 1)"},
    {.name = "inflight",
     .value = &v_inflight,
     .at = CLI_AT(par.inflight),
     .dflt = 0,
     .dflt_text = "2",
     .help = "cavities reaching other ranks that a rank keeps in flight at most (more hide "
             "latency but conflict with each other: more RSRs and undone attempts); eight times "
             "as many, in a shuffled order, once the rank has no work of its own left"},
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
     .value = &v_check_angle,
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
    {.letter = 'c',
     .name = "convex-hull",
     .value = &v_flag,
     .at = CLI_AT(par.convex_hull),
     .help = "the mesh was made with -c: its domain is input.poly's segments plus its convex hull "
             "enclosed by segments (needed unless input.poly is the mesh's own written .poly, "
             "which holds the hull's segments)"},
    {.letter = 'A',
     .name = "region-attributes",
     .value = &v_flag,
     .at = CLI_AT(par.region_attr),
     .help = "fail unless each triangle's .ele attribute is its region's (found from the .poly; "
             "0 outside every region)"},
    {.name = "region-areas",
     .value = &v_flag,
     .at = CLI_AT(par.region_area),
     .help = "fail if a triangle's area exceeds its region's bound (the .poly's regions)"},
    {.help = NULL}};

static const cli_opt *const mesh_tables[] = {mesher_rows, mesh_rows, common_rows, NULL};
static const cli_opt *const meshcheck_tables[] = {meshcheck_rows, common_rows, NULL};
static const cli_opt *const pcdm_tables[] = {mesher_rows, parallel_rows, pcdm_rows, common_rows,
                                             NULL};
static const cli_opt *const pbw_tables[] = {mesher_rows, parallel_rows, pbw_rows, common_rows,
                                            NULL};

const cli_prog cli_mesh = {
    .name = "mesh",
    .usage = "./mesh [options] input.poly",
    .about = "Constrained Delaunay triangulation + Ruppert/Chew quality refinement.",
    .tables = mesh_tables,
    .args = {"input.poly", NULL},
    .notes = "Coordinates: any finite doubles whose largest magnitude is at least 2^-723 (about "
             "1.8e-218); nonzero coordinates below 2^-247 (about 4.4e-75) times the largest are "
             "rejected (FILE:LINE message).  Precision: a domain whose smallest feature (its "
             "shortest segment, the smallest distance between a vertex and a segment it is not "
             "on) is at least 2^-40 of its largest coordinate (1 mm at 1e9, 1e-5 m in UTM "
             "metres) meshes at -q 30 with any area bound, wherever it lies: a new vertex rounds "
             "to the coordinates' grid, and refinement and --check allow a split point a few "
             "ulps off its segment.  Features below about 2^-44 of the magnitude cannot be "
             "resolved: such inputs, and angle bounds refinement cannot reach, end with an "
             "error (exit 1), never with a mesh outside the bounds unless --write-partial asks "
             "for it.",
    .triangle_names = 1};
const cli_prog cli_meshcheck = {
    .name = "meshcheck",
    .usage = "meshcheck [options] input.poly PREFIX",
    .about = "Validates PREFIX.node/.ele (and PREFIX.poly) against input.poly: conformity, "
             "orientation, input vertices and segments present, domain area, local Delaunay "
             "property, and the quality bounds given.",
    .tables = meshcheck_tables,
    .args = {"input.poly", "PREFIX"}};
const cli_prog cli_pcdm = {.name = "pcdm",
                           .usage = "mpirun -np P ./pcdm [options] input.poly",
                           .about = "Parallel constrained Delaunay meshing (PCDM: constrained "
                                    "subdomains, TR-97-17 section 3).",
                           .tables = pcdm_tables,
                           .args = {"input.poly", NULL},
                           .notes = "Every rank exits with the same status.",
                           .triangle_names = 1};
const cli_prog cli_pbw = {.name = "pbw",
                          .usage = "mpirun -np P ./pbw [options] input.poly",
                          .about = "Parallel Delaunay meshing (PBW: distributed Bowyer-Watson, "
                                   "TR-97-17 section 2).",
                          .tables = pbw_tables,
                          .args = {"input.poly", NULL},
                          .notes = "Every rank exits with the same status.",
                          .triangle_names = 1};

/* The meshers' --help states the switch-string rule (cli.h) in short. */
static const char syntax_text[] =
    "Switch strings as Triangle's: -pq30a0.01Q is -p -q 30 -a 0.01 -Q (a glued number ends at "
    "the next letter); -q and -a without a number mean 20 degrees and --region-areas; -q or -a "
    "alone take the next argument only if it looks like a number (-q 30, but -q lake.poly is "
    "-q 20); -o2 (also inside a string: -pq30o2) is --order2, any other -oPREFIX or -o PREFIX "
    "the output prefix.  Without -o, output goes next to the input: NAME.1.node/.ele/.poly for "
    "NAME.poly (-r: NAME.2 for NAME.1); -NEP writes none of them.";

static const char exit_text[] = "Exit status: 0 success; 1 bad input (an unreadable or invalid "
                                "file), an output error, a failed mesh or a failed check; 2 "
                                "usage error; 3 the Steiner limit (-S) stopped refinement: the "
                                "mesh is written and conforming but does not meet -q/-a.";

static int has_value(const cli_opt *r) {
    return r->value->kind != CLI_FLAG && r->value->kind != CLI_HELP &&
           r->value->kind != CLI_VERSION;
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
            char left[64], text[640], dflt[192] = "";
            int n = snprintf(left, sizeof left, "  ");
            char sw[2] = {r->letter, 0};
            if (r->letter || r->spelling)
                n += snprintf(left + n, sizeof left - (size_t)n, "-%s%s",
                              r->spelling ? r->spelling : sw, r->name ? ", " : "");
            if (r->name) n += snprintf(left + n, sizeof left - (size_t)n, "--%s", r->name);
            if (has_value(r))
                n += snprintf(left + n, sizeof left - (size_t)n, " %s", r->value->metavar);
            if (r->dflt_text)
                snprintf(dflt, sizeof dflt, " (default: %s)", r->dflt_text);
            else if (has_value(r) && r->value->kind != CLI_STRING)
                snprintf(dflt, sizeof dflt, " (default: %.15g)", r->dflt);
            snprintf(text, sizeof text, "%s%s", r->help, dflt);
            fputs(left, f);
            if (n >= COL - 1)
                fprintf(f, "\n%*s", COL, "");
            else
                fprintf(f, "%*s", COL - n, "");
            wrap(f, text, COL);
        }
    if (p->triangle_names) wrap(f, syntax_text, 0);
    wrap(f, exit_text, 0);
    if (p->notes) wrap(f, p->notes, 0);
}
