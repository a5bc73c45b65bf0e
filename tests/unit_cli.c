/* unit_cli: Check suite for the front end's parser (apps/cli.c), without MPI.
 *
 * Every program's defaults as the tables state them; the accepted spellings (-q30, -q 30,
 * --vtk=F, "--"); the edges of every number kind (largest int64 for -S and one more, the
 * largest uint64 seed and one more, --subdomains 1 and 1000001, --imbalance just above 0);
 * what strict reading refuses (blanks, hexadecimal, NaN, infinities, trailing characters,
 * empty strings); the usage-error status and its one line; --help's status and its text (exit
 * statuses, every option of the program and none of another program's); Triangle's switch
 * strings (each the same options as its spaced form, for ./mesh and ./pbw), their errors (a
 * letter not supported or unknown, a value letter without its value, a bad glued number), the
 * bare -q and -a, --version, and Triangle's output names (cli_output_name, the default prefix,
 * its copy through cli_par_parse).
 */
#include "../apps/cli.h"
#include "check_run.h"
#include "pcdm.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Parses the NULL-terminated argument list for p; returns -1 when parsing goes on, else the
 * exit status; *msg (if not NULL) gets what went to stderr or stdout. */
static int parse(const cli_prog *p, cli_opts *o, char *msg, size_t msglen, ...) {
    char *argv[32];
    int argc = 0;
    argv[argc++] = (char *)p->name;
    va_list ap;
    va_start(ap, msglen);
    for (char *a; (a = va_arg(ap, char *)) != NULL;)
        argv[argc++] = a;
    va_end(ap);
    argv[argc] = NULL;
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    ck_assert_ptr_nonnull(f);
    int status = -7;
    int stop = cli_parse(p, argc, argv, f, f, o, &status);
    fclose(f);
    if (msg) snprintf(msg, msglen, "%s", buf ? buf : "");
    free(buf);
    return stop ? status : -1;
}

START_TEST(test_defaults) {
    cli_opts o;
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "in.poly", NULL), -1);
    ck_assert_str_eq(o.par.prog, "mesh");
    ck_assert_str_eq(o.par.input, "in.poly");
    ck_assert(o.par.min_angle == 20.7);
    ck_assert(o.par.max_area == 0);
    ck_assert_int_eq(o.par.max_steiner, -1);
    ck_assert_str_eq(o.par.out_prefix, "in.1"); /* Triangle's name (test_output_names) */
    ck_assert_int_eq(o.par.stats + o.par.check + o.par.circumcenters + o.lens + o.cdt_only, 0);
    ck_assert_int_eq(parse(&cli_pbw, &o, NULL, 0, "in.poly", NULL), -1);
    ck_assert(o.par.min_angle == 20.7);
    ck_assert(o.par.imbalance == 1);
    ck_assert_int_eq(o.par.nsub, 0);
    ck_assert_int_eq(o.par.max_steiner, -1);
    ck_assert_uint_eq(o.par.perturb, 0);
    ck_assert_int_eq(parse(&cli_meshcheck, &o, NULL, 0, "in.poly", "out", NULL), -1);
    ck_assert(o.par.min_angle == 0); /* the validator checks no bound unless told */
    ck_assert(o.par.max_area == 0);
    ck_assert_str_eq(o.mesh_prefix, "out");
}
END_TEST

START_TEST(test_spellings) {
    cli_opts o;
    char msg[512];
    ck_assert_int_eq(parse(&cli_pcdm, &o, msg, sizeof msg, "-q30", "-a", "0.5", "--vtk=v.vtk",
                           "--svg", "s.svg", "-oout", "--stats", "--check", "--progress",
                           "--subdomains=8", "--imbalance", "2.5", "--perturb", "7", "--",
                           "-x.poly", NULL),
                     -1);
    ck_assert(o.par.min_angle == 30 && o.par.max_area == 0.5);
    ck_assert_str_eq(o.par.vtk, "v.vtk");
    ck_assert_str_eq(o.par.svg, "s.svg");
    ck_assert_str_eq(o.par.out_prefix, "out");
    ck_assert_int_eq(o.par.stats + o.par.check + o.par.progress, 3);
    ck_assert_int_eq(o.par.nsub, 8);
    ck_assert(o.par.imbalance == 2.5);
    ck_assert_uint_eq(o.par.perturb, 7);
    ck_assert_str_eq(o.par.input, "-x.poly");
    ck_assert_str_eq(msg, "");
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "--circumcenters", "--lens", "--cdt-only",
                           "in.poly", "-q", "0", NULL),
                     -1);
    ck_assert_int_eq(o.par.circumcenters + o.lens + o.cdt_only, 3);
    ck_assert(o.par.min_angle == 0);
}
END_TEST

START_TEST(test_number_edges) {
    cli_opts o;
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-S", "9223372036854775807", "i", NULL), -1);
    ck_assert_int_eq(o.par.max_steiner, INT64_MAX);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-S", "9223372036854775808", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_pbw, &o, NULL, 0, "--perturb", "18446744073709551615", "i", NULL),
                     -1);
    ck_assert_uint_eq(o.par.perturb, UINT64_MAX);
    ck_assert_int_eq(parse(&cli_pbw, &o, NULL, 0, "--perturb", "18446744073709551616", "i", NULL),
                     2);
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--subdomains", "1", "i", NULL), -1);
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--subdomains", "1000000", "i", NULL), -1);
    ck_assert_int_eq(o.par.nsub, 1000000);
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--subdomains", "1000001", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--subdomains", "0", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--imbalance", "1e-9", "i", NULL), -1);
    ck_assert(o.par.imbalance == 1e-9);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-q", "59.999", "-a", "1e300", "i", NULL), -1);
    ck_assert(o.par.min_angle == 59.999 && o.par.max_area == 1e300);
    /* a bound of 60 no mesh meets: refused as the library refuses it (bounds_check) */
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-q", "60", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-q", "60.000001", "i", NULL), 2);
    /* ./meshcheck may hold a mesh to 60 */
    ck_assert_int_eq(parse(&cli_meshcheck, &o, NULL, 0, "-q", "60", "m", "i", NULL), -1);
    ck_assert(o.par.min_angle == 60);
}
END_TEST

/* a word among choices (--balance static|dynamic): exact words only, a usage error naming them
 * otherwise; ./pbw has no --balance */
START_TEST(test_choices) {
    cli_opts o;
    char msg[512];
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "i", NULL), -1);
    ck_assert_ptr_null(o.par.balance);
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--balance", "dynamic", "i", NULL), -1);
    ck_assert_str_eq(o.par.balance, "dynamic");
    ck_assert(par_balance_dynamic(&o.par));
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--balance=static", "i", NULL), -1);
    ck_assert(!par_balance_dynamic(&o.par));
    static const char *const bad[] = {"", "dyn", "dynamics", "Dynamic", "static|dynamic", "|"};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        int st = parse(&cli_pcdm, &o, msg, sizeof msg, "--balance", bad[k], "i", NULL);
        ck_assert_msg(st == 2, "--balance '%s' gave status %d", bad[k], st);
        ck_assert_msg(bad[k][0] == 0 || strstr(msg, "one of static|dynamic"), "message: %s", msg);
    }
    ck_assert_int_eq(parse(&cli_pbw, &o, NULL, 0, "--balance", "dynamic", "i", NULL), 2);
}
END_TEST

START_TEST(test_strict) {
    static const char *const bad_reals[] = {"nan", "NAN", "-nan", "inf",  "+Inf",  "infinity",
                                            " 30", "30 ", "30x",  "0x1e", "1e400", "-1",
                                            "",    ".",   "e5",   "1e",   "--1",   "1,5"};
    cli_opts o;
    char msg[512];
    for (size_t k = 0; k < sizeof bad_reals / sizeof *bad_reals; k++) {
        for (int opt = 0; opt < 2; opt++) {
            const char *name = opt ? "-a" : "-q";
            int st = parse(&cli_mesh, &o, msg, sizeof msg, name, bad_reals[k], "i", NULL);
            ck_assert_msg(st == 2, "%s '%s' gave status %d", name, bad_reals[k], st);
            ck_assert_msg(strchr(msg, '\n') == msg + strlen(msg) - 1, "not one line: %s", msg);
            ck_assert_msg(strstr(msg, "(try --help)") && !strncmp(msg, "mesh: ", 6), "%s", msg);
        }
    }
    static const char *const bad_ints[] = {"1.0", "1e3", " 5", "5 ", "0x10", "-", "+", ""};
    for (size_t k = 0; k < sizeof bad_ints / sizeof *bad_ints; k++)
        ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-S", bad_ints[k], "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--perturb", "+5", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-o", "", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "--vtk=", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "+1.5e1", "i", NULL), 2); /* two inputs */
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-q", "+1.5e1", "i", NULL), -1);
    ck_assert(o.par.min_angle == 15);
}
END_TEST

START_TEST(test_usage_errors) {
    cli_opts o;
    char msg[512];
    ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, NULL), 2);
    ck_assert_str_eq(msg,
                     "mesh: missing input.poly; usage: ./mesh [options] input.poly (try --help)\n");
    ck_assert_int_eq(parse(&cli_meshcheck, &o, msg, sizeof msg, "in", NULL), 2);
    ck_assert_ptr_nonnull(strstr(msg, "missing PREFIX"));
    ck_assert_int_eq(parse(&cli_meshcheck, &o, msg, sizeof msg, "in", "out", "more", NULL), 2);
    ck_assert_ptr_nonnull(strstr(msg, "unexpected argument 'more'"));
    ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, "i", "-S", NULL), 2);
    ck_assert_str_eq(msg, "mesh: option -S needs a value (N) (try --help)\n");
    ck_assert_int_eq(parse(&cli_meshcheck, &o, msg, sizeof msg, "i", "o", "-q", NULL), 2);
    ck_assert_str_eq(msg, "meshcheck: option -q needs a value (DEG) (try --help)\n");
    ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, "--stats=yes", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, "--stat", "i", NULL), 2);
    ck_assert_str_eq(msg, "mesh: unknown option '--stat' (try --help)\n");
    ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, "-hq", "i", NULL), 0); /* Triangle's */
    ck_assert(!strncmp(msg, "usage: ", 7));
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--phases", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_pbw, &o, NULL, 0, "--phases", "i", NULL), -1);
    ck_assert_int_eq(o.par.phases, 1);
    ck_assert_int_eq(parse(&cli_meshcheck, &o, NULL, 0, "-S", "5", "i", "o", NULL), 2);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "--interfaces-delaunay", "i", NULL), 2);
    /* a warning is not an error */
    ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, "-q", "35", "i", NULL), -1);
    ck_assert_str_eq(msg, "mesh: warning: -q 35 above about 34 degrees may not be reachable "
                          "(refinement then stops with an error)\n");
    ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, "-Q", "-q", "35", "i", NULL), -1);
    ck_assert_str_eq(msg, ""); /* -Q: nothing but errors */
    ck_assert_int_eq(parse(&cli_meshcheck, &o, msg, sizeof msg, "-q", "35", "i", "o", NULL), -1);
    ck_assert_str_eq(msg, "");
}
END_TEST

START_TEST(test_help) {
    const cli_prog *progs[] = {&cli_mesh, &cli_meshcheck, &cli_pcdm, &cli_pbw};
    /* options that belong to one program only must appear in its --help alone */
    const char *only[] = {"--cdt-only", "--interfaces-delaunay", NULL, "--phases"};
    for (int k = 0; k < 4; k++) {
        cli_opts o;
        char msg[16384];
        ck_assert_int_eq(parse(progs[k], &o, msg, sizeof msg, "--help", NULL), 0);
        ck_assert_msg(!strncmp(msg, "usage: ", 7), "%s", msg);
        ck_assert_ptr_nonnull(strstr(msg, "Exit status: 0 success; 1 bad input"));
        ck_assert_ptr_nonnull(strstr(msg, "2 usage error"));
        ck_assert_ptr_nonnull(strstr(msg, "-h, --help"));
        for (int j = 0; j < 4; j++)
            if (only[j])
                ck_assert_msg(!strstr(msg, only[j]) == (j != k), "%s --help and %s", progs[k]->name,
                              only[j]);
        ck_assert_int_eq(parse(progs[k], &o, msg, sizeof msg, "-h", NULL), 0);
    }
    cli_opts o;
    char msg[16384];
    parse(&cli_pcdm, &o, msg, sizeof msg, "--help", NULL);
    ck_assert_ptr_nonnull(strstr(msg, "(default: 20.7)"));
    ck_assert_ptr_nonnull(strstr(msg, "--subdomains K"));
    ck_assert_ptr_nonnull(strstr(msg, "Every rank exits with the same status."));
}
END_TEST

/* Parses a NULL-terminated list given as an array (the switch-string tests build pairs). */
static int parse_v(const cli_prog *p, cli_opts *o, char *msg, size_t msglen, char **args) {
    char *argv[32];
    int argc = 0;
    argv[argc++] = (char *)p->name;
    while (*args)
        argv[argc++] = *args++;
    argv[argc] = NULL;
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    ck_assert_ptr_nonnull(f);
    int status = -7;
    int stop = cli_parse(p, argc, argv, f, f, o, &status);
    fclose(f);
    if (msg) snprintf(msg, msglen, "%s", buf ? buf : "");
    free(buf);
    return stop ? status : -1;
}

/* Whether two parses gave the same options: the strings equal, then every other byte. */
static void same_opts(const cli_opts *x, const cli_opts *y, const char *what) {
    cli_opts a, b;
    memcpy(&a, x, sizeof a);
    memcpy(&b, y, sizeof b);
    const char **sa[] = {&a.par.prog,       &a.par.input,  &a.par.out_prefix, &a.par.vtk,
                         &a.par.svg,        &a.par.cuts,   &a.par.write_cuts, &a.par.msh,
                         &a.par.size_field, &a.mesh_prefix};
    const char **sb[] = {&b.par.prog,       &b.par.input,  &b.par.out_prefix, &b.par.vtk,
                         &b.par.svg,        &b.par.cuts,   &b.par.write_cuts, &b.par.msh,
                         &b.par.size_field, &b.mesh_prefix};
    for (size_t k = 0; k < sizeof sa / sizeof *sa; k++) {
        ck_assert_msg(!*sa[k] == !*sb[k] && (!*sa[k] || !strcmp(*sa[k], *sb[k])),
                      "%s: string option %zu differs", what, k);
        *sa[k] = *sb[k] = NULL;
    }
    ck_assert_msg(!memcmp(&a, &b, sizeof a), "%s: options differ", what);
}

/* Each Triangle switch string parses to exactly what its spaced form does. */
START_TEST(test_switch_strings) {
    static char *pairs[][2][10] = {
        {{"-pq30a0.01Q", "in.poly"}, {"-p", "-q", "30", "-a", "0.01", "-Q", "in.poly"}},
        {{"-pq", "in.poly"}, {"-p", "-q", "20", "in.poly"}},
        {{"-q", "in.poly"}, {"-q", "20", "in.poly"}},
        {{"in.poly", "-q"}, {"-q", "20", "in.poly"}},
        {{"-q", "-V", "in.poly"}, {"-q", "20", "-V", "in.poly"}},
        {{"-pa", "in.poly"}, {"-p", "--region-areas", "in.poly"}},
        {{"-a", "in.poly"}, {"--region-areas", "in.poly"}},
        {{"-pq25.5a", "in.poly"}, {"-p", "-q", "25.5", "--region-areas", "in.poly"}},
        {{"-Aenr", "in.1"}, {"-A", "--edges", "-n", "--refine", "in.1"}},
        {{"-QVS100", "in.poly"}, {"--quiet", "--verbose", "-S", "100", "in.poly"}},
        {{"-pq30o2", "in.poly"}, {"-p", "-q", "30", "--order2", "in.poly"}},
        {{"-o2", "in.poly"}, {"--order2", "in.poly"}},
        {{"-NEP", "in.poly"}, {"--no-node", "--no-ele", "--no-poly", "in.poly"}},
        {{"-pq30.5a1e-3V", "in.poly"}, {"-p", "-q", "30.5", "-a", "0.001", "-V", "in.poly"}},
        {{"-q30e", "in.poly"}, {"-q", "30", "-e", "in.poly"}},
        {{"-oout", "in.poly"}, {"-o", "out", "in.poly"}},
        {{"-q.5a2", "in.poly"}, {"-q", "0.5", "-a", "2", "in.poly"}},
    };
    for (size_t k = 0; k < sizeof pairs / sizeof *pairs; k++) {
        cli_opts a, b;
        char msg[512], what[128];
        snprintf(what, sizeof what, "pair %zu (%s)", k, pairs[k][0][0]);
        ck_assert_msg(parse_v(&cli_mesh, &a, msg, sizeof msg, pairs[k][0]) == -1, "%s: %s", what,
                      msg);
        ck_assert_msg(parse_v(&cli_mesh, &b, msg, sizeof msg, pairs[k][1]) == -1, "%s: %s", what,
                      msg);
        same_opts(&a, &b, what);
        ck_assert_msg(parse_v(&cli_pbw, &a, NULL, 0, pairs[k][0]) == -1, "%s (pbw)", what);
        ck_assert_msg(parse_v(&cli_pbw, &b, NULL, 0, pairs[k][1]) == -1, "%s (pbw)", what);
        same_opts(&a, &b, what);
    }
    cli_opts o;
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-pq30a0.01QVAenNEPo2S7", "i", NULL), -1);
    ck_assert(o.par.min_angle == 30 && o.par.max_area == 0.01 && o.par.max_steiner == 7);
    ck_assert_int_eq(o.pslg + o.par.quiet + o.par.verbose + o.par.region_attr + o.par.edges +
                         o.par.neighbors + o.par.no_node + o.par.no_ele + o.par.no_poly +
                         o.par.order2,
                     10);
    ck_assert_int_eq(o.par.region_area + o.par.refine + o.par.convex_hull, 0);
    /* -c (Triangle's convex hull) inside a switch string, in every mesher and ./meshcheck */
    const cli_prog *progs[] = {&cli_mesh, &cli_pcdm, &cli_pbw};
    for (size_t k = 0; k < sizeof progs / sizeof *progs; k++) {
        ck_assert_int_eq(parse(progs[k], &o, NULL, 0, "-pcq30", "i", NULL), -1);
        ck_assert_msg(o.par.convex_hull == 1 && o.par.min_angle == 30 && o.pslg == 1, "%s",
                      progs[k]->name);
        ck_assert_int_eq(parse(progs[k], &o, NULL, 0, "--convex-hull", "i", NULL), -1);
        ck_assert_int_eq(o.par.convex_hull, 1);
    }
    ck_assert_int_eq(parse(&cli_meshcheck, &o, NULL, 0, "-cq30", "i", "p", NULL), -1);
    ck_assert(o.par.convex_hull == 1 && o.par.min_angle == 30);
}
END_TEST

START_TEST(test_switch_errors) {
    static const struct {
        const char *arg, *want;
    } bad[] = {
        {"-pqcD", "mesh: option -D in '-pqcD' is not supported (in Triangle: conforming "
                  "Delaunay) (try --help)\n"},
        {"-C", "mesh: option -C is not supported (in Triangle: consistency check; here: --check) "
               "(try --help)\n"},
        {"-pZ", "mesh: unknown option '-Z' in '-pZ' (try --help)\n"},
        {"-pS", "mesh: option -S needs a value (N) glued on, in '-pS' (try --help)\n"},
        {"-po", "mesh: option -o (PREFIX) must open its argument, as in -o PREFIX, not '-po' (try "
                "--help)\n"},
        {"-q30x", "mesh: unknown option '-x' in '-q30x' (try --help)\n"},
        {"-S1.5", "mesh: bad value '1.5': -S needs a non-negative integer (try --help)\n"},
        {"-q70", "mesh: bad value '70': -q needs a non-negative number below 60 (try --help)\n"},
        {"-pq-5", "mesh: bad value '-5': -q needs a non-negative number below 60 (try --help)\n"},
        {"-a1e400", "mesh: bad value '1e400': -a needs a non-negative number (try --help)\n"},
        {"-S0x10", "mesh: bad value '0x10': -S needs a non-negative integer (try --help)\n"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        cli_opts o;
        char msg[512];
        ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, bad[k].arg, "x", NULL), 2);
        ck_assert_str_eq(msg, bad[k].want);
    }
    /* a lone -q or -a takes the next argument when it looks like a number: read strictly */
    cli_opts o;
    char msg[512];
    ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, "-q", "30x", "i", NULL), 2);
    ck_assert_ptr_nonnull(strstr(msg, "bad value '30x': -q"));
    ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, "-a", "-inf", "i", NULL), 2);
    ck_assert_ptr_nonnull(strstr(msg, "bad value '-inf': -a"));
    /* ./meshcheck's -q is a bound to verify: no bare meaning, no Triangle defaults */
    ck_assert_int_eq(parse(&cli_meshcheck, &o, msg, sizeof msg, "-q", "i", "o", NULL), 2);
    ck_assert_int_eq(parse(&cli_meshcheck, &o, NULL, 0, "-q30a2", "i", "o", NULL), -1);
    ck_assert(o.par.min_angle == 30 && o.par.max_area == 2);
}
END_TEST

START_TEST(test_version) {
    const cli_prog *progs[] = {&cli_mesh, &cli_meshcheck, &cli_pcdm, &cli_pbw};
    for (int k = 0; k < 4; k++) {
        cli_opts o;
        char msg[256], want[128];
        ck_assert_int_eq(parse(progs[k], &o, msg, sizeof msg, "--version", NULL), 0);
        snprintf(want, sizeof want, "%s (pcdm) %s\n", progs[k]->name, pcdm_version());
        ck_assert_str_eq(msg, want);
    }
}
END_TEST

START_TEST(test_output_names) {
    static const struct {
        const char *in;
        int refine;
        const char *want;
    } cases[] = {{"dir/lake.poly", 0, "dir/lake.1"}, {"lake", 0, "lake.1"},
                 {"lake.node", 0, "lake.1"},         {"x.1.poly", 0, "x.1.1"},
                 {"a.b/c.ele", 0, "a.b/c.1"},        {"lake.1", 1, "lake.2"},
                 {"d/lake.1.node", 1, "d/lake.2"},   {"lake.9.ele", 1, "lake.10"},
                 {"lake.poly", 1, "lake.1"},         {"v2", 1, "v2.1"},
                 {"lake.1.area", 1, "lake.2"}};
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        char buf[64];
        ck_assert_int_eq(cli_output_name(cases[k].in, cases[k].refine, buf, sizeof buf), 0);
        ck_assert_str_eq(buf, cases[k].want);
    }
    char small[8];
    ck_assert_int_eq(cli_output_name("abcdef.poly", 0, small, sizeof small), -1);
    /* the meshers default to it; -o wins; ./meshcheck writes nothing */
    cli_opts o;
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "d/in.poly", NULL), -1);
    ck_assert_str_eq(o.par.out_prefix, "d/in.1");
    ck_assert_ptr_eq(o.par.out_prefix, o.par.out_name);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-r", "d/in.3", NULL), -1);
    ck_assert_str_eq(o.par.out_prefix, "d/in.4");
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-o", "p", "d/in.poly", NULL), -1);
    ck_assert_str_eq(o.par.out_prefix, "p");
    ck_assert_int_eq(parse(&cli_meshcheck, &o, NULL, 0, "in.poly", "m", NULL), -1);
    ck_assert_ptr_null(o.par.out_prefix);
    /* the parallel front end copies the options out: the prefix must follow the copy */
    char *argv[] = {"pcdm", "-q", "d/in.poly", NULL};
    par_opts po;
    int status;
    ck_assert_int_eq(cli_par_parse(3, argv, 1, &cli_pcdm, &po, &status), 0);
    ck_assert_ptr_eq(po.out_prefix, po.out_name);
    ck_assert_str_eq(po.out_prefix, "d/in.1");
    ck_assert(po.min_angle == 20);
    char name[PAR_NAME_MAX + 8];
    memset(name, 'x', sizeof name - 1);
    name[sizeof name - 1] = 0;
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, name, NULL), 2);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-o", "p", name, NULL), -1);
}
END_TEST

int main(void) {
    return ck_run(ck_suite("cli", 0,
                           CK_TESTS(test_defaults, test_spellings, test_number_edges, test_strict,
                                    test_usage_errors, test_choices, test_help, test_switch_strings,
                                    test_switch_errors, test_version, test_output_names)));
}
